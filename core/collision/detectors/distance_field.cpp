#include "core/collision/detectors/distance_field.hpp"

#include "core/collision/detectors/triangles.hpp"
#include "core/collision/detectors/voxel_exact.hpp"
#include "core/collision/detectors/voxel_exact_geometry.hpp"
#include "core/collision/initializer.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>
#include <string>
#include <utility>

namespace harness {

namespace geo = voxel_exact_geometry;

void DistanceFieldDetector::initialize(const World& w, const ContactSpec& spec) {
  const Body& g = w.bodies[spec.guest];
  const Body& h = w.bodies[spec.host];
  if (h.n_surface <= 0 || h.faces.empty())
    throw std::invalid_argument("distance_field detector: the host '" + h.name + "' has no surface");
  guest_begin_ = g.begin, guest_end_ = g.end;
  host_begin_ = h.begin, host_surface_ = h.n_surface;
  margin_ = spec.margin;
  resample_ = spec.field_resample;
  if (!(resample_ > 0.0 && resample_ <= 1.0))
    throw std::invalid_argument("distance_field detector: field_resample must lie in (0, 1]");
  faces_ = h.faces;
  vf_start_ = h.vf_start, vf_faces_ = h.vf_faces;
  adjacent_ = edge_adjacency(faces_);  // the face across each edge, for the edges' pseudonormals
  h_ = resolve_voxel_size(w, spec);
  rebuilds_ = 0;
  sample(w);
  rebuilds_ = 0;  // the first sampling is not a rebuild
}

Vec3 DistanceFieldDetector::pseudonormal(const World& w, int face, int feature) const {
  const Tri& t = faces_[face];
  auto unit = [&](int f) {
    const Tri& u = faces_[f];
    const Vec3& a = w.x[host_begin_ + u[0]];
    const Vec3 n = (w.x[host_begin_ + u[1]] - a).cross(w.x[host_begin_ + u[2]] - a);
    const double len = n.norm();
    return len > 0.0 && std::isfinite(len) ? Vec3(n / len) : Vec3(Vec3::Zero());
  };
  if (feature == VoxelExactDetector::kInterior) return unit(face);
  if (feature >= 3) return unit(face) + unit(adjacent_[3 * face + (feature - 3)]);
  return vertex_pseudonormal(w, host_begin_, faces_, vf_start_, vf_faces_, t[feature]);  // a vertex
}

namespace {

// The closest point of triangle f to x: its squared distance, feature and point.
struct Nearest {
  double d2 = std::numeric_limits<double>::infinity();
  int face = -1, feature = 0;
  Vec3 q = Vec3::Zero();
};

}  // namespace

double DistanceFieldDetector::signed_distance(const World& w, const Vec3& x, int* face) const {
  Nearest best;
  const int F = static_cast<int>(faces_.size());
  for (int f = 0; f < F; ++f) consider(w, x, f, best.d2, best.face, best.feature, best.q);
  if (face) *face = best.face;
  return signed_of(w, x, best.d2, best.face, best.feature, best.q);
}

void DistanceFieldDetector::consider(const World& w, const Vec3& x, int f, double& d2, int& face, int& feature,
                                     Vec3& q) const {
  const Tri& t = faces_[f];
  const Vec3 v[3] = {w.x[host_begin_ + t[0]], w.x[host_begin_ + t[1]], w.x[host_begin_ + t[2]]};
  const Vec3 lo = v[0].cwiseMin(v[1]).cwiseMin(v[2]), hi = v[0].cwiseMax(v[1]).cwiseMax(v[2]);
  if (geo::box_bound(lo, hi, x) >= d2) return;  // cannot be nearer
  Vec3 p;
  double wt[3];
  int ft = 0;
  if (!geo::closest_feature(x, v[0], v[1], v[2], p, wt, ft)) geo::closest_on_edges(x, v, p, wt, ft);
  const double e2 = (x - p).squaredNorm();
  if (e2 < d2) d2 = e2, face = f, feature = ft, q = p;
}

double DistanceFieldDetector::signed_of(const World& w, const Vec3& x, double d2, int face, int feature,
                                        const Vec3& q) const {
  if (face < 0) return std::numeric_limits<double>::infinity();
  const double d = std::sqrt(d2);
  return (x - q).dot(pseudonormal(w, face, feature)) < 0.0 ? -d : d;
}

// The corner's nearest triangle from the buckets: the cells around the corner ring by ring
// (Chebyshev rings of cells; every point of ring r lies at least r voxels from the corner), until
// the next ring cannot hold a nearer point. A triangle is in every cell its box overlaps, so the
// cell holding its nearest point to the corner is among them: the answer is the brute force's.
double DistanceFieldDetector::corner_distance(const World& w, int i, int j, int k, int* face) {
  const Vec3 x = origin_ + h_ * Vec3(i, j, k);
  ++stamp_now_;
  double d2 = std::numeric_limits<double>::infinity();
  int best_f = -1, feature = 0;
  Vec3 q = Vec3::Zero();
  const int c[3] = {i, j, k};
  const int rings = std::max(n_[0], std::max(n_[1], n_[2]));
  for (int r = 0; r <= rings; ++r) {
    int lo[3], hi[3];
    for (int a = 0; a < 3; ++a) lo[a] = std::max(0, c[a] - 1 - r), hi[a] = std::min(n_[a] - 1, c[a] + r);
    for (int z = lo[2]; z <= hi[2]; ++z)
      for (int y = lo[1]; y <= hi[1]; ++y)
        for (int xx = lo[0]; xx <= hi[0]; ++xx) {
          const bool inner = r > 0 && xx >= c[0] - r && xx <= c[0] + r - 1 && y >= c[1] - r && y <= c[1] + r - 1 &&
                             z >= c[2] - r && z <= c[2] + r - 1;
          if (inner) continue;  // in an earlier ring
          const int cell = (z * n_[1] + y) * n_[0] + xx;
          for (int b = bucket_start_[cell]; b < bucket_start_[cell + 1]; ++b) {
            const int f = bucket_faces_[b];
            if (stamp_[f] == stamp_now_) continue;
            stamp_[f] = stamp_now_;
            consider(w, x, f, d2, best_f, feature, q);
          }
        }
    if (best_f >= 0 && (r + 1) * h_ >= std::sqrt(d2)) break;
  }
  if (face) *face = best_f;
  return signed_of(w, x, d2, best_f, feature, q);
}

void DistanceFieldDetector::sample(const World& w) {
  Vec3 lo = Vec3::Constant(std::numeric_limits<double>::infinity()), hi = -lo;
  for (int s = 0; s < host_surface_; ++s) lo = lo.cwiseMin(w.x[host_begin_ + s]), hi = hi.cwiseMax(w.x[host_begin_ + s]);
  if (!lo.allFinite() || !hi.allFinite())
    throw std::invalid_argument("distance_field detector: the host's positions are not finite");
  // The paper's grid attached to the host: centred on its box, power-of-two voxels, margin voxels.
  const Vec3 c = 0.5 * (lo + hi);
  double count = 1.0;
  for (int a = 0; a < 3; ++a) {
    const double n = std::ceil((hi[a] - lo[a]) / h_) + 2.0 * margin_;
    count *= n + 1.0;
    n_[a] = static_cast<int>(std::min(n, 1e9));
    origin_[a] = c[a] - 0.5 * n * h_;
  }
  if (!(count <= static_cast<double>(kMaxVoxels)))
    throw std::invalid_argument("distance_field detector: the field needs " + std::to_string(count) +
                                " corners (more than " + std::to_string(kMaxVoxels) + "): use a larger voxel_size");
  phi_.resize(static_cast<std::size_t>(count));
  face_.resize(phi_.size());
  // Each triangle in the cells its box overlaps (CSR over the grid's cells).
  const int F = static_cast<int>(faces_.size());
  const std::size_t cells = static_cast<std::size_t>(n_[0]) * n_[1] * n_[2];
  bucket_start_.assign(cells + 1, 0);
  auto range = [&](int f, int c0[3], int c1[3]) {
    const Tri& t = faces_[f];
    const Vec3 &a = w.x[host_begin_ + t[0]], &b = w.x[host_begin_ + t[1]], &q = w.x[host_begin_ + t[2]];
    const Vec3 l = a.cwiseMin(b).cwiseMin(q), u = a.cwiseMax(b).cwiseMax(q);
    for (int d = 0; d < 3; ++d) {
      c0[d] = std::clamp(static_cast<int>(std::floor((l[d] - origin_[d]) / h_)), 0, n_[d] - 1);
      c1[d] = std::clamp(static_cast<int>(std::floor((u[d] - origin_[d]) / h_)), 0, n_[d] - 1);
    }
  };
  for (int pass = 0; pass < 2; ++pass) {
    std::vector<int> cursor;
    if (pass == 1) {
      for (std::size_t c2 = 0; c2 < cells; ++c2) bucket_start_[c2 + 1] += bucket_start_[c2];
      bucket_faces_.resize(static_cast<std::size_t>(bucket_start_[cells]));
      cursor.assign(bucket_start_.begin(), bucket_start_.end() - 1);
    }
    for (int f = 0; f < F; ++f) {
      int c0[3], c1[3];
      range(f, c0, c1);
      for (int z = c0[2]; z <= c1[2]; ++z)
        for (int y = c0[1]; y <= c1[1]; ++y)
          for (int xx = c0[0]; xx <= c1[0]; ++xx) {
            const int cell = (z * n_[1] + y) * n_[0] + xx;
            if (pass == 0) ++bucket_start_[cell + 1];
            else bucket_faces_[cursor[cell]++] = f;
          }
    }
  }
  stamp_.assign(faces_.size(), 0);
  stamp_now_ = 0;
  for (int k = 0; k <= n_[2]; ++k)
    for (int j = 0; j <= n_[1]; ++j)
      for (int i = 0; i <= n_[0]; ++i) {
        const int q = corner(i, j, k);
        phi_[q] = corner_distance(w, i, j, k, &face_[q]);
      }
  sampled_at_.assign(w.x.begin() + host_begin_, w.x.begin() + host_begin_ + host_surface_);
  ++rebuilds_;
}

bool DistanceFieldDetector::cell_of(const Vec3& x, std::array<int, 3>& c, Vec3& t) const {
  for (int a = 0; a < 3; ++a) {
    const double u = (x[a] - origin_[a]) / h_;
    if (!(u >= 0.0 && u <= n_[a])) return false;
    c[a] = std::min(static_cast<int>(u), n_[a] - 1);
    t[a] = u - c[a];
  }
  return true;
}

bool DistanceFieldDetector::field(const Vec3& x, double& phi, Vec3* grad) const {
  std::array<int, 3> c;
  Vec3 t;
  if (phi_.empty() || !cell_of(x, c, t)) return false;
  double v[8];
  for (int k = 0; k < 2; ++k)
    for (int j = 0; j < 2; ++j)
      for (int i = 0; i < 2; ++i) v[4 * k + 2 * j + i] = phi_[corner(c[0] + i, c[1] + j, c[2] + k)];
  const double x0 = 1.0 - t[0], y0 = 1.0 - t[1], z0 = 1.0 - t[2];
  phi = z0 * (y0 * (x0 * v[0] + t[0] * v[1]) + t[1] * (x0 * v[2] + t[0] * v[3])) +
        t[2] * (y0 * (x0 * v[4] + t[0] * v[5]) + t[1] * (x0 * v[6] + t[0] * v[7]));
  if (grad) {
    (*grad)[0] = (z0 * (y0 * (v[1] - v[0]) + t[1] * (v[3] - v[2])) + t[2] * (y0 * (v[5] - v[4]) + t[1] * (v[7] - v[6]))) / h_;
    (*grad)[1] = (z0 * (x0 * (v[2] - v[0]) + t[0] * (v[3] - v[1])) + t[2] * (x0 * (v[6] - v[4]) + t[0] * (v[7] - v[5]))) / h_;
    (*grad)[2] = (y0 * (x0 * (v[4] - v[0]) + t[0] * (v[5] - v[1])) + t[1] * (x0 * (v[6] - v[2]) + t[0] * (v[7] - v[3]))) / h_;
  }
  return true;
}

void DistanceFieldDetector::detect(const World& w, std::vector<Contact>& out) {
  out.clear();
  const double limit = resample_ * h_;
  for (int s = 0; s < host_surface_; ++s)
    if (!((w.x[host_begin_ + s] - sampled_at_[s]).squaredNorm() <= limit * limit)) {
      try {
        sample(w);
      } catch (const std::invalid_argument& e) {  // during a run: a failed step (named after any blow-up)
        throw std::runtime_error(e.what());
      }
      break;
    }
  for (int i = guest_begin_; i < guest_end_; ++i) {
    double phi;
    if (field(w.x[i], phi) && phi < 0.0) out.push_back(Contact{i, -1});
  }
}

int DistanceFieldDetector::nearest_face(const World& w, const Vec3& x) const {
  std::array<int, 3> c;
  Vec3 t;
  if (!cell_of(x, c, t)) return -1;
  int best_f = -1;
  double best = std::numeric_limits<double>::infinity();
  for (int k = 0; k < 2; ++k)
    for (int j = 0; j < 2; ++j)
      for (int i = 0; i < 2; ++i) {
        const int f = face_[corner(c[0] + i, c[1] + j, c[2] + k)];
        if (f < 0 || f == best_f) continue;
        const Tri& tr = faces_[f];
        const Vec3 v[3] = {w.x[host_begin_ + tr[0]], w.x[host_begin_ + tr[1]], w.x[host_begin_ + tr[2]]};
        Vec3 q;
        double wt[3];
        int feature = 0;
        if (!geo::closest_feature(x, v[0], v[1], v[2], q, wt, feature)) geo::closest_on_edges(x, v, q, wt, feature);
        const double d2 = (x - q).squaredNorm();
        if (d2 < best) best = d2, best_f = f;
      }
  return best_f;
}

bool DistanceFieldDetector::contact_direction(const World& w, const Contact& c, Vec3& n) const {
  double phi;
  Vec3 g;
  if (!field(w.x[c.guest], phi, &g)) return false;
  const double len = g.norm();
  if (!(len > 0.0) || !std::isfinite(len)) return false;
  n = g / len;
  return true;
}

bool DistanceFieldDetector::contact_point(const World& w, const Contact& c, ContactPoint& out) const {
  const Vec3& x = w.x[c.guest];
  double phi;
  Vec3 g;
  if (!field(x, phi, &g)) return false;
  const int f = nearest_face(w, x);
  if (f < 0) return false;
  const Tri& t = faces_[f];
  const double len = g.norm();
  if (len > 0.0 && std::isfinite(len)) {
    out.normal = g / len;
  } else if (!face_normal(w, host_begin_, t, out.normal)) {
    return false;
  }
  out.depth = -phi;
  const Vec3 v[3] = {w.x[host_begin_ + t[0]], w.x[host_begin_ + t[1]], w.x[host_begin_ + t[2]]};
  Vec3 q;
  int feature = 0;
  if (!geo::closest_feature(x, v[0], v[1], v[2], q, out.weight, feature)) geo::closest_on_edges(x, v, q, out.weight, feature);
  for (int k = 0; k < 3; ++k) out.hosts[k] = host_begin_ + t[k];
  return true;
}

int DistanceFieldDetector::nearest_hosts(const World& w, const Contact& c, int k, int* out) const {
  const int f = nearest_face(w, w.x[c.guest]);
  if (f < 0) return 0;
  return triangle_vertices_nearest_first(w, host_begin_, faces_[f], w.x[c.guest], k, out);
}

bool DistanceFieldDetector::region(Vec3& lo, Vec3& hi) const {
  if (phi_.empty()) return false;
  lo = origin_;
  hi = origin_ + h_ * Vec3(n_[0], n_[1], n_[2]);
  return true;
}

HARNESS_DETECTOR(distance_field) {
  DetectorDef d;
  d.name = "distance_field";
  d.doc = "the host's signed distance sampled at the corners of the paper's power-of-two voxels over its box, resampled when a host vertex moves field_resample of a voxel; a node is in contact where the interpolated field is negative";
  d.make = [] { return std::unique_ptr<CollisionDetector>(std::make_unique<DistanceFieldDetector>()); };
  return d;
}

}  // namespace harness
