// Limits of the shape generators that the scene format checks too: icosphere subdivisions
// (163842 surface vertices), box nodes (nx+1)(ny+1)(nz+1), cylinder nodes. A leaf header, so that
// the scene layer (core/scene/keys.cpp, readers.cpp) and the shapes layer (core/shapes/) read the
// same numbers without the scene including the shapes.
#pragma once

namespace harness {

constexpr int kMaxSubdivisions = 7;
constexpr long long kMaxBoxNodes = 20'000'000;
constexpr long long kMaxCylinderNodes = 20'000'000;

}  // namespace harness
