// Mass-spring models from shape descriptions. Everything here runs once at load time, so it is
// written for clarity and robustness, but stays O(n log n) so that fine surfaces (millions of
// vertices) remain buildable.
#include "core/shapes.hpp"

#include "core/edge_key.hpp"
#include "core/geometry.hpp"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>
#include <numeric>
#include <queue>
#include <unordered_map>
#include <utility>

namespace harness {
namespace {

constexpr long long kMaxBoxNodes = 20'000'000;
constexpr long long kMaxCylinderNodes = 20'000'000;
// Volume fill: the interior lattice spans the bounding box with at most this many points; a
// finer lattice (mean edge length on a very fine surface) is coarsened to fit.
constexpr long long kMaxLattice = 2'000'000;
// Triangle-to-cell insertions allowed for the surface distance test before falling back to
// the distance to surface vertices (only reached by surfaces with huge slivers).
constexpr long long kMaxInsertions = 64'000'000;

template <class C>
int isize(const C& c) {
  return static_cast<int>(c.size());
}

void require(bool ok, const std::string& msg) {
  if (!ok) throw std::invalid_argument(msg);
}

void sort_unique(std::vector<std::uint64_t>& v) {
  std::sort(v.begin(), v.end());
  v.erase(std::unique(v.begin(), v.end()), v.end());
}


// Static kd-tree over a subset of points (implicit layout: the median of each range is its
// node), for k-nearest and radius queries.
class KdTree {
 public:
  KdTree(const Points& pts, std::vector<int> ids) : pts_(pts), ids_(std::move(ids)) {
    axis_.assign(ids_.size(), 0);
    build(0, isize(ids_));
  }
  bool empty() const { return ids_.empty(); }
  // The k nearest points to q, nearest first.
  std::vector<int> nearest(const Vec3& q, int k) const {
    std::vector<std::pair<double, int>> best;  // sorted by distance, at most k
    knn(0, isize(ids_), q, k, best);
    std::vector<int> out;
    for (const auto& b : best) out.push_back(b.second);
    return out;
  }
  std::vector<int> within(const Vec3& q, double r) const {
    std::vector<int> out;
    radius(0, isize(ids_), q, r * r, out);
    return out;
  }

 private:
  void build(int lo, int hi) {
    if (hi - lo <= 1) return;
    Vec3 mn = pts_[ids_[lo]], mx = mn;
    for (int i = lo; i < hi; ++i) {
      mn = mn.cwiseMin(pts_[ids_[i]]);
      mx = mx.cwiseMax(pts_[ids_[i]]);
    }
    Eigen::Index ax = 0;
    (mx - mn).maxCoeff(&ax);
    const int axis = static_cast<int>(ax);
    const int mid = (lo + hi) / 2;
    std::nth_element(ids_.begin() + lo, ids_.begin() + mid, ids_.begin() + hi,
                     [&](int a, int b) { return pts_[a][axis] < pts_[b][axis]; });
    axis_[mid] = axis;
    build(lo, mid);
    build(mid + 1, hi);
  }
  void knn(int lo, int hi, const Vec3& q, int k, std::vector<std::pair<double, int>>& best) const {
    if (lo >= hi) return;
    const int mid = (lo + hi) / 2;
    const int id = ids_[mid];
    const double d2 = (pts_[id] - q).squaredNorm();
    if (isize(best) < k || d2 < best.back().first) {
      best.insert(std::upper_bound(best.begin(), best.end(), std::make_pair(d2, id)),
                  std::make_pair(d2, id));
      if (isize(best) > k) best.pop_back();
    }
    const double diff = q[axis_[mid]] - pts_[id][axis_[mid]];
    const bool left_first = diff < 0.0;
    knn(left_first ? lo : mid + 1, left_first ? mid : hi, q, k, best);
    if (isize(best) < k || diff * diff < best.back().first)
      knn(left_first ? mid + 1 : lo, left_first ? hi : mid, q, k, best);
  }
  void radius(int lo, int hi, const Vec3& q, double r2, std::vector<int>& out) const {
    if (lo >= hi) return;
    const int mid = (lo + hi) / 2;
    const int id = ids_[mid];
    if ((pts_[id] - q).squaredNorm() <= r2) out.push_back(id);
    const double diff = q[axis_[mid]] - pts_[id][axis_[mid]];
    if (diff <= 0.0 || diff * diff <= r2) radius(lo, mid, q, r2, out);
    if (diff >= 0.0 || diff * diff <= r2) radius(mid + 1, hi, q, r2, out);
  }

  const Points& pts_;
  std::vector<int> ids_;
  std::vector<int> axis_;
};

// ---- icosphere ---------------------------------------------------------------------------

void icosphere(int subdivisions, Points& V, std::vector<Tri>& F) {
  const double t = (1.0 + std::sqrt(5.0)) / 2.0;
  V = {Vec3(-1, t, 0), Vec3(1, t, 0), Vec3(-1, -t, 0), Vec3(1, -t, 0),
       Vec3(0, -1, t), Vec3(0, 1, t), Vec3(0, -1, -t), Vec3(0, 1, -t),
       Vec3(t, 0, -1), Vec3(t, 0, 1), Vec3(-t, 0, -1), Vec3(-t, 0, 1)};
  for (Vec3& v : V) v.normalize();
  F = {{0, 11, 5},  {0, 5, 1},  {0, 1, 7},  {0, 7, 10}, {0, 10, 11}, {1, 5, 9}, {5, 11, 4},
       {11, 10, 2}, {10, 7, 6}, {7, 1, 8},  {3, 9, 4},  {3, 4, 2},   {3, 2, 6}, {3, 6, 8},
       {3, 8, 9},   {4, 9, 5},  {2, 4, 11}, {6, 2, 10}, {8, 6, 7},   {9, 8, 1}};
  for (int s = 0; s < subdivisions; ++s) {
    // Shared midpoints found by sorting the half-edges by edge (no hash map of 30M entries).
    const std::size_t nf = F.size();
    std::vector<std::pair<std::uint64_t, std::uint32_t>> half(3 * nf);
    for (std::size_t f = 0; f < nf; ++f)
      for (int k = 0; k < 3; ++k)
        half[3 * f + k] = {edge_key(F[f][k], F[f][(k + 1) % 3]),
                           static_cast<std::uint32_t>(3 * f + k)};
    std::sort(half.begin(), half.end());
    std::vector<int> mid(3 * nf);
    for (std::size_t i = 0; i < half.size(); ++i) {
      if (i == 0 || half[i].first != half[i - 1].first) {
        const Edge e = key_edge(half[i].first);
        V.push_back((V[e[0]] + V[e[1]]).normalized());
      }
      mid[half[i].second] = isize(V) - 1;
    }
    std::vector<Tri> G(4 * nf);
    for (std::size_t f = 0; f < nf; ++f) {
      const int a = F[f][0], b = F[f][1], c = F[f][2];
      const int ab = mid[3 * f], bc = mid[3 * f + 1], ca = mid[3 * f + 2];
      G[4 * f] = {a, ab, ca};
      G[4 * f + 1] = {ab, b, bc};
      G[4 * f + 2] = {ca, bc, c};
      G[4 * f + 3] = {ab, bc, ca};
    }
    F.swap(G);
  }
}

// ---- volume fill -------------------------------------------------------------------------

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

Vec3 frame_normal(const Vec3& axis) {
  // Any unit vector perpendicular to axis: cross with the least aligned coordinate axis.
  Eigen::Index i = 0;
  axis.cwiseAbs().minCoeff(&i);
  return axis.cross(Vec3::Unit(i)).normalized();
}

void require_finite(const Vec3& v, const char* what) {
  require(v.allFinite(), std::string(what) + " must be finite");
}

ShapeModel icosahedral(const Vec3& center, const Vec3& radii, int subdivisions, Fill fill,
                       const char* who) {
  const std::string w(who);
  require_finite(center, (w + ": center").c_str());
  require(radii.allFinite() && (radii.array() > 0.0).all(), w + ": radius must be positive");
  require(subdivisions >= 0 && subdivisions <= kMaxSubdivisions,
          w + ": subdivisions must be in [0, " + std::to_string(kMaxSubdivisions) + "], got " +
              std::to_string(subdivisions));
  Points V;
  std::vector<Tri> F;
  icosphere(subdivisions, V, F);
  for (Vec3& v : V) v = center + radii.cwiseProduct(v);
  return finish_model(std::move(V), std::move(F), fill);
}

}  // namespace

namespace {

// The box lattice of make_box: nodes, springs, surface and lumped volumes, one step each.
struct BoxLattice {
  Vec3 min, max;
  int nx, ny, nz;
  int dims[3];
  std::vector<int> id;  // lattice index -> node index (boundary nodes first)
  ShapeModel out;

  CellSprings cell{};  // per unit E (elastic_map.hpp)

  BoxLattice(const Vec3& lo, const Vec3& hi, const Vec3i& cells)
      : min(lo), max(hi), nx(cells.x()), ny(cells.y()), nz(cells.z()), dims{nx, ny, nz} {
    cell = isotropic_cell((hi - lo).cwiseQuotient(cells.cast<double>()), &out.kappa_anisotropy);
  }
  // Cells of index c - 1 and c along an axis of n cells that exist (1 or 2).
  static int around(int c, int n) { return (c > 0 ? 1 : 0) + (c < n ? 1 : 0); }
  void spring(int a, int b, double kappa) {
    out.springs.push_back({a, b});
    out.spring_kappa.push_back(kappa);
    out.spring_role.push_back(SpringRole::volume);
  }
  int lid(int i, int j, int k) const { return (k * (ny + 1) + j) * (nx + 1) + i; }
  bool boundary(int i, int j, int k) const { return i == 0 || j == 0 || k == 0 || i == nx || j == ny || k == nz; }
  int at(int i, int j, int k) const { return id[lid(i, j, k)]; }
  int at(const int c[3]) const { return at(c[0], c[1], c[2]); }

  // Boundary nodes first, then interior, each in lattice order.
  void place_nodes() {
    const Vec3 step = (max - min).cwiseQuotient(Vec3(nx, ny, nz));
    const int n = (nx + 1) * (ny + 1) * (nz + 1);
    id.resize(static_cast<std::size_t>(n));
    out.nodes.resize(static_cast<std::size_t>(n));
    int next = 0;
    for (int pass = 0; pass < 2; ++pass)
      for (int k = 0; k <= nz; ++k)
        for (int j = 0; j <= ny; ++j)
          for (int i = 0; i <= nx; ++i) {
            if (boundary(i, j, k) != (pass == 0)) continue;
            id[lid(i, j, k)] = next;
            // The last layer is placed at max exactly, not min + n * step.
            out.nodes[next] = Vec3(i == nx ? max.x() : min.x() + i * step.x(), j == ny ? max.y() : min.y() + j * step.y(),
                                   k == nz ? max.z() : min.z() + k * step.z());
            if (pass == 0) ++out.n_surface;
            ++next;
          }
  }

  // Springs, each enumerated once: structural along +axis from every node, both diagonals of
  // every lattice face, the 4 diagonals of every cell.
  void add_springs() {
    for (int k = 0; k <= nz; ++k)
      for (int j = 0; j <= ny; ++j)
        for (int i = 0; i <= nx; ++i) {
          const int p[3] = {i, j, k};
          for (int a = 0; a < 3; ++a) {  // edge along a: a quarter from each cell around it
            int q[3] = {i, j, k};
            if (p[a] >= dims[a]) continue;
            ++q[a];
            const int u = (a + 1) % 3, w = (a + 2) % 3;
            spring(at(p), at(q), around(p[u], dims[u]) * around(p[w], dims[w]) * cell.edge[a] / 4.0);
          }
          for (int a = 0; a < 3; ++a) {  // face of the lattice spanned by axes u, w (normal a)
            const int u = (a + 1) % 3, w = (a + 2) % 3;
            if (p[u] >= dims[u] || p[w] >= dims[w]) continue;
            int c11[3] = {i, j, k}, c10[3] = {i, j, k}, c01[3] = {i, j, k};
            ++c11[u], ++c11[w], ++c10[u], ++c01[w];
            const double kappa = around(p[a], dims[a]) * cell.face[a] / 2.0;  // half from each cell
            spring(at(p), at(c11), kappa);
            spring(at(c10), at(c01), kappa);
          }
          if (i < nx && j < ny && k < nz) {
            spring(at(i, j, k), at(i + 1, j + 1, k + 1), cell.body);
            spring(at(i + 1, j, k), at(i, j + 1, k + 1), cell.body);
            spring(at(i, j + 1, k), at(i + 1, j, k + 1), cell.body);
            spring(at(i, j, k + 1), at(i + 1, j + 1, k), cell.body);
          }
        }
  }

  // Surface: both triangles of each boundary quad. On the face of normal +a (axes a, u, w
  // right-handed) the quad (p,q) -> (p+1,q) -> (p+1,q+1) -> (p,q+1) is counter-clockwise.
  void add_surface() {
    for (int a = 0; a < 3; ++a) {
      const int u = (a + 1) % 3, w = (a + 2) % 3;
      for (int side = 0; side < 2; ++side)
        for (int q = 0; q < dims[w]; ++q)
          for (int pp = 0; pp < dims[u]; ++pp) {
            auto node = [&](int du, int dw) {
              int c[3];
              c[a] = side == 0 ? 0 : dims[a];
              c[u] = pp + du;
              c[w] = q + dw;
              return at(c);
            };
            const int n00 = node(0, 0), n10 = node(1, 0), n11 = node(1, 1), n01 = node(0, 1);
            if (side == 1) {
              out.faces.push_back({n00, n10, n11});
              out.faces.push_back({n00, n11, n01});
            } else {
              out.faces.push_back({n00, n11, n10});
              out.faces.push_back({n00, n01, n11});
            }
          }
    }
  }

  // An eighth of every cell's volume to each of its corners.
  void add_volumes() {
    out.volume = (max - min).prod();
    out.node_volume.assign(out.nodes.size(), 0.0);
    const double eighth = out.volume / (static_cast<double>(nx) * ny * nz) / 8.0;
    for (int k = 0; k < nz; ++k)
      for (int j = 0; j < ny; ++j)
        for (int i = 0; i < nx; ++i)
          for (int c = 0; c < 8; ++c) out.node_volume[at(i + (c & 1), j + ((c >> 1) & 1), k + ((c >> 2) & 1))] += eighth;
  }
};

}  // namespace

ShapeModel make_box(const Vec3& min, const Vec3& max, const Vec3i& cells) {
  require_finite(min, "box: min");
  require_finite(max, "box: max");
  require((max - min).minCoeff() > 0.0, "box: max must exceed min along every axis");
  require(cells.minCoeff() >= 1, "box: cells must be >= 1 along every axis");
  require((static_cast<long long>(cells.x()) + 1) * (static_cast<long long>(cells.y()) + 1) *
                  (static_cast<long long>(cells.z()) + 1) <=
              kMaxBoxNodes,
          "box: too many nodes (limit " + std::to_string(kMaxBoxNodes) + ")");
  BoxLattice box(min, max, cells);
  box.place_nodes();
  box.add_springs();
  box.add_surface();
  box.add_volumes();
  return std::move(box.out);
}

ShapeModel make_sphere(const Vec3& center, double radius, int subdivisions, Fill fill) {
  return icosahedral(center, Vec3::Constant(radius), subdivisions, fill, "sphere");
}

ShapeModel make_ellipsoid(const Vec3& center, const Vec3& radii, int subdivisions, Fill fill) {
  return icosahedral(center, radii, subdivisions, fill, "ellipsoid");
}

ShapeModel make_cylinder(const Vec3& center, const Vec3& axis, double radius, double length,
                         int segments, int rings, Fill fill) {
  require_finite(center, "cylinder: center");
  require(axis.allFinite() && axis.norm() > 0.0, "cylinder: axis must be a non-zero vector");
  require(std::isfinite(radius) && radius > 0.0, "cylinder: radius must be positive");
  require(std::isfinite(length) && length > 0.0, "cylinder: length must be positive");
  require(segments >= 3, "cylinder: segments must be >= 3");
  require(rings >= 1, "cylinder: rings must be >= 1");
  require(static_cast<long long>(segments) * (static_cast<long long>(rings) + 1) + 2 <=
              kMaxCylinderNodes,
          "cylinder: too many nodes (limit " + std::to_string(kMaxCylinderNodes) + ")");
  // Right-handed frame (u, w, a): u x w = a, so increasing angle turns counter-clockwise
  // about the axis.
  const Vec3 a = axis.normalized();
  const Vec3 u = frame_normal(a);
  const Vec3 w = a.cross(u);
  const double pi = std::acos(-1.0);
  Points V;
  for (int r = 0; r <= rings; ++r) {
    const Vec3 c = center + a * (length * (static_cast<double>(r) / rings - 0.5));
    for (int s = 0; s < segments; ++s) {
      const double th = 2.0 * pi * s / segments;
      V.push_back(c + radius * (std::cos(th) * u + std::sin(th) * w));
    }
  }
  const int bottom = isize(V), top = bottom + 1;
  V.push_back(center - 0.5 * length * a);
  V.push_back(center + 0.5 * length * a);
  std::vector<Tri> F;
  auto ring = [&](int r, int s) { return r * segments + s % segments; };
  for (int r = 0; r < rings; ++r)
    for (int s = 0; s < segments; ++s) {
      // Tangent (A->B) x axial (B->C) points outward.
      const int A = ring(r, s), B = ring(r, s + 1), C = ring(r + 1, s + 1), D = ring(r + 1, s);
      F.push_back({A, B, C});
      F.push_back({A, C, D});
    }
  for (int s = 0; s < segments; ++s) {
    F.push_back({bottom, ring(0, s + 1), ring(0, s)});
    F.push_back({top, ring(rings, s), ring(rings, s + 1)});
  }
  return finish_model(std::move(V), std::move(F), fill);
}

ShapeModel make_from_surface(const SurfaceMesh& mesh, double scale, const Vec3& translate,
                             Fill fill) {
  require(std::isfinite(scale) && scale > 0.0, "mesh: scale must be positive");
  require_finite(translate, "mesh: translate");
  Points V = mesh.V;
  for (Vec3& v : V) v = v * scale + translate;
  return finish_model(std::move(V), mesh.F, fill);
}

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
