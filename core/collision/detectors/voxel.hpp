// VoxelDetector: the paper's collision detection (name "voxel"). Each step:
//   1. the Initializer re-attaches the grid to the host (initializer.hpp);
//   2. the voxel lists are filled with the host's nodes: all of them (host_nodes == all) or
//      only its surface vertices, body-local 0..n_surface-1 (host_nodes == surface);
//   3. every guest node is looked up; a guest node whose voxel is non-empty is a contact,
//      Contact{guest = its global index, key = the linear voxel index}, in guest node order.
// Contact keys refer to this step's grid (region overlap changes its layout every step), so
// nearest_hosts() must be called after the detect() that produced the contact.
// No heap allocation per step after initialize(), except when the host outgrows the region
// (a rebuild) and once when the thread count is first raised; `out` must have capacity for
// every guest node to avoid growing it. With several threads (core/parallel.hpp) the grid is
// filled in parallel (VoxelData), then the guest nodes are looked up in chunks whose contacts
// are appended in chunk order: the contacts are the same, in the same order, for any thread
// count.
#pragma once

#include "core/collision/detectors/collision_detector.hpp"
#include "core/collision/initializer.hpp"
#include "core/collision/voxel_data.hpp"

namespace harness {

class VoxelDetector final : public CollisionDetector {
 public:
  const char* name() const override { return "voxel"; }
  void initialize(const World& w, const ContactSpec& spec) override;
  void detect(const World& w, std::vector<Contact>& out) override;
  // k == 1: the nearest host node in the contact's voxel. k > 1: the k nearest host nodes in the
  // voxel and its 26 neighbours (those inside the grid). Nearest first; equal distances are
  // ordered by node index. Returns how many were written (< k when fewer exist).
  int nearest_hosts(const World& w, const Contact& c, int k, int* out) const override;
  double voxel_size() const override { return init_.voxel_size(); }
  int rebuilds() const override { return init_.rebuilds(); }
  bool region(Vec3& lo, Vec3& hi) const override {
    const GridGeometry& g = grid_.geometry();
    if (g.num_voxels() <= 0) return false;
    lo = g.center + g.voxel * g.lo.cast<double>();
    hi = lo + g.voxel * g.dims.cast<double>();
    return true;
  }

  const VoxelData& grid() const { return grid_; }
  const Initializer& initializer() const { return init_; }

 private:
  template <class Emit, class Occupied>
  void lookup(const VoxelIndexer& idx, const Points& x, int begin, int end, Emit&& emit, Occupied&& occupied) const;

  Initializer init_;
  VoxelData grid_;
  int guest_ = -1;                     // the guest body
  int fill_begin_ = 0, fill_end_ = 0;  // global host node range listed in the voxels
  std::vector<Contact> scratch_;       // parallel lookup: per-chunk contacts (guest size)
};

}  // namespace harness
