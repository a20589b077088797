#include "core/collision/detectors/voxel_exact.hpp"

#include "core/collision/detectors/triangles.hpp"
#include "core/collision/detectors/voxel_exact_geometry.hpp"
#include "core/parallel.hpp"
#include "core/device/contact_kernels.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>
#include <cstring>
#include <unordered_map>

#ifdef _OPENMP
#include <omp.h>
#endif

namespace harness {

namespace {

constexpr double kInf = std::numeric_limits<double>::infinity();
// 1/sqrt(3) and the relative slack that keeps the band a lower bound under rounding (the band
// then errs on the safe side by ~1e-12 of L_max; rounding errors are ~1e-16).
constexpr double kInvSqrt3 = 0.57735026918962576;
constexpr double kSlack = 1e-12;

inline int thread_index() {
#ifdef _OPENMP
  return omp_get_thread_num();
#else
  return 0;
#endif
}

using namespace voxel_exact_geometry;

}  // namespace

double VoxelExactDetector::automatic_voxel_size(const World& w, const ContactSpec& spec) {
  ContactSpec paper = spec;
  paper.voxel_size = 0.0;
  double v = resolve_voxel_size(w, paper);
  const Body& h = w.bodies[spec.host];
  double l2 = 0.0;
  for (const Tri& t : h.faces)
    for (int k = 0; k < 3; ++k) l2 = std::max(l2, (w.x[h.begin + t[k]] - w.x[h.begin + t[(k + 1) % 3]]).squaredNorm());
  const double need = std::sqrt(l2) * kInvSqrt3 * (1.0 + kSlack);
  if (!std::isfinite(need)) throw std::invalid_argument("voxel_exact: the host's surface is not finite");
  while (!(v > need)) v *= 2.0;
  return v;
}

void VoxelExactDetector::initialize(const World& w, const ContactSpec& spec) {
  const Body& h = w.bodies[spec.host];
  if (h.faces.empty() || h.n_surface <= 0)
    throw std::invalid_argument("voxel_exact detector: the host '" + h.name + "' has no surface");
  if (static_cast<int>(h.vf_start.size()) != h.n_surface + 1)
    throw std::invalid_argument("voxel_exact detector: the host '" + h.name + "' has no vertex-face table");
  // The grid: the paper's, with the surface vertices listed and the automatic size above.
  ContactSpec grid_spec = spec;
  grid_spec.host_nodes = HostNodes::surface;
  if (spec.voxel_size == 0.0) grid_spec.voxel_size = automatic_voxel_size(w, spec);
  init_.initialize(w, grid_spec, grid_);
  host_begin_ = h.begin;
  n_surface_ = h.n_surface;
  faces_ = h.faces;
  vf_start_ = h.vf_start;
  vf_faces_ = h.vf_faces;

  // Edge adjacency of a closed, consistently oriented 2-manifold: directed edge (u, v) of one
  // face meets (v, u) of exactly one other.
  const std::size_t F = faces_.size();
  std::unordered_map<long long, int> directed;  // (u, v) -> 3 f + k
  directed.reserve(3 * F);
  auto key = [&](int u, int v) { return static_cast<long long>(u) * n_surface_ + v; };
  const std::string bad = "voxel_exact detector: the host '" + h.name + "' surface is not a closed, consistently "
                          "oriented 2-manifold";
  for (std::size_t f = 0; f < F; ++f)
    for (int k = 0; k < 3; ++k) {
      const int u = faces_[f][k], v = faces_[f][(k + 1) % 3];
      if (u < 0 || u >= n_surface_ || v < 0 || v >= n_surface_ || u == v) throw std::invalid_argument(bad);
      if (!directed.emplace(key(u, v), static_cast<int>(3 * f) + k).second) throw std::invalid_argument(bad);
    }
  adjacent_.assign(3 * F, -1);
  edges_.clear();
  edges_.reserve(3 * F / 2);
  for (std::size_t f = 0; f < F; ++f)
    for (int k = 0; k < 3; ++k) {
      const int u = faces_[f][k], v = faces_[f][(k + 1) % 3];
      const auto it = directed.find(key(v, u));
      if (it == directed.end()) throw std::invalid_argument(bad);
      adjacent_[3 * f + k] = it->second / 3;
      if (u < v) edges_.push_back(Edge{host_begin_ + u, host_begin_ + v});
    }

  const Body& g = w.bodies[spec.guest];
  guest_begin_ = g.begin;
  guest_size_ = g.size();
  hits_.reset(new Hit[static_cast<std::size_t>(std::max(1, guest_size_))]);
  hit_step_.assign(static_cast<std::size_t>(guest_size_), 0);
  now_ = 0;
  beyond_ = 0;
  lmax_ = lterm_ = 0.0;
  ws_.clear();
  ensure_workspaces(1);
}

void VoxelExactDetector::ensure_workspaces(int threads) {
  const std::size_t F = faces_.size();
  while (static_cast<int>(ws_.size()) < threads) {
    Workspace ws;
    ws.stamp.assign(F, 0);
    for (Entry& e : ws.entry) {
      e.cap = kEntryCap;
      e.tri.assign(kEntryCap, -1);
      e.box.assign(static_cast<std::size_t>(6) * kEntryCap, 0.0);
    }
    ws.gathered.assign(F, -1);
    ws.bound.assign(F + 4, 0.0);
    ws_.push_back(std::move(ws));
  }
}

bool VoxelExactDetector::region(Vec3& lo, Vec3& hi) const {
  const GridGeometry& g = grid_.geometry();
  if (g.num_voxels() <= 0) return false;
  lo = g.center + g.voxel * g.lo.cast<double>();
  hi = lo + g.voxel * g.dims.cast<double>();
  return true;
}

double VoxelExactDetector::longest_edge_now(const World& w) const {
  const std::size_t E = edges_.size();
  const int T = std::min(64, threads_for(E, 32768));
  double part[64];
  const Edge* e = edges_.data();
#pragma omp parallel for num_threads(T) if(T > 1) schedule(static, 1)
  for (int t = 0; t < T; ++t) {
    std::size_t b, end;
    split_range(E, T, t, b, end);
    double m = 0.0;
    for (std::size_t i = b; i < end; ++i) {
      const double d2 = (w.x[e[i][0]] - w.x[e[i][1]]).squaredNorm();
      m = d2 > m ? d2 : m;  // NaN never wins (a non-finite host finds nothing anyway)
    }
    part[t] = m;
  }
  double m = 0.0;
  for (int t = 0; t < T; ++t) m = part[t] > m ? part[t] : m;  // a max: exact in any order
  return std::sqrt(m);
}

double VoxelExactDetector::band_of(const Vec3& x, const double tlo[3], const double thi[3]) const {
  const GridGeometry& g = grid_.geometry();
  const double inv = 1.0 / g.voxel;  // a power of two: exact
  double r = kInf, far = 0.0;
  for (int a = 0; a < 3; ++a) {
    const double t = (x[a] - g.center[a]) * inv;  // as VoxelIndexer computes it
    r = std::min(r, std::min(t - tlo[a], thi[a] - t));
    far = std::max(far, std::fabs(t));
  }
  // Slack: a vertex's voxel comes from its own rounded t, ~1e-16 (|t| + 2) voxels from the exact.
  return g.voxel * (r - 1e-14 * (far + 2.0)) - lterm_;
}

double VoxelExactDetector::band_at(const Vec3& x) const {
  const GridGeometry& g = grid_.geometry();
  if (g.num_voxels() <= 0) return -kInf;
  Vec3i ijk;
  if (voxel_of(g, x, &ijk) < 0) return -kInf;
  double tlo[3], thi[3];
  for (int a = 0; a < 3; ++a) {
    tlo[a] = static_cast<double>(g.lo[a]) + std::max(ijk[a] - 1, 0);
    thi[a] = static_cast<double>(g.lo[a]) + std::min(ijk[a] + 2, g.dims[a]);
  }
  return band_of(x, tlo, thi);
}

VoxelExactDetector::Entry& VoxelExactDetector::candidates(const World& w, int cell, Workspace& ws) const {
  const int slot = static_cast<int>((static_cast<std::uint32_t>(cell) * 2654435761u) >> (32 - kEntryBits));
  Entry& e = ws.entry[slot];
  if (e.step == now_ && e.cell == cell) return e;
  const GridGeometry& g = grid_.geometry();
  e.step = now_;
  e.cell = cell;
  const Vec3i ijk = voxel_ijk(g, cell);
  int lo[3], hi[3];
  for (int a = 0; a < 3; ++a) {
    lo[a] = std::max(ijk[a] - 1, 0);
    hi[a] = std::min(ijk[a] + 2, g.dims[a]);
    e.tlo[a] = static_cast<double>(g.lo[a]) + lo[a];
    e.thi[a] = static_cast<double>(g.lo[a]) + hi[a];
  }
  if (++ws.gather == 0) {  // the stamps wrapped: start afresh
    std::fill(ws.stamp.begin(), ws.stamp.end(), 0u);
    ws.gather = 1;
  }
  const std::uint32_t now = ws.gather;
  std::uint32_t* stamp = ws.stamp.data();
  int* tris = ws.gathered.data();
  int m = 0;
  for (int z = lo[2]; z < hi[2]; ++z)
    for (int y = lo[1]; y < hi[1]; ++y)
      for (int x = lo[0]; x < hi[0]; ++x) {
        const int c = x + g.dims.x() * (y + g.dims.y() * z);
        if (!grid_.occupied(c)) continue;
        for (int node : grid_.nodes(c)) {
          const int s = node - host_begin_;
          for (int k = vf_start_[s]; k < vf_start_[s + 1]; ++k) {
            const int f = vf_faces_[k];
            if (stamp[f] == now) continue;
            stamp[f] = now;
            tris[m++] = f;
          }
        }
      }
  e.count = m;
  if (m > e.cap) {  // the entry's storage doubles (a few times in a run at most)
    e.cap = std::max(m + (m & 1), 2 * e.cap);  // even: box_bounds reads candidates in pairs
    e.tri.assign(static_cast<std::size_t>(e.cap), -1);
    e.box.assign(static_cast<std::size_t>(6) * e.cap, 0.0);
  }
  const std::size_t cap = static_cast<std::size_t>(e.cap);
  int* dst = e.tri.data();
  double* box = e.box.data();
  for (int i = 0; i < m; ++i) {
    const int f = tris[i];
    dst[i] = f;
    const Tri& t = faces_[f];
    const Vec3 &a = w.x[host_begin_ + t[0]], &b = w.x[host_begin_ + t[1]], &c = w.x[host_begin_ + t[2]];
    for (std::size_t d = 0; d < 3; ++d) {
      box[d * cap + i] = std::min(a[d], std::min(b[d], c[d]));
      box[(3 + d) * cap + i] = std::max(a[d], std::max(b[d], c[d]));
    }
  }
  return e;
}

Vec3 VoxelExactDetector::unit_normal(const World& w, int face) const {
  const Tri& t = faces_[face];
  const Vec3& a = w.x[host_begin_ + t[0]];
  const Vec3 n = (w.x[host_begin_ + t[1]] - a).cross(w.x[host_begin_ + t[2]] - a);
  const double len = n.norm();
  return len > 0.0 && std::isfinite(len) ? Vec3(n / len) : Vec3(Vec3::Zero());
}

Vec3 VoxelExactDetector::pseudonormal(const World& w, int face, int feature) const {
  if (feature == kInterior) {  // its direction is all the verdict needs
    const Tri& t = faces_[face];
    const Vec3& a = w.x[host_begin_ + t[0]];
    return (w.x[host_begin_ + t[1]] - a).cross(w.x[host_begin_ + t[2]] - a);
  }
  if (feature >= 3) return unit_normal(w, face) + unit_normal(w, adjacent_[3 * face + (feature - 3)]);
  // A vertex: its incident faces' normals weighted by their angles at it.
  return vertex_pseudonormal(w, host_begin_, faces_, vf_start_, vf_faces_, faces_[face][feature]);
}

bool VoxelExactDetector::evaluate(const World& w, const Vec3& x, int cell, Workspace& ws, Hit& out) const {
  const Entry& e = candidates(w, cell, ws);
  const int m = e.count;
  if (m == 0) return false;  // nothing listed around: deeper than the grid sees, or far outside
  const int* tris = e.tri.data();
  double* bound = ws.bound.data();

  // The nearest candidate: the one with the least lower bound first, then every other one whose
  // bound is below the best distance so far (one whose bound is not can at most tie it: any
  // nearest point gives the exact distance and verdict). Ties go to the first found, in the
  // voxel's fixed candidate order: the answer does not depend on the thread.
  double best = kInf, best_w[3] = {1, 0, 0};
  int best_f = -1, best_feature = 0;
  Vec3 best_p = Vec3::Zero();
  auto consider = [&](int i) {
    Vec3 v[3], q;
    double wt[3];
    int feature;
    const Tri& t = faces_[tris[i]];
    for (int k = 0; k < 3; ++k) v[k] = w.x[host_begin_ + t[k]];
    if (!closest_feature(x, v[0], v[1], v[2], q, wt, feature)) closest_on_edges(x, v, q, wt, feature);
    const double d2 = (q - x).squaredNorm();
    const int f = tris[i];
    if (d2 < best) {
      best = d2, best_f = f, best_feature = feature, best_p = q;
      for (int k = 0; k < 3; ++k) best_w[k] = wt[k];
    }
  };
  // Lower bounds: the squared distance from x to each candidate's box (min and max are exact,
  // so the cached and the computed boxes are the same numbers).
  box_bounds(e.box.data(), e.cap, m, x, bound);
  int first = 0;
  for (int i = 1; i < m; ++i) first = bound[i] < bound[first] ? i : first;
  consider(first);
  for (int i = 0; i < m; ++i)
    if (bound[i] < best && i != first) consider(i);
  if (best_f < 0 || !std::isfinite(best)) return false;

  const Vec3 N = pseudonormal(w, best_f, best_feature);
  if (!((x - best_p).dot(N) < 0.0)) return false;  // outside, or on the surface
  const double d = std::sqrt(best);
  out.tri = best_f;
  out.feature = best_feature;
  out.depth = d;
  out.band = band_of(x, e.tlo, e.thi);
  out.within = d < out.band;
  for (int k = 0; k < 3; ++k) out.weight[k] = best_w[k];
  Vec3 n;
  if (d > 1e-12 * (1.0 + x.norm()) && std::isfinite(d)) {
    n = (best_p - x) / d;
  } else {
    const double len = N.norm();
    n = len > 0.0 && std::isfinite(len) ? Vec3(N / len) : Vec3(unit_normal(w, best_f));
  }
  for (int k = 0; k < 3; ++k) out.normal[k] = n[k];
  return true;
}

template <class Emit>
void VoxelExactDetector::scan(const World& w, const VoxelIndexer& idx, int begin, int end, Workspace& ws, Emit&& emit,
                              int& beyond, int& undecided_part) {
  constexpr int kBatch = 256;
  int cells[kBatch];
  const Vec3 &lo = init_.host_lo(), &hi = init_.host_hi();
  for (int b = begin; b < end; b += kBatch) {
    const int m = std::min(kBatch, end - b);
    idx(w.x.data() + b, static_cast<std::size_t>(m), cells);
    for (int k = 0; k < m; ++k) {
      if (cells[k] < 0) continue;
      const int i = b + k, local = i - guest_begin_;
      // Outside the host's box, or on it: outside a closed surface within it (exact, and most
      // nodes of a region's margin).
      const Vec3& x = w.x[i];
      if (!((x.array() > lo.array()).all() && (x.array() < hi.array()).all())) continue;
      Hit& h = hits_[static_cast<std::size_t>(local)];
      if (!evaluate(w, w.x[i], cells[k], ws, h)) {
        // Inside the host's box with no host vertex listed in its block: the grid cannot tell
        // (a node deep inside, or in a hollow of the box): undecided, counted beyond the band.
        if (candidates(w, cells[k], ws).count == 0) ++beyond, ++undecided_part;
        continue;
      }
      hit_step_[static_cast<std::size_t>(local)] = now_;
      beyond += h.within ? 0 : 1;
      emit(Contact{i, h.tri});
    }
  }
}

void VoxelExactDetector::detect(const World& w, std::vector<Contact>& out) {
  out.clear();
  beyond_ = 0;
  undecided_ = 0;
  if (++now_ == 0) {  // the counter wrapped: forget every stamp
    std::fill(hit_step_.begin(), hit_step_.end(), 0u);
    for (Workspace& ws : ws_)
      for (Entry& e : ws.entry) e.step = 0;
    now_ = 1;
  }
  const GridGeometry g = init_.update(w, grid_);
  grid_.fill(g, w.x, host_begin_, host_begin_ + n_surface_);  // in parallel parts when large
  if (grid_.listed_nodes() == 0) return;
  lmax_ = longest_edge_now(w);
  lterm_ = lmax_ * kInvSqrt3 * (1.0 + kSlack);
  const VoxelIndexer idx(g);
  const std::size_t n = static_cast<std::size_t>(guest_size_);
  const int T = threads_for(n, 8192);
  if (T == 1) {
    scan(w, idx, guest_begin_, guest_begin_ + guest_size_, ws_[0], [&](const Contact& c) { out.push_back(c); },
         beyond_, undecided_);
    return;
  }
  // Parallel lookup as in voxel.cpp: each chunk writes its contacts into its own part of the
  // scratch list, the parts are appended in chunk order; chunks handed out dynamically. Each
  // thread has its workspace; a node's answer does not depend on which thread computes it.
  if (scratch_.size() < n) scratch_.resize(n);  // once, on the first parallel detection
  ensure_workspaces(T);                          // once per new thread count
  const int L = std::min(64, 4 * T);
  int found[64] = {}, beyond[64] = {}, undecided[64] = {};
#pragma omp parallel num_threads(T)
  {
    Workspace& ws = ws_[static_cast<std::size_t>(thread_index())];
#pragma omp for schedule(dynamic, 1)
    for (int c = 0; c < L; ++c) {
      std::size_t b, e;
      split_range(n, L, c, b, e);
      Contact* dst = scratch_.data() + b;
      int m = 0, over = 0, unknown = 0;
      scan(w, idx, guest_begin_ + static_cast<int>(b), guest_begin_ + static_cast<int>(e), ws,
           [&](const Contact& k) { dst[m++] = k; }, over, unknown);
      found[c] = m;
      beyond[c] = over;
      undecided[c] = unknown;
    }
  }
  for (int c = 0; c < L; ++c) {
    std::size_t b, e;
    split_range(n, L, c, b, e);
    out.insert(out.end(), scratch_.begin() + static_cast<std::ptrdiff_t>(b),
               scratch_.begin() + static_cast<std::ptrdiff_t>(b) + found[c]);
    beyond_ += beyond[c];
    undecided_ += undecided[c];
  }
}

const VoxelExactDetector::Hit* VoxelExactDetector::hit(const Contact& c) const {
  const long long local = static_cast<long long>(c.guest) - guest_begin_;
  if (local < 0 || local >= guest_size_ || now_ == 0) return nullptr;
  const std::size_t i = static_cast<std::size_t>(local);
  if (hit_step_[i] != now_ || hits_[i].tri != c.key) return nullptr;
  return &hits_[i];
}

int VoxelExactDetector::nearest_hosts(const World& w, const Contact& c, int k, int* out) const {
  const Hit* h = hit(c);
  if (!h) return 0;
  return triangle_vertices_nearest_first(w, host_begin_, faces_[h->tri], w.x[c.guest], k, out);
}

bool VoxelExactDetector::contact_direction(const World&, const Contact& c, Vec3& n) const {
  const Hit* h = hit(c);
  if (!h) return false;
  n = Vec3(h->normal[0], h->normal[1], h->normal[2]);
  return n.squaredNorm() > 0.0;
}

bool VoxelExactDetector::contact_point(const World&, const Contact& c, ContactPoint& out) const {
  const Hit* h = hit(c);
  if (!h) return false;
  out.normal = Vec3(h->normal[0], h->normal[1], h->normal[2]);
  out.depth = h->depth;
  for (int k = 0; k < 3; ++k) {
    out.hosts[k] = host_begin_ + faces_[h->tri][k];
    out.weight[k] = h->weight[k];
  }
  return true;
}

HARNESS_DETECTOR(voxel_exact) {
  DetectorDef d;
  d.name = "voxel_exact";
  d.doc = "the paper's grid with an exact narrow phase: the closest host triangle and its pseudonormal, exact within a stated band";
  d.make = [] { return std::unique_ptr<CollisionDetector>(std::make_unique<VoxelExactDetector>()); };
  d.device = dev::kDetVoxelExact;
  return d;
}

}  // namespace harness
