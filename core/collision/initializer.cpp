#include "core/collision/initializer.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <sstream>
#include <stdexcept>

namespace harness {

namespace {

bool all_finite(const Vec3& a) { return std::isfinite(a.x()) && std::isfinite(a.y()) && std::isfinite(a.z()); }

std::string pair_name(const World& w, int host, int guest) {
  return "contact pair (host '" + w.bodies[host].name + "', guest '" + w.bodies[guest].name + "')";
}

}  // namespace

double resolve_voxel_size(const World& w, const ContactSpec& spec) {
  if (!(spec.voxel_size >= 0.0) || !std::isfinite(spec.voxel_size))
    throw std::invalid_argument("voxel_size must be finite and >= 0 (0 = automatic)");
  if (spec.voxel_size > 0.0) return round_down_pow2(spec.voxel_size);

  // The smallest power of two at or above the host's node spacing at rest (its mean surface
  // edge; a body without a surface: node_spacing): a finer voxel inside the host can hold none of
  // its nodes, and the guest's nodes there go undetected (the run warns about an explicit one).
  const Body& b = w.bodies[spec.host];
  const double spacing = host_node_spacing(w, spec.host);
  if (!(spacing > 0.0) || !std::isfinite(spacing))
    throw std::invalid_argument("cannot choose an automatic voxel_size for host '" + b.name +
                                "' (no springs and no extent); give voxel_size");
  const double v = round_down_pow2(spacing);
  return v < spacing ? 2.0 * v : v;
}

double host_node_spacing(const World& w, int host) {
  const double e = rest_surface_edge(w, host);
  return e > 0.0 ? e : rest_spring_length(w, host);
}

void Initializer::initialize(const World& w, const ContactSpec& spec, VoxelData& grid) {
  if (spec.margin < 0) throw std::invalid_argument(pair_name(w, spec.host, spec.guest) + ": margin must be >= 0");
  host_ = spec.host;
  guest_ = spec.guest;
  region_ = spec.region;
  margin_ = spec.margin;
  host_nodes_ = spec.host_nodes;
  voxel_ = resolve_voxel_size(w, spec);
  rebuilds_ = 0;

  Vec3 lo, hi;
  body_bounds(w, spec.host, lo, hi);
  const Vec3 c = 0.5 * (lo + hi);
  const Vec3 h = 0.5 * (hi - lo);
  if (!all_finite(c) || !all_finite(h))
    throw std::invalid_argument(pair_name(w, host_, guest_) +
                                ": host has no nodes or non-finite positions");
  center_ = c;
  host_lo_ = lo;
  host_hi_ = hi;
  build(w, h, c, true, grid);
}

Vec3 Initializer::guest_center(const World& w) const {
  Vec3 lo, hi;
  body_bounds(w, guest_, lo, hi);
  return 0.5 * (lo + hi);
}

void Initializer::build(const World& w, const Vec3& host_half, const Vec3& host_center,
                        bool initial, VoxelData& grid) {
  const double m = margin_;
  // Everything in double first: huge extents must fail the cap, not overflow an int.
  double n[3], dims_full[3];
  double full_count = 1.0;
  for (int a = 0; a < 3; ++a) {
    n[a] = std::floor(host_half[a] / voxel_) + 2.0;
    dims_full[a] = 2.0 * (n[a] + m);
    full_count *= dims_full[a];
  }

  // Half: the side of the host's box facing the guest.
  int axis = -1, sign = 1;
  if (region_ == Region::half) {
    const Vec3 d = guest_center(w) - host_center;
    double best = 0.0;
    for (int a = 0; a < 3; ++a) {
      const double ad = std::fabs(d[a]);
      const double r = host_half[a] > 0.0 ? ad / host_half[a]
                                          : (ad > 0.0 ? std::numeric_limits<double>::infinity() : 0.0);
      if (r > best) {  // strict: ties keep the first axis; NaN never wins
        best = r;
        axis = a;
      }
    }
    if (axis >= 0) sign = d[axis] >= 0.0 ? 1 : -1;
  }
  double region_count = full_count;
  if (axis >= 0) region_count = full_count / dims_full[axis] * (n[axis] + 2.0 * m);
  const double alloc_count = region_ == Region::overlap ? full_count : region_count;

  if (!(alloc_count <= static_cast<double>(kMaxVoxels))) {
    std::ostringstream msg;
    msg << pair_name(w, host_, guest_) << ": the voxel region needs " << alloc_count << " voxels ("
        << dims_full[0] << " x " << dims_full[1] << " x " << dims_full[2]
        << " for the full box, voxel " << voxel_ << " m), above the cap of " << kMaxVoxels
        << "; use a larger voxel_size or a smaller margin";
    if (initial) throw std::invalid_argument(msg.str());
    throw std::runtime_error(msg.str() + " (the host grew during the run)");
  }

  built_h_ = host_half;
  half_axis_ = axis;
  half_sign_ = sign;
  for (int a = 0; a < 3; ++a) {
    n_[a] = static_cast<int>(n[a]);
    cap_lo_[a] = -(n_[a] + margin_);
    cap_dims_[a] = 2 * (n_[a] + margin_);
  }
  lo_ = cap_lo_;
  dims_ = cap_dims_;
  if (axis >= 0) {
    dims_[axis] = n_[axis] + 2 * margin_;
    lo_[axis] = sign > 0 ? -margin_ : -n_[axis] - margin_;
  }

  const Body& hb = w.bodies[host_];
  const int listed = host_nodes_ == HostNodes::surface ? hb.n_surface : hb.size();
  grid.allocate(static_cast<long long>(alloc_count), listed);
}

GridGeometry Initializer::update(const World& w, VoxelData& grid) {
  Vec3 lo, hi;
  body_bounds(w, host_, lo, hi);
  const Vec3 c = 0.5 * (lo + hi);
  const Vec3 h = 0.5 * (hi - lo);
  center_ = c;
  host_lo_ = lo;
  host_hi_ = hi;

  GridGeometry g;
  g.voxel = voxel_;
  g.center = c;
  if (!all_finite(c) || !all_finite(h)) return g;  // dims 0: nothing is found this step

  if ((h.array() > built_h_.array() + voxel_).any()) {
    build(w, h, c, false, grid);
    ++rebuilds_;
  }

  if (region_ != Region::overlap) {
    g.lo = lo_;
    g.dims = dims_;
    return g;
  }

  Vec3 glo, ghi;
  body_bounds(w, guest_, glo, ghi);
  const double inv_v = 1.0 / voxel_;
  const double m = margin_;
  for (int a = 0; a < 3; ++a) {
    double a0 = std::max(std::floor((lo[a] - c[a]) * inv_v), std::floor((glo[a] - c[a]) * inv_v)) - m;
    double a1 = std::min(std::floor((hi[a] - c[a]) * inv_v), std::floor((ghi[a] - c[a]) * inv_v)) + m;
    a0 = std::max(a0, static_cast<double>(cap_lo_[a]));
    a1 = std::min(a1, static_cast<double>(cap_lo_[a] + cap_dims_[a] - 1));
    if (!(a1 >= a0)) {  // disjoint (or NaN): an empty region
      g.lo = Vec3i::Zero();
      g.dims = Vec3i::Zero();
      return g;
    }
    g.lo[a] = static_cast<int>(a0);
    g.dims[a] = static_cast<int>(a1 - a0) + 1;
  }
  return g;
}

}  // namespace harness
