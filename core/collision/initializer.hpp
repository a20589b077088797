// Initializer: the paper's builder of the voxel model of one contact pair. It chooses the
// voxel size and the region, allocates the VoxelData, and every step re-attaches the grid to
// the host body (re-centres it on the host's bounding-box centre, so it moves with the host)
// and rebuilds the region when the host has outgrown it.
//
// Notation (per axis, m): the host's current bounding box [lo_h, hi_h], centre
// c = 0.5 * (lo_h + hi_h), half extents h = 0.5 * (hi_h - lo_h); likewise the guest's box
// [lo_g, hi_g] and centre c_g. H are the host half extents the region was built for, v the
// voxel edge, m the margin in voxels. Cells are counted from c (see voxel_data.hpp).
//
// Regions:
//   n     = floor(H / v) + 2 per axis: the fewest cells with n v > H + v, so the host may grow
//           by up to one voxel per side (relative to its centre) before anything falls out.
//   full    cells [-n - m, n + m) on every axis.
//   half    the paper's: the half of the host's box that faces the guest. Axis a maximises
//           |c_g - c|_a / H_a (H_a = 0 counts as infinitely thin: any offset wins; ties go to
//           the first axis), sign s = sign((c_g - c)_a) (0 counts as +). Along a the cells are
//           [-m, n + m) for s = + and [-n - m, m) for s = -; the other axes as in full. The
//           choice is made when the region is built (initialisation and rebuilds). When the
//           guest's centre coincides with the host's, no half faces it and the region is full.
//   overlap recomputed every step inside the capacity of `full`: the cells both current
//           boxes touch, [max(floor((lo_h - c)/v), floor((lo_g - c)/v)),
//           min(floor((hi_h - c)/v), floor((hi_g - c)/v))] per axis, widened by m, clipped to
//           full. A voxel that holds a host and a guest node is touched by both boxes, so with
//           any margin this finds exactly the contacts of `full`. Disjoint ranges = no voxels.
//
// Rebuild: when on some axis h > H + v (an expanding implant), H := h and the region is built
// again (half re-chooses its side); rebuilds() counts these. Non-finite host positions never
// trigger a rebuild (that step simply finds no contacts; the run reports the bad state).
//
// Voxel size: ContactSpec::voxel_size rounded down to a power of two. voxel_size == 0 means
// automatic: the smallest power of two >= the host's mean surface edge at rest
// (host_node_spacing; for a host without a surface its rest_spring_length, world.hpp). Capacity cap: a region of more than
// kMaxVoxels voxels throws std::invalid_argument at initialisation (the scene loader reports
// it) and std::runtime_error when a rebuild during the run would need it.
#pragma once

#include "core/scene/contact_spec.hpp"
#include "core/collision/voxel_data.hpp"
#include "core/world.hpp"

namespace harness {

constexpr long long kMaxVoxels = 64LL * 1000 * 1000;

// Voxel size the pair uses (m, a power of two), as documented above. Throws
// std::invalid_argument for a bad request or when no automatic size can be chosen.
double resolve_voxel_size(const World& w, const ContactSpec& spec);
// The spacing of a host's nodes that a voxel must not be below: its mean surface edge at rest,
// or rest_spring_length for a body without a surface (world.hpp). The automatic voxel size is the smallest power
// of two at or above it; a run warns about a paper's grid finer than it.
double host_node_spacing(const World& w, int host);

class Initializer {
 public:
  // Builds the grid for the pair at the current positions and allocates `grid`; keeps of the
  // spec the bodies, the region, the margin and which host nodes are listed. Throws
  // std::invalid_argument for a negative margin or a region above kMaxVoxels (the bodies are
  // checked by check_pair, collision.hpp).
  void initialize(const World& w, const ContactSpec& spec, VoxelData& grid);
  // This step's grid geometry: re-centred on the host, rebuilt if the host outgrew the region,
  // overlap recomputed. May reallocate `grid` on a rebuild (and only then).
  GridGeometry update(const World& w, VoxelData& grid);

  double voxel_size() const { return voxel_; }
  int rebuilds() const { return rebuilds_; }
  Region region() const { return region_; }
  // Half extents the region was built for (H), m.
  const Vec3& built_half_extents() const { return built_h_; }
  // For region half: the axis (0..2) and side (+1 / -1) chosen; axis -1 when the region is full.
  int half_axis() const { return half_axis_; }
  int half_sign() const { return half_sign_; }
  // Host bounding box centre found by the last update(), m.
  const Vec3& host_center() const { return center_; }
  // Host bounding box found by the last update() (or initialize()), m.
  const Vec3& host_lo() const { return host_lo_; }
  const Vec3& host_hi() const { return host_hi_; }

 private:
  void build(const World& w, const Vec3& host_half, const Vec3& host_center, bool initial,
             VoxelData& grid);
  Vec3 guest_center(const World& w) const;

  int host_ = -1, guest_ = -1;
  Region region_ = Region::half;
  int margin_ = 1;  // voxels
  HostNodes host_nodes_ = HostNodes::all;
  double voxel_ = 0.0;
  int rebuilds_ = 0;
  Vec3 built_h_ = Vec3::Zero();
  Vec3 center_ = Vec3::Zero();
  Vec3 host_lo_ = Vec3::Zero(), host_hi_ = Vec3::Zero();
  Vec3i n_ = Vec3i::Zero();        // cells per side, floor(H / v) + 2
  Vec3i cap_lo_ = Vec3i::Zero();   // the full region (capacity) ...
  Vec3i cap_dims_ = Vec3i::Zero();
  Vec3i lo_ = Vec3i::Zero();       // ... and the built region (half / full)
  Vec3i dims_ = Vec3i::Zero();
  int half_axis_ = -1;
  int half_sign_ = 1;
};

}  // namespace harness
