#include "core/node_order.hpp"

#include <algorithm>
#include <cstdint>
#include <numeric>
#include <stdexcept>

namespace harness {

const char* node_order_name(NodeOrder o) {  // (world.hpp)
  switch (o) {
    case NodeOrder::scene: return "scene";
    case NodeOrder::morton: return "morton";
    case NodeOrder::rcm: return "rcm";
  }
  return "scene";
}

bool parse_node_order(const std::string& name, NodeOrder& out) {
  for (NodeOrder o : {NodeOrder::scene, NodeOrder::morton, NodeOrder::rcm})
    if (name == node_order_name(o)) {
      out = o;
      return true;
    }
  return false;
}

namespace {

// The 21 low bits of v spread to every third bit.
std::uint64_t spread3(std::uint64_t v) {
  v &= 0x1fffff;
  v = (v | v << 32) & 0x1f00000000ffffULL;
  v = (v | v << 16) & 0x1f0000ff0000ffULL;
  v = (v | v << 8) & 0x100f00f00f00f00fULL;
  v = (v | v << 4) & 0x10c30c30c30c30c3ULL;
  v = (v | v << 2) & 0x1249249249249249ULL;
  return v;
}

// The model's nodes in Morton order of their positions over the body's box.
void morton_order(const ShapeModel& m, int* out) {
  const int n = static_cast<int>(m.nodes.size());
  if (n == 0) return;
  Vec3 a = m.nodes[0], b = m.nodes[0];
  for (int i = 0; i < n; ++i) a = a.cwiseMin(m.nodes[i]), b = b.cwiseMax(m.nodes[i]);
  const double extent = std::max((b - a).maxCoeff(), 1e-300);
  const double scale = static_cast<double>((1 << 21) - 1) / extent;  // one scale: cubes stay cubes
  std::vector<std::pair<std::uint64_t, int>> key(static_cast<std::size_t>(n));
  for (int i = 0; i < n; ++i) {
    std::uint64_t code = 0;
    for (int c = 0; c < 3; ++c) {
      const double q = std::clamp((m.nodes[i][c] - a[c]) * scale, 0.0, static_cast<double>((1 << 21) - 1));
      code |= spread3(static_cast<std::uint64_t>(q)) << c;
    }
    key[static_cast<std::size_t>(i)] = {code, i};
  }
  std::sort(key.begin(), key.end());
  for (std::size_t k = 0; k < key.size(); ++k) out[k] = key[k].second;
}

// The n nodes of the adjacency (CSR: start, adj) in reverse Cuthill-McKee order: each connected
// part breadth-first from a peripheral node (the George-Liu search: the last node reached from
// the part's lowest-degree node, repeated while the depth grows), neighbours taken by increasing
// degree, then the whole order reversed.
void rcm_order(const std::vector<int>& start, const std::vector<int>& adj, int n, int* out) {
  if (n <= 0) return;
  auto degree = [&](int i) { return start[i + 1] - start[i]; };
  std::vector<int> level(static_cast<std::size_t>(n), -1);
  std::vector<int> order;
  order.reserve(static_cast<std::size_t>(n));
  std::vector<int> queue, nb;
  // Breadth-first from s over the unplaced nodes; returns the depth, fills queue with the visit order.
  std::vector<int> mark(static_cast<std::size_t>(n), -1);
  int stamp = 0;
  auto bfs = [&](int s) {
    ++stamp;
    queue.assign(1, s);
    mark[s] = stamp;
    level[s] = 0;
    int depth = 0;
    for (std::size_t q = 0; q < queue.size(); ++q) {
      const int u = queue[q];
      nb.clear();
      for (int k = start[u]; k < start[u + 1]; ++k) {
        const int v = adj[k];
        if (mark[v] == stamp || level[v] == -2) continue;  // -2: placed in an earlier part
        mark[v] = stamp;
        nb.push_back(v);
      }
      std::sort(nb.begin(), nb.end(), [&](int p, int r) { return degree(p) != degree(r) ? degree(p) < degree(r) : p < r; });
      for (int v : nb) {
        level[v] = level[u] + 1;
        depth = std::max(depth, level[v]);
        queue.push_back(v);
      }
    }
    return depth;
  };
  for (int seed = 0; seed < n; ++seed) {
    if (level[seed] == -2) continue;
    // The part's lowest-degree node (lowest index among equals), found by one search from the seed.
    bfs(seed);
    int s = seed;
    for (int u : queue)
      if (degree(u) < degree(s) || (degree(u) == degree(s) && u < s)) s = u;
    int depth = bfs(s);
    for (int iter = 0; iter < 8; ++iter) {  // George-Liu: move to the farthest level while it deepens
      int t = queue.back();
      for (int u : queue)
        if (level[u] == depth && (degree(u) < degree(t) || (degree(u) == degree(t) && u < t))) t = u;
      const int d = bfs(t);
      if (d <= depth) {
        bfs(s);
        break;
      }
      s = t, depth = d;
    }
    for (int u : queue) {
      level[u] = -2;
      order.push_back(u);
    }
  }
  std::reverse(order.begin(), order.end());
  std::copy(order.begin(), order.end(), out);
}

}  // namespace

std::vector<int> node_permutation(const ShapeModel& m, NodeOrder order) {
  const int n = static_cast<int>(m.nodes.size());
  const int ns = std::clamp(m.n_surface, 0, n);
  std::vector<int> perm(static_cast<std::size_t>(n));
  std::iota(perm.begin(), perm.end(), 0);
  if (order == NodeOrder::scene) return perm;
  // One order over the whole body, then split stably: the surface's nodes first, the interior's
  // after, each in that order. Both sweep the body alike, so that a spring between the two joins
  // nodes at about the same point of their sweeps (ordered apart, the two lists would run through
  // the body on different paths, and such springs would reach across it).
  std::vector<int> all(static_cast<std::size_t>(n));
  if (order == NodeOrder::morton) {
    morton_order(m, all.data());
  } else {
    std::vector<int> start(static_cast<std::size_t>(n) + 1, 0), adj;
    for (const Edge& e : m.springs)
      if (e[0] != e[1]) ++start[e[0] + 1], ++start[e[1] + 1];
    for (int i = 0; i < n; ++i) start[i + 1] += start[i];
    adj.assign(static_cast<std::size_t>(start[n]), 0);
    std::vector<int> fill(start.begin(), start.end() - 1);
    for (const Edge& e : m.springs)
      if (e[0] != e[1]) adj[fill[e[0]]++] = e[1], adj[fill[e[1]]++] = e[0];
    for (int i = 0; i < n; ++i) std::sort(adj.begin() + start[i], adj.begin() + start[i + 1]);
    rcm_order(start, adj, n, all.data());
  }
  std::stable_partition(all.begin(), all.end(), [&](int i) { return i < ns; });
  return all;
}

void apply_node_permutation(ShapeModel& m, const std::vector<int>& perm) {
  const std::size_t n = m.nodes.size();
  if (perm.size() != n) throw std::invalid_argument("node permutation: wrong size");
  std::vector<int> inv(n, -1);
  for (std::size_t k = 0; k < n; ++k) {
    const int p = perm[k];
    if (p < 0 || static_cast<std::size_t>(p) >= n || inv[static_cast<std::size_t>(p)] >= 0)
      throw std::invalid_argument("node permutation: not a permutation of the nodes");
    inv[static_cast<std::size_t>(p)] = static_cast<int>(k);
  }
  if (!m.node_volume.empty() && m.node_volume.size() != n) throw std::invalid_argument("node permutation: node volumes");
  Points nodes(n);
  std::vector<double> vol(m.node_volume.size());
  for (std::size_t k = 0; k < n; ++k) {
    nodes[k] = m.nodes[static_cast<std::size_t>(perm[k])];
    if (!vol.empty()) vol[k] = m.node_volume[static_cast<std::size_t>(perm[k])];
  }
  m.nodes = std::move(nodes);
  m.node_volume = std::move(vol);
  for (Tri& t : m.faces)
    for (int& v : t) v = inv[static_cast<std::size_t>(v)];
  for (Cell& cell : m.cells)
    for (int& v : cell) v = inv[static_cast<std::size_t>(v)];
  for (Edge& e : m.springs)
    for (int& v : e) v = inv[static_cast<std::size_t>(v)];
  std::vector<std::size_t> idx(m.springs.size());
  std::iota(idx.begin(), idx.end(), std::size_t{0});
  auto key = [&](std::size_t s) {
    const Edge& e = m.springs[s];
    return std::pair<int, int>{std::min(e[0], e[1]), std::max(e[0], e[1])};
  };
  std::stable_sort(idx.begin(), idx.end(), [&](std::size_t a, std::size_t b) { return key(a) < key(b); });
  std::vector<Edge> springs(idx.size());
  std::vector<double> kappa(m.spring_kappa.empty() ? 0 : idx.size());
  std::vector<SpringRole> role(m.spring_role.empty() ? 0 : idx.size());
  for (std::size_t k = 0; k < idx.size(); ++k) {
    springs[k] = m.springs[idx[k]];
    if (!kappa.empty()) kappa[k] = m.spring_kappa[idx[k]];
    if (!role.empty()) role[k] = m.spring_role[idx[k]];
  }
  m.springs = std::move(springs);
  m.spring_kappa = std::move(kappa);
  m.spring_role = std::move(role);
}

}  // namespace harness
