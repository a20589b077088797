#include "core/collision/detectors/hash.hpp"

#include "core/collision/detectors/triangles.hpp"
#include "core/geometry.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>

namespace harness {

namespace {

constexpr long long kP1 = 73856093, kP2 = 19349663, kP3 = 83492791;

bool is_prime(std::size_t n) {
  if (n < 2) return false;
  for (std::size_t d = 2; d * d <= n; ++d)
    if (n % d == 0) return false;
  return true;
}

std::size_t prime_at_least(std::size_t n) {
  while (!is_prime(n)) ++n;
  return n;
}

}  // namespace

void HashDetector::initialize(const World& w, const ContactSpec& spec) {
  guest_ = spec.guest;
  const Body& h = w.bodies[spec.host];
  if (h.faces.empty()) throw std::invalid_argument("hash detector: the host '" + h.name + "' has no surface");
  host_begin_ = h.begin;
  faces_ = h.faces;
  cell_ = spec.cell_size;
  if (!(cell_ > 0.0)) cell_ = current_surface_edge(w, spec.host);  // automatic
  if (!(cell_ > 0.0) || !std::isfinite(cell_)) throw std::invalid_argument("hash detector: no positive cell size");
  const std::size_t n = prime_at_least(std::max<std::size_t>(97, 4 * faces_.size()));
  head_.assign(n, -1);
  stamp_.assign(n, 0);
  seen_.assign(faces_.size(), 0);
  entry_tri_.reserve(8 * faces_.size());
  entry_next_.reserve(8 * faces_.size());
}

HashDetector::Cell HashDetector::cell_of(const Vec3& x) const {
  return {static_cast<long long>(std::floor(x.x() / cell_)), static_cast<long long>(std::floor(x.y() / cell_)),
          static_cast<long long>(std::floor(x.z() / cell_))};
}

std::size_t HashDetector::bucket(long long i, long long j, long long k) const {
  const long long h = (i * kP1) ^ (j * kP2) ^ (k * kP3);
  const long long n = static_cast<long long>(head_.size());
  return static_cast<std::size_t>(((h % n) + n) % n);
}

void HashDetector::hash_host(const World& w) {
  if (++now_ == 0) {  // the stamps wrapped: start afresh
    std::fill(stamp_.begin(), stamp_.end(), 0);
    now_ = 1;
  }
  entry_tri_.clear();
  entry_next_.clear();
  lo_ = Vec3::Constant(std::numeric_limits<double>::infinity());
  hi_ = -lo_;
  for (std::size_t f = 0; f < faces_.size(); ++f) {
    const Tri& t = faces_[f];
    Vec3 lo = w.x[host_begin_ + t[0]], hi = lo;
    for (int k = 1; k < 3; ++k) {
      lo = lo.cwiseMin(w.x[host_begin_ + t[k]]);
      hi = hi.cwiseMax(w.x[host_begin_ + t[k]]);
    }
    lo_ = lo_.cwiseMin(lo);
    hi_ = hi_.cwiseMax(hi);
    const Cell a = cell_of(lo), b = cell_of(hi);
    for (long long i = a.i; i <= b.i; ++i)
      for (long long j = a.j; j <= b.j; ++j)
        for (long long k = a.k; k <= b.k; ++k) {
          const std::size_t q = bucket(i, j, k);
          if (stamp_[q] != now_) stamp_[q] = now_, head_[q] = -1;
          entry_tri_.push_back(static_cast<int>(f));
          entry_next_.push_back(head_[q]);
          head_[q] = static_cast<int>(entry_tri_.size()) - 1;
        }
  }
}

// The signed crossing of the ray from p along axis a (towards +a when up, -a otherwise) with
// triangle t: its orientation sign in the projection onto the other two axes (b, c) = (a+1, a+2)
// mod 3, cyclic so that the sign is that of the normal's a component, when the ray passes through
// it beyond p (negated for a ray towards -a: leaving through a face whose normal points -a), 0
// when it misses; 2 when p lies on the triangle (the boundary: outside). Edges are evaluated in one
// canonical direction, so the two triangles of an edge agree on which side a tie goes (an
// infinitesimal shift of the ray). Axis 0, up: the ray towards +x in the (y, z) projection.
int HashDetector::crossings(const World& w, const Vec3& p, const Tri& t, int ax, bool up) const {
  const int by = (ax + 1) % 3, bz = (ax + 2) % 3;
  const Vec3 &a = w.x[host_begin_ + t[0]], &b = w.x[host_begin_ + t[1]], &c = w.x[host_begin_ + t[2]];
  const double area2 = (b[by] - a[by]) * (c[bz] - a[bz]) - (b[bz] - a[bz]) * (c[by] - a[by]);
  if (area2 == 0.0) return 0;  // parallel to the ray: its neighbours carry the crossing
  const int s = area2 > 0.0 ? 1 : -1;
  auto edge_side = [&](int ip, int iq) {
    const bool canon = ip < iq;
    const Vec3& P = w.x[host_begin_ + (canon ? ip : iq)];
    const Vec3& Q = w.x[host_begin_ + (canon ? iq : ip)];
    const double dy = Q[by] - P[by], dz = Q[bz] - P[bz];
    double e = dy * (p[bz] - P[bz]) - dz * (p[by] - P[by]);
    if (e == 0.0) e = dz != 0.0 ? -dz : dy;
    return canon ? e : -e;
  };
  const double eab = s * edge_side(t[0], t[1]), ebc = s * edge_side(t[1], t[2]), eca = s * edge_side(t[2], t[0]);
  if (!(eab > 0.0 && ebc > 0.0 && eca > 0.0)) return 0;
  const double wa = std::fabs(ebc), wb = std::fabs(eca), wc = std::fabs(eab), sum = wa + wb + wc;
  const double x = sum > 0.0 ? (wa * a[ax] + wb * b[ax] + wc * c[ax]) / sum : (a[ax] + b[ax] + c[ax]) / 3.0;
  if (x == p[ax]) return 2;
  if (up) return x > p[ax] ? s : 0;
  return x < p[ax] ? -s : 0;
}

// The ray goes along the axis and the direction of the shortest way out of the host's box (the
// fewest cells to walk); x first on a tie.
bool HashDetector::inside(const World& w, const Vec3& p) {
  if (!p.allFinite() || (p.array() <= lo_.array()).any() || (p.array() >= hi_.array()).any()) return false;
  if (++query_ == 0) std::fill(seen_.begin(), seen_.end(), 0), query_ = 1;
  int ax = 0;
  bool up = true;
  double shortest = hi_.x() - p.x();
  for (int a = 0; a < 3; ++a) {
    if (hi_[a] - p[a] < shortest) shortest = hi_[a] - p[a], ax = a, up = true;
    if (p[a] - lo_[a] < shortest) shortest = p[a] - lo_[a], ax = a, up = false;
  }
  const Cell c = cell_of(p), far = cell_of(up ? hi_ : lo_);
  long long cc[3] = {c.i, c.j, c.k};
  const long long from = cc[ax], to = (ax == 0 ? far.i : ax == 1 ? far.j : far.k), step = up ? 1 : -1;
  int winding = 0;
  for (long long m = from;; m += step) {
    cc[ax] = m;
    const std::size_t q = bucket(cc[0], cc[1], cc[2]);
    if (stamp_[q] == now_) {
      for (int e = head_[q]; e >= 0; e = entry_next_[e]) {
        const int f = entry_tri_[e];
        if (seen_[f] == query_) continue;
        seen_[f] = query_;
        const int sgn = crossings(w, p, faces_[f], ax, up);
        if (sgn == 2) return false;  // on the surface
        winding += sgn;
      }
    }
    if (m == to) break;
  }
  return winding >= 1;
}

int HashDetector::nearest_triangle(const World& w, const Vec3& p) {
  if (++query_ == 0) std::fill(seen_.begin(), seen_.end(), 0), query_ = 1;
  const Cell c = cell_of(p);
  // Shells of cells at Chebyshev distance r: a cell of shell r + 1 is at least r cells away.
  const Cell lo = cell_of(lo_), hi = cell_of(hi_);
  const long long reach = std::max({std::abs(c.i - lo.i), std::abs(c.i - hi.i), std::abs(c.j - lo.j),
                                    std::abs(c.j - hi.j), std::abs(c.k - lo.k), std::abs(c.k - hi.k)});
  double best = std::numeric_limits<double>::infinity();
  int best_f = -1;
  for (long long r = 0; r <= reach; ++r) {
    for (long long i = c.i - r; i <= c.i + r; ++i)
      for (long long j = c.j - r; j <= c.j + r; ++j)
        for (long long k = c.k - r; k <= c.k + r; ++k) {
          if (std::max({std::abs(i - c.i), std::abs(j - c.j), std::abs(k - c.k)}) != r) continue;
          const std::size_t q = bucket(i, j, k);
          if (stamp_[q] != now_) continue;
          for (int e = head_[q]; e >= 0; e = entry_next_[e]) {
            const int f = entry_tri_[e];
            if (seen_[f] == query_) continue;
            seen_[f] = query_;
            const Tri& t = faces_[f];
            const double d2 =
                (closest_on_triangle(p, w.x[host_begin_ + t[0]], w.x[host_begin_ + t[1]], w.x[host_begin_ + t[2]]) - p)
                    .squaredNorm();
            if (d2 < best || (d2 == best && f < best_f)) best = d2, best_f = f;
          }
        }
    const double reached = static_cast<double>(r) * cell_;
    if (best_f >= 0 && best <= reached * reached) break;
  }
  return best_f;
}

void HashDetector::detect(const World& w, std::vector<Contact>& out) {
  out.clear();
  hash_host(w);
  const Body& g = w.bodies[guest_];
  for (int i = g.begin; i < g.end; ++i)
    if (inside(w, w.x[i])) out.push_back(Contact{i, nearest_triangle(w, w.x[i])});
}

int HashDetector::nearest_hosts(const World& w, const Contact& c, int k, int* out) const {
  if (c.key < 0 || c.key >= static_cast<int>(faces_.size())) return 0;
  return triangle_vertices_nearest_first(w, host_begin_, faces_[c.key], w.x[c.guest], k, out);
}

bool HashDetector::contact_direction(const World& w, const Contact& c, Vec3& n) const {
  if (c.key < 0 || c.key >= static_cast<int>(faces_.size())) return false;
  return triangle_direction(w, host_begin_, faces_[c.key], w.x[c.guest], n);
}

bool HashDetector::contact_point(const World& w, const Contact& c, ContactPoint& out) const {
  if (c.key < 0 || c.key >= static_cast<int>(faces_.size())) return false;
  return triangle_contact_point(w, host_begin_, faces_[c.key], w.x[c.guest], out);
}

HARNESS_DETECTOR(hash) {
  DetectorDef d;
  d.name = "hash";
  d.doc = "spatial hashing, Teschner et al. 2003";
  d.make = [] { return std::unique_ptr<CollisionDetector>(std::make_unique<HashDetector>()); };
  return d;
}

}  // namespace harness
