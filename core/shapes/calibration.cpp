// Elastic calibration of a generated model: each spring's stiffness per unit Young's modulus
// and its role (elastic_map.hpp maps them to N/m): the lattice's shares of a volume fill plus an
// isotropic surface layer, or a shell's membrane and bending springs.
#include "core/edge_key.hpp"
#include "core/shapes/internal.hpp"

#include <algorithm>
#include <cstdint>
#include <unordered_map>

namespace harness::shapes {

// Volume fill: lattice springs their shares, every other spring the surface layer's kappa.
void volume_kappa(ShapeModel& out, const LatticeShares& shares) {
  const std::size_t n = out.springs.size();
  out.spring_kappa.assign(n, 0.0);
  out.spring_role.assign(n, SpringRole::volume);
  double layer_l2 = 0.0;
  for (std::size_t s = 0; s < n; ++s) {
    const Edge e = out.springs[s];
    out.spring_kappa[s] = shares.kappa(e[0], e[1]);
    if (out.spring_kappa[s] == 0.0) layer_l2 += (out.nodes[e[0]] - out.nodes[e[1]]).squaredNorm();
  }
  const double h3 = shares.L.h * shares.L.h * shares.L.h;
  const double layer_volume = std::max(0.0, out.volume - static_cast<double>(shares.complete_cells) * h3);
  const double layer = layer_l2 > 0.0 ? 6.0 * layer_volume / layer_l2 : 0.0;
  for (std::size_t s = 0; s < n; ++s)
    if (out.spring_kappa[s] == 0.0) out.spring_kappa[s] = layer;
}

// Shell: edge springs E t sum A_T / |e|^2 (van Gelder 1998), bending springs E t^3 / (4 l^2).
void shell_kappa(ShapeModel& out) {
  std::unordered_map<std::uint64_t, double> area;  // edge -> area of its triangles
  for (const Tri& t : out.faces) {
    const Points& V = out.nodes;
    const double a = 0.5 * (V[t[1]] - V[t[0]]).cross(V[t[2]] - V[t[0]]).norm();
    for (int k = 0; k < 3; ++k) area[edge_key(t[k], t[(k + 1) % 3])] += a;
  }
  out.spring_kappa.resize(out.springs.size());
  out.spring_role.resize(out.springs.size());
  for (std::size_t s = 0; s < out.springs.size(); ++s) {
    const Edge e = out.springs[s];
    const double l2 = (out.nodes[e[0]] - out.nodes[e[1]]).squaredNorm();
    const auto it = area.find(edge_key(e[0], e[1]));
    if (it != area.end()) {
      out.spring_role[s] = SpringRole::membrane;
      out.spring_kappa[s] = it->second / l2;
    } else {
      out.spring_role[s] = SpringRole::bending;
      out.spring_kappa[s] = 1.0 / (4.0 * l2);
    }
  }
}

}  // namespace harness::shapes
