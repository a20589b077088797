// Volume fill: the interior lattice of a closed surface (which lattice points are inside, which
// are too near the surface), its springs and the surface's ties to it.
#include "core/geometry.hpp"
#include "core/edge_key.hpp"
#include "core/shapes/internal.hpp"
#include "core/shapes/kd_tree.hpp"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <numeric>
#include <utility>

namespace harness::shapes {

namespace {

// The interior lattice spans the bounding box with at most this many points; a finer lattice
// (mean edge length on a very fine surface) is coarsened to fit.
constexpr long long kMaxLattice = 2'000'000;
// Triangle-to-cell insertions allowed for the surface distance test before falling back to
// the distance to surface vertices (only reached by surfaces with huge slivers).
constexpr long long kMaxInsertions = 64'000'000;

Lattice make_lattice(const Vec3& lo, const Vec3& hi, double h) {
  Lattice L;
  const Vec3 ext = hi - lo;
  for (int pass = 0; pass < 64; ++pass) {
    for (int a = 0; a < 3; ++a)
      L.m[a] = std::max(1, static_cast<int>(std::min(std::ceil(ext[a] / h), 1e6)));
    if (L.size() <= kMaxLattice) break;
    h *= std::cbrt(static_cast<double>(L.size()) / static_cast<double>(kMaxLattice)) * 1.01;
  }
  L.h = h;
  // Centred in the box with m-1 < extent/h, so no point lies on the box; the tiny irrational
  // shift keeps lattice lines off the vertices and edges of meshes with round coordinates.
  const Vec3 shift(0.61803398875e-7, 0.41421356237e-7, 0.73205080757e-7);
  for (int a = 0; a < 3; ++a) L.o[a] = lo[a] + 0.5 * (ext[a] - (L.m[a] - 1) * h) + shift[a] * h;
  return L;
}

// Winding number of the lattice points, by counting signed crossings of the surface along
// each lattice line parallel to x (a ray towards +x from a point inside crosses one more
// outward face than inward ones). Ties (a line through an edge or vertex of the projection)
// are broken by simulating an infinitesimal shift of the line by (eps, eps^2) in (y, z), with
// each edge evaluated in one canonical direction so its two faces agree. A line whose signed
// crossings do not sum to zero is inconsistent (numerical trouble) and keeps no points.
std::vector<std::uint8_t> inside_points(const Points& V, const std::vector<Tri>& F,
                                        const Lattice& L) {
  struct Crossing {
    long long line;
    double x;
    int sign;
  };
  std::vector<Crossing> cross;
  const double h = L.h;
  // Edge function of the directed edge p->q at (y, z), times the triangle's orientation sign.
  auto edge_side = [&](int ip, int iq, double y, double z) {
    const bool canon = ip < iq;
    const Vec3& P = V[canon ? ip : iq];
    const Vec3& Q = V[canon ? iq : ip];
    const double dy = Q.y() - P.y(), dz = Q.z() - P.z();
    double e = dy * (z - P.z()) - dz * (y - P.y());
    if (e == 0.0) e = dz != 0.0 ? -dz : dy;  // the shifted line decides
    return canon ? e : -e;
  };
  for (const Tri& t : F) {
    const Vec3 &a = V[t[0]], &b = V[t[1]], &c = V[t[2]];
    const double area2 = (b.y() - a.y()) * (c.z() - a.z()) - (b.z() - a.z()) * (c.y() - a.y());
    if (area2 == 0.0) continue;  // parallel to x: its neighbours carry the crossing
    const int s = area2 > 0.0 ? 1 : -1;
    const double ylo = std::min({a.y(), b.y(), c.y()}), yhi = std::max({a.y(), b.y(), c.y()});
    const double zlo = std::min({a.z(), b.z(), c.z()}), zhi = std::max({a.z(), b.z(), c.z()});
    const int j0 = std::max(0, static_cast<int>(std::floor((ylo - L.o.y()) / h)));
    const int j1 = std::min(L.m[1] - 1, static_cast<int>(std::ceil((yhi - L.o.y()) / h)));
    const int k0 = std::max(0, static_cast<int>(std::floor((zlo - L.o.z()) / h)));
    const int k1 = std::min(L.m[2] - 1, static_cast<int>(std::ceil((zhi - L.o.z()) / h)));
    for (int k = k0; k <= k1; ++k)
      for (int j = j0; j <= j1; ++j) {
        const double y = L.o.y() + j * h, z = L.o.z() + k * h;
        const double eab = s * edge_side(t[0], t[1], y, z);
        const double ebc = s * edge_side(t[1], t[2], y, z);
        const double eca = s * edge_side(t[2], t[0], y, z);
        if (!(eab > 0.0 && ebc > 0.0 && eca > 0.0)) continue;
        // Barycentric weights from the sub-areas (clamped: ties may carry a stand-in value).
        const double wa = std::fabs(ebc), wb = std::fabs(eca), wc = std::fabs(eab);
        const double sum = wa + wb + wc;
        const double x = sum > 0.0 ? (wa * a.x() + wb * b.x() + wc * c.x()) / sum
                                   : (a.x() + b.x() + c.x()) / 3.0;
        cross.push_back({static_cast<long long>(k) * L.m[1] + j, x, s});
      }
  }
  std::sort(cross.begin(), cross.end(), [](const Crossing& p, const Crossing& q) {
    return p.line != q.line ? p.line < q.line : p.x < q.x;
  });
  std::vector<std::uint8_t> inside(static_cast<std::size_t>(L.size()), 0);
  for (std::size_t i = 0; i < cross.size();) {
    std::size_t j = i;
    int total = 0;
    while (j < cross.size() && cross[j].line == cross[i].line) total += cross[j++].sign;
    if (total == 0) {
      const int yj = static_cast<int>(cross[i].line % L.m[1]);
      const int zk = static_cast<int>(cross[i].line / L.m[1]);
      std::size_t c = i;
      int before = 0;  // signed crossings at x <= the point: winding = -before
      for (int xi = 0; xi < L.m[0]; ++xi) {
        const double x = L.o.x() + xi * L.h;
        while (c < j && cross[c].x <= x) before += cross[c++].sign;
        if (-before >= 1) inside[L.index(xi, yj, zk)] = 1;
      }
    }
    i = j;
  }
  return inside;
}

// Drops the inside points closer than r to the surface. Triangles are binned into the cells
// around the lattice points (cell = points whose nearest lattice point it is), expanded by r.
void drop_near_surface(const Points& V, const std::vector<Tri>& F, const Lattice& L, double r,
                       std::vector<std::uint8_t>& inside) {
  auto cell_range = [&](double lo, double hi, int a, int& c0, int& c1) {
    c0 = std::max(0, static_cast<int>(std::floor((lo - L.o[a]) / L.h + 0.5)));
    c1 = std::min(L.m[a] - 1, static_cast<int>(std::floor((hi - L.o[a]) / L.h + 0.5)));
  };
  auto tri_cells = [&](const Tri& t, int c0[3], int c1[3]) {
    for (int a = 0; a < 3; ++a) {
      const double lo = std::min({V[t[0]][a], V[t[1]][a], V[t[2]][a]}) - r;
      const double hi = std::max({V[t[0]][a], V[t[1]][a], V[t[2]][a]}) + r;
      cell_range(lo, hi, a, c0[a], c1[a]);
    }
  };
  long long total = 0;
  for (const Tri& t : F) {
    int c0[3], c1[3];
    tri_cells(t, c0, c1);
    long long n = 1;
    for (int a = 0; a < 3; ++a) n *= std::max(0, c1[a] - c0[a] + 1);
    total += n;
    if (total > kMaxInsertions) break;
  }
  const double r2 = r * r;
  if (total > kMaxInsertions) {
    // Fallback for surfaces of huge slivers: distance to the surface vertices only.
    std::vector<int> ids(V.size());
    std::iota(ids.begin(), ids.end(), 0);
    const KdTree tree(V, std::move(ids));
    for (int k = 0; k < L.m[2]; ++k)
      for (int j = 0; j < L.m[1]; ++j)
        for (int i = 0; i < L.m[0]; ++i) {
          std::uint8_t& in = inside[L.index(i, j, k)];
          if (in && !tree.within(L.point(i, j, k), r).empty()) in = 0;
        }
    return;
  }
  // CSR bins (count, then fill), only for the cells of inside points.
  auto for_cells_of = [&](int f, auto&& fn) {
    int c0[3], c1[3];
    tri_cells(F[f], c0, c1);
    for (int k = c0[2]; k <= c1[2]; ++k)
      for (int j = c0[1]; j <= c1[1]; ++j)
        for (int i = c0[0]; i <= c1[0]; ++i) {
          const long long c = L.index(i, j, k);
          if (inside[c]) fn(c);
        }
  };
  std::vector<int> start(static_cast<std::size_t>(L.size()) + 1, 0);
  for (int f = 0; f < isize(F); ++f) for_cells_of(f, [&](long long c) { ++start[c + 1]; });
  for (std::size_t c = 1; c < start.size(); ++c) start[c] += start[c - 1];
  std::vector<int> items(static_cast<std::size_t>(start.back()));
  std::vector<int> fill(start.begin(), start.end() - 1);
  for (int f = 0; f < isize(F); ++f) for_cells_of(f, [&](long long c) { items[fill[c]++] = f; });

  for (int k = 0; k < L.m[2]; ++k)
    for (int j = 0; j < L.m[1]; ++j)
      for (int i = 0; i < L.m[0]; ++i) {
        const long long c = L.index(i, j, k);
        if (!inside[c]) continue;
        const Vec3 p = L.point(i, j, k);
        for (int q = start[c]; q < start[c + 1]; ++q) {
          const Tri& t = F[items[q]];
          if ((closest_on_triangle(p, V[t[0]], V[t[1]], V[t[2]]) - p).squaredNorm() <= r2) {
            inside[c] = 0;
            break;
          }
        }
      }
}

Vec3 volume_centroid(const Points& V, const std::vector<Tri>& F) {
  const Vec3 o = V[0];
  Vec3 sum = Vec3::Zero();
  double six_v = 0.0;
  for (const Tri& t : F) {
    const Vec3 a = V[t[0]] - o, b = V[t[1]] - o, c = V[t[2]] - o;
    const double w = a.dot(b.cross(c));
    six_v += w;
    sum += w * (a + b + c) / 4.0;
  }
  return o + sum / six_v;
}

}  // namespace

// Volume fill. Interior nodes are the points of a lattice of spacing h = mean surface edge
// length (coarsened to at most kMaxLattice points over the bounding box), kept when
//   - their winding number is >= 1 (exact crossing count, see inside_points), and
//   - they are farther than 0.4 h from the surface itself (point-triangle distance; the
//     distance to the vertices only, if binning the triangles would be absurdly large).
// Springs: lattice neighbours (axis, face and body diagonals), each surface node to its 4
// nearest interior nodes and to every interior node within 1.5 h. A surface too thin for
// any lattice point gets one node at its volume centroid, tied to every surface node.
// Appends the nodes, adds the spring keys, and returns the interior count and h used.
void fill_volume(ShapeModel& out, double mean_edge, std::vector<std::uint64_t>& keys,
                 int& n_interior, double& h_used, LatticeShares& shares) {
  const Points& V = out.nodes;  // surface only at this point
  const int ns = out.n_surface;
  Vec3 lo = V[0], hi = V[0];
  for (const Vec3& v : V) {
    lo = lo.cwiseMin(v);
    hi = hi.cwiseMax(v);
  }
  const Lattice L = make_lattice(lo, hi, mean_edge);
  const double h = L.h;
  h_used = h;
  std::vector<std::uint8_t> inside = inside_points(V, out.faces, L);
  drop_near_surface(V, out.faces, L, 0.4 * h, inside);

  std::vector<int> node_at(static_cast<std::size_t>(L.size()), -1);
  Points interior;
  for (int k = 0; k < L.m[2]; ++k)
    for (int j = 0; j < L.m[1]; ++j)
      for (int i = 0; i < L.m[0]; ++i)
        if (inside[L.index(i, j, k)]) {
          node_at[L.index(i, j, k)] = ns + isize(interior);
          shares.cell_of.push_back(L.index(i, j, k));
          interior.push_back(L.point(i, j, k));
        }
  inside.clear();
  inside.shrink_to_fit();

  auto add = [&](int a, int b) {
    if (a != b && (out.nodes[a] - out.nodes[b]).squaredNorm() > 0.0) keys.push_back(edge_key(a, b));
  };
  if (interior.empty()) {
    // Too thin for the lattice: one centre node tied to the whole surface.
    out.nodes.push_back(volume_centroid(out.nodes, out.faces));
    for (int s = 0; s < ns; ++s) add(s, ns);
    n_interior = 1;
    return;
  }
  n_interior = isize(interior);
  out.nodes.insert(out.nodes.end(), interior.begin(), interior.end());

  // Lattice neighbours: the 13 offsets of the forward half of the 26-neighbourhood.
  static const int off[13][3] = {{1, 0, 0},  {0, 1, 0},  {0, 0, 1},  {1, 1, 0},  {1, -1, 0},
                                 {1, 0, 1},  {1, 0, -1}, {0, 1, 1},  {0, 1, -1}, {1, 1, 1},
                                 {1, 1, -1}, {1, -1, 1}, {1, -1, -1}};
  for (int k = 0; k < L.m[2]; ++k)
    for (int j = 0; j < L.m[1]; ++j)
      for (int i = 0; i < L.m[0]; ++i) {
        const int a = node_at[L.index(i, j, k)];
        if (a < 0) continue;
        for (const auto& d : off) {
          const int ii = i + d[0], jj = j + d[1], kk = k + d[2];
          if (ii < 0 || jj < 0 || kk < 0 || ii >= L.m[0] || jj >= L.m[1] || kk >= L.m[2]) continue;
          const int b = node_at[L.index(ii, jj, kk)];
          if (b >= 0) add(a, b);
        }
      }
  shares.L = L;
  shares.n_surface = ns;
  shares.node_at = std::move(node_at);
  shares.count_cells();

  // Surface to interior: the 4 nearest interior nodes and every one within 1.5 h.
  std::vector<int> ids(interior.size());
  std::iota(ids.begin(), ids.end(), ns);
  const KdTree inner(out.nodes, std::move(ids));
  for (int s = 0; s < ns; ++s) {
    for (int b : inner.nearest(out.nodes[s], 4)) add(s, b);
    for (int b : inner.within(out.nodes[s], 1.5 * h)) add(s, b);
  }
}

// Every interior node gets at least 3 springs and every group of interior nodes a path to the
// surface, by tying the odd ones to their nearest surface nodes.
void anchor_interior(ShapeModel& out, std::vector<std::uint64_t>& keys) {
  const int ns = out.n_surface, n = isize(out.nodes);
  if (n == ns) return;
  std::vector<int> ids(static_cast<std::size_t>(ns));
  std::iota(ids.begin(), ids.end(), 0);
  const KdTree surf(out.nodes, std::move(ids));
  auto tie = [&](int a, int count) {
    for (int b : surf.nearest(out.nodes[a], count))
      if ((out.nodes[a] - out.nodes[b]).squaredNorm() > 0.0) keys.push_back(edge_key(a, b));
  };
  sort_unique(keys);
  std::vector<int> degree(static_cast<std::size_t>(n), 0);
  UnionFind uf(static_cast<std::size_t>(n));
  for (std::uint64_t k : keys) {
    const Edge e = key_edge(k);
    ++degree[e[0]];
    ++degree[e[1]];
    uf.unite(e[0], e[1]);
  }
  std::vector<std::uint8_t> grounded(static_cast<std::size_t>(n), 0);
  for (int s = 0; s < ns; ++s) grounded[uf.find(s)] = 1;
  // Per floating group, its node nearest to the surface.
  std::vector<std::pair<double, int>> best(static_cast<std::size_t>(n), {HUGE_VAL, -1});
  for (int a = ns; a < n; ++a) {
    if (degree[a] < 3) tie(a, 3);
    const int root = uf.find(a);
    if (grounded[root]) continue;
    const int nearest = surf.nearest(out.nodes[a], 1).front();
    const double d2 = (out.nodes[a] - out.nodes[nearest]).squaredNorm();
    if (d2 < best[root].first) best[root] = {d2, a};
  }
  for (const auto& b : best)
    if (b.second >= 0) tie(b.second, 3);
  sort_unique(keys);
}

}  // namespace harness::shapes
