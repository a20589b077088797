// What the model generators (shapes/*.cpp) share and nothing else uses: small helpers, the
// interior lattice of a volume fill and its stiffness shares, and the steps of a model's assembly
// each file provides (model.cpp calls them).
#pragma once

#include "core/elastic_map.hpp"
#include "core/shapes/shapes.hpp"

#include <algorithm>
#include <cstdint>
#include <stdexcept>
#include <string>
#include <vector>

namespace harness::shapes {

template <class C>
int isize(const C& c) {
  return static_cast<int>(c.size());
}

inline void require(bool ok, const std::string& msg) {
  if (!ok) throw std::invalid_argument(msg);
}

inline void require_finite(const Vec3& v, const char* what) {
  require(v.allFinite(), std::string(what) + " must be finite");
}

inline void sort_unique(std::vector<std::uint64_t>& v) {
  std::sort(v.begin(), v.end());
  v.erase(std::unique(v.begin(), v.end()), v.end());
}

// Interior lattice: o + (i, j, k) h for 0 <= i < m.
struct Lattice {
  Vec3 o = Vec3::Zero();
  double h = 0.0;
  int m[3] = {1, 1, 1};
  long long size() const { return static_cast<long long>(m[0]) * m[1] * m[2]; }
  long long index(int i, int j, int k) const {
    return (static_cast<long long>(k) * m[1] + j) * m[0] + i;
  }
  Vec3 point(int i, int j, int k) const { return o + h * Vec3(i, j, k); }
};

// The interior lattice of a volume fill, kept for the springs' stiffness shares (per unit E):
// a lattice spring takes its share from every complete cell (all eight corners are nodes) it
// borders, as in the box lattice (elastic_map.hpp).
struct LatticeShares {
  Lattice L;
  std::vector<int> node_at;           // lattice index -> node, -1 none
  std::vector<long long> cell_of;     // interior node (node - n_surface) -> lattice index
  int n_surface = 0;
  long long complete_cells = 0;
  CellSprings cell{};

  bool complete(int i, int j, int k) const {
    if (i < 0 || j < 0 || k < 0 || i + 1 >= L.m[0] || j + 1 >= L.m[1] || k + 1 >= L.m[2]) return false;
    for (int c = 0; c < 8; ++c)
      if (node_at[L.index(i + (c & 1), j + ((c >> 1) & 1), k + ((c >> 2) & 1))] < 0) return false;
    return true;
  }
  void count_cells() {
    cell = isotropic_cell(Vec3::Constant(L.h));
    for (int k = 0; k + 1 < L.m[2]; ++k)
      for (int j = 0; j + 1 < L.m[1]; ++j)
        for (int i = 0; i + 1 < L.m[0]; ++i) complete_cells += complete(i, j, k);
  }
  Vec3i ijk(int node) const {
    const long long c = cell_of[node - n_surface];
    const long long i = c % L.m[0], j = (c / L.m[0]) % L.m[1], k = c / (static_cast<long long>(L.m[0]) * L.m[1]);
    return Vec3i(static_cast<int>(i), static_cast<int>(j), static_cast<int>(k));
  }
  // kappa of the spring between nodes a and b from the complete cells it borders (0: none, or
  // not a lattice spring).
  double kappa(int a, int b) const {
    if (a < n_surface || b < n_surface || cell_of.empty()) return 0.0;
    const Vec3i p = ijk(a), q = ijk(b), d = q - p;
    if (d.cwiseAbs().maxCoeff() != 1) return 0.0;
    const int axes = static_cast<int>((d.array() != 0).count());
    // Cells holding both ends: fixed (the lower one) along the axes the spring spans, either
    // side along the others.
    double share = axes == 1 ? 0.25 * cell.edge[d[0] ? 0 : d[1] ? 1 : 2]
                   : axes == 2 ? 0.5 * cell.face[d[0] == 0 ? 0 : d[1] == 0 ? 1 : 2]
                               : cell.body;
    double sum = 0.0;
    for (int c = 0; c < 8; ++c) {
      int lo[3];
      bool valid = true;
      for (int ax = 0; ax < 3; ++ax) {
        const int bit = (c >> ax) & 1;
        if (d[ax] != 0) {
          if (bit) valid = false;  // one choice only along spanned axes
          lo[ax] = std::min(p[ax], q[ax]);
        } else {
          lo[ax] = p[ax] - 1 + bit;
        }
      }
      if (valid && complete(lo[0], lo[1], lo[2])) sum += share;
    }
    return sum;
  }
};

// volume_fill.cpp. Volume fill: appends the interior nodes, adds the spring keys, returns the
// interior count, the lattice spacing h used and the lattice's stiffness shares (below the
// definition). anchor_interior: ties loose interior nodes to the surface.
void fill_volume(ShapeModel& out, double mean_edge, std::vector<std::uint64_t>& keys, int& n_interior,
                 double& h_used, LatticeShares& shares);
void anchor_interior(ShapeModel& out, std::vector<std::uint64_t>& keys);

// calibration.cpp: every spring's stiffness per unit Young's modulus and its role
// (elastic_map.hpp), for a volume fill and for a shell.
void volume_kappa(ShapeModel& out, const LatticeShares& shares);
void shell_kappa(ShapeModel& out);

}  // namespace harness::shapes
