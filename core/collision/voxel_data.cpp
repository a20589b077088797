#include "core/collision/voxel_data.hpp"

#include <cmath>
#include <stdexcept>
#include <string>

namespace harness {

double round_down_pow2(double v) {
  if (!(v > 0.0) || !std::isfinite(v))
    throw std::invalid_argument("voxel size must be finite and > 0, got " + std::to_string(v));
  int e = 0;
  std::frexp(v, &e);  // v = m 2^e with m in [0.5, 1)
  return std::ldexp(1.0, e - 1);
}

int voxel_of(const GridGeometry& g, const Vec3& p, Vec3i* ijk) {
  // 1/v is a power of two: the product equals the quotient (x - c)/v exactly.
  const double inv_v = 1.0 / g.voxel;
  int idx[3];
  for (int a = 0; a < 3; ++a) {
    const double t = std::floor((p[a] - g.center[a]) * inv_v);
    const double lo = g.lo[a];
    // Compared in double: NaN and huge values fail here, so the cast below is always defined.
    if (!(t >= lo && t < lo + g.dims[a])) return -1;
    idx[a] = static_cast<int>(t - lo);
  }
  if (ijk) *ijk = Vec3i(idx[0], idx[1], idx[2]);
  return idx[0] + g.dims.x() * (idx[1] + g.dims.y() * idx[2]);
}

Vec3i voxel_ijk(const GridGeometry& g, int cell) {
  const int ix = cell % g.dims.x();
  const int r = cell / g.dims.x();
  return Vec3i(ix, r % g.dims.y(), r / g.dims.y());
}

void VoxelData::allocate(long long max_voxels, int max_nodes) {
  // Drop the old lists first: the layout is about to change.
  for (int c : occupied_) cells_[c] = Cell{};
  occupied_.clear();
  listed_ = 0;
  cells_.assign(static_cast<std::size_t>(max_voxels), Cell{});
  index_.assign(static_cast<std::size_t>(max_nodes), 0);
  node_cell_.assign(static_cast<std::size_t>(max_nodes), -1);
  // Every listed node can open at most one voxel.
  occupied_.reserve(static_cast<std::size_t>(max_nodes));
}

void VoxelData::fill(const GridGeometry& g, const Points& x, int node_begin, int node_end) {
  if (g.num_voxels() > capacity() || node_end - node_begin > static_cast<int>(index_.size()))
    throw std::logic_error("VoxelData::fill: grid exceeds the allocated capacity");
  // Clear by the previous occupancy list: slots are linear indices, valid whatever the layout.
  for (int c : occupied_) cells_[c] = Cell{};
  occupied_.clear();
  geom_ = g;

  // Count.
  const int n = node_end - node_begin;
  for (int k = 0; k < n; ++k) {
    const int c = voxel_of(g, x[node_begin + k]);
    node_cell_[k] = c;
    if (c < 0) continue;
    if (cells_[c].count++ == 0) occupied_.push_back(c);  // within reserved capacity
  }
  // Prefix sum over the occupied voxels only; `first` then serves as the scatter cursor.
  int offset = 0;
  for (int c : occupied_) {
    cells_[c].first = offset;
    offset += cells_[c].count;
  }
  listed_ = offset;
  // Scatter in node order, so each voxel's list is sorted by node index.
  for (int k = 0; k < n; ++k) {
    const int c = node_cell_[k];
    if (c >= 0) index_[cells_[c].first++] = node_begin + k;
  }
  // Restore `first` (the cursor ended one past the voxel's last node).
  for (int c : occupied_) cells_[c].first -= cells_[c].count;
}

}  // namespace harness
