// Model assembly (finish_model): a checked closed surface becomes a mass-spring model: the
// shell's edge and bending springs, the volume fill's interior (volume_fill.cpp), lumped volumes,
// and each spring's calibration (calibration.cpp).
#include "core/edge_key.hpp"
#include "core/mesh.hpp"
#include "core/shapes/internal.hpp"

#include <algorithm>
#include <cstdint>
#include <utility>

namespace harness {

using namespace shapes;

ShapeModel finish_model(Points surface_nodes, std::vector<Tri> faces, Fill fill) {
  for (const Vec3& v : surface_nodes) require_finite(v, "surface vertex");
  {
    SurfaceMesh m{std::move(surface_nodes), std::move(faces)};
    const SurfaceReport rep = check_surface(m);
    require(rep.ok(), "surface is not a closed, outward-oriented 2-manifold: " + rep.problem);
    surface_nodes = std::move(m.V);
    faces = std::move(m.F);
  }
  ShapeModel out;
  out.n_surface = isize(surface_nodes);
  out.nodes = std::move(surface_nodes);
  out.faces = std::move(faces);
  out.volume = signed_volume(out.nodes, out.faces);
  const Points& V = out.nodes;
  const int ns = out.n_surface;

  // Shell: the edges, then one bending spring per edge between the two opposite vertices.
  std::vector<std::uint64_t> edges;
  std::vector<std::pair<std::uint64_t, int>> opposite;  // (edge, vertex opposite it)
  edges.reserve(3 * out.faces.size());
  opposite.reserve(3 * out.faces.size());
  for (const Tri& t : out.faces)
    for (int k = 0; k < 3; ++k) {
      edges.push_back(edge_key(t[k], t[(k + 1) % 3]));
      opposite.emplace_back(edges.back(), t[(k + 2) % 3]);
    }
  sort_unique(edges);
  std::sort(opposite.begin(), opposite.end());
  std::vector<std::uint64_t> keys = edges;
  for (std::size_t i = 0; i + 1 < opposite.size(); i += 2) {
    // Closed and manifold: the half-edges come in pairs of the same edge.
    const int c = opposite[i].second, d = opposite[i + 1].second;
    if (c == d || (V[c] - V[d]).squaredNorm() == 0.0) continue;
    const std::uint64_t k = edge_key(c, d);
    if (!std::binary_search(edges.begin(), edges.end(), k)) keys.push_back(k);
  }
  opposite.clear();
  opposite.shrink_to_fit();
  double mean_edge = 0.0;
  for (std::uint64_t k : edges) {
    const Edge e = key_edge(k);
    mean_edge += (V[e[0]] - V[e[1]]).norm();
  }
  mean_edge /= static_cast<double>(edges.size());
  edges.clear();
  edges.shrink_to_fit();

  // A third of each triangle's area to each of its vertices.
  std::vector<double> area(static_cast<std::size_t>(ns), 0.0);
  double total_area = 0.0;
  for (const Tri& t : out.faces) {
    const double a = 0.5 * (V[t[1]] - V[t[0]]).cross(V[t[2]] - V[t[0]]).norm();
    total_area += a;
    for (int v : t) area[v] += a / 3.0;
  }

  double surface_share = out.volume;
  LatticeShares shares;
  if (fill == Fill::volume) {
    int n_interior = 0;
    double h = mean_edge;
    fill_volume(out, mean_edge, keys, n_interior, h, shares);
    anchor_interior(out, keys);
    const double v_in = std::min(h * h * h, 0.8 * out.volume / n_interior);
    out.node_volume.assign(out.nodes.size(), v_in);
    surface_share = out.volume - v_in * n_interior;
  } else {
    out.node_volume.assign(out.nodes.size(), 0.0);
  }
  for (int s = 0; s < ns; ++s) out.node_volume[s] = surface_share * area[s] / total_area;

  sort_unique(keys);
  out.springs.reserve(keys.size());
  for (std::uint64_t k : keys) out.springs.push_back(key_edge(k));
  if (fill == Fill::volume) volume_kappa(out, shares);
  else shell_kappa(out);
  return out;
}

}  // namespace harness
