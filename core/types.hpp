// Basic types shared by the whole harness. SI units throughout (m, kg, s, N).
#pragma once

#include <Eigen/Core>
#include <Eigen/Geometry>  // cross products

#include <array>
#include <cstdint>
#include <stdexcept>
#include <string>
#include <vector>

namespace harness {

using Vec3 = Eigen::Vector3d;
using Vec3i = Eigen::Vector3i;
// Node positions / velocities / forces: one Vec3 per node, contiguous.
using Points = std::vector<Vec3>;
// Triangle as three node indices, counter-clockwise seen from outside (outward normal).
using Tri = std::array<int, 3>;
// Spring as the indices of its two end nodes.
using Edge = std::array<int, 2>;
// Hexahedral cell of a box lattice as its 8 corner nodes, corner c at lattice offset
// (c & 1, (c >> 1) & 1, (c >> 2) & 1) from the cell's lowest corner.
using Cell = std::array<int, 8>;

// Raised for bad input: `where` is "file: key.path" or "file:line:col"; the command line turns
// it into one line on stderr and exit status 2.
struct InputError : std::runtime_error {
  InputError(const std::string& where, const std::string& what)
      : std::runtime_error(where + ": " + what) {}
};

}  // namespace harness
