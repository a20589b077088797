// VoxelData: the paper's voxel grid of one contact pair, holding in each voxel the list of the
// host body's node indices that lie in it.
//
// Geometry (all lengths in m). The grid is attached to the host: its origin is the host's
// current bounding-box centre c = 0.5 * (lo + hi) (componentwise, exactly this expression).
// The voxel edge v is a power of two, so multiplying by 1/v is exact and the index of a point
// x along one axis is the paper's formula
//     i = floor((x - c) / v) - lo,
// where `lo` is the first cell of the region counted from c (cell k covers
// [c + k v, c + (k + 1) v), so a point exactly on a face belongs to the cell above it).
// Points with i outside [0, dims) on any axis are rejected, and so are non-finite or huge
// coordinates: the range test is done in double before any float->int conversion.
// Linear voxel index: ix + dims.x * (iy + dims.y * iz).
//
// Storage (rebuilt every step, no heap allocation after allocate()): a counting sort of the
// host nodes by voxel into one index array. Per voxel a {first, count} record (8 bytes, so one
// cache line answers "is it occupied, where are its nodes"); only the voxels that were occupied
// in the last fill are listed and cleared again, so a fill costs O(host nodes), not O(voxels),
// and huge sparse grids (small voxels) stay cheap per step. Within a voxel the nodes appear in
// increasing index order.
#pragma once

#include "core/types.hpp"

#include <cstddef>
#include <vector>

namespace harness {

// Largest power of two <= v (exact: frexp/ldexp). Throws std::invalid_argument unless v is
// finite and > 0.
double round_down_pow2(double v);

// Where the grid lies in one step.
struct GridGeometry {
  double voxel = 0.0;             // edge length v, m, a power of two
  Vec3 center = Vec3::Zero();     // c: the host's bounding-box centre, m
  Vec3i lo = Vec3i::Zero();       // first cell of the region, counted from c (may be negative)
  Vec3i dims = Vec3i::Zero();     // cells per axis (0 on some axis = empty region)

  long long num_voxels() const {
    return static_cast<long long>(dims.x()) * dims.y() * dims.z();
  }
};

// Linear index of the voxel that holds p, or -1 when p is outside the region (or not finite).
// `ijk`, when given, receives the per-axis indices of an accepted point.
int voxel_of(const GridGeometry& g, const Vec3& p, Vec3i* ijk = nullptr);
// Per-axis indices of a linear voxel index.
Vec3i voxel_ijk(const GridGeometry& g, int cell);

class VoxelData {
 public:
  // Node range of one voxel: pointers into the index array, [begin, end).
  struct Span {
    const int* b = nullptr;
    const int* e = nullptr;
    const int* begin() const { return b; }
    const int* end() const { return e; }
    int size() const { return static_cast<int>(e - b); }
  };

  // Reserves room for grids of up to `max_voxels` voxels and `max_nodes` listed nodes. The only
  // place that allocates; called at initialisation and when the region is rebuilt.
  void allocate(long long max_voxels, int max_nodes);

  // Lists the nodes [node_begin, node_end) of x in the voxels of g (count, prefix sum over the
  // occupied voxels, scatter). Nodes outside g are left out. g.num_voxels() must not exceed the
  // allocated capacity, nor node_end - node_begin the allocated node count.
  void fill(const GridGeometry& g, const Points& x, int node_begin, int node_end);

  const GridGeometry& geometry() const { return geom_; }
  long long capacity() const { return static_cast<long long>(cells_.size()); }
  bool occupied(int cell) const { return cells_[cell].count > 0; }
  Span nodes(int cell) const {
    const Cell& c = cells_[cell];
    return {index_.data() + c.first, index_.data() + c.first + c.count};
  }
  // Linear indices of the non-empty voxels, in order of first appearance in the fill.
  const std::vector<int>& occupied_voxels() const { return occupied_; }
  // Nodes listed in the last fill (those inside the region).
  int listed_nodes() const { return listed_; }

 private:
  struct Cell {
    int first = 0;  // offset into index_ (valid when count > 0)
    int count = 0;
  };
  GridGeometry geom_;
  std::vector<Cell> cells_;     // one per voxel of the capacity; all zero except occupied_
  std::vector<int> index_;      // node indices grouped by voxel
  std::vector<int> node_cell_;  // voxel of each node of the range in the last fill, -1 = outside
  std::vector<int> occupied_;   // voxels with count > 0
  int listed_ = 0;
};

}  // namespace harness
