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
// Storage (rebuilt every step, no heap allocation after allocate()): per voxel the head of a
// linked list of the host nodes in it (4 bytes per voxel), threaded through a per-node `next`
// array. A fill computes every node's voxel (vectorised, VoxelIndexer) and pushes the nodes onto
// their lists in decreasing index order, so each list comes out in increasing index order. A
// fill empties only what the last one set: the voxels of its nodes (O(nodes), so huge sparse
// grids of small voxels stay cheap per step), or the whole last layout when that is no larger
// than a few slots per node (one sequential pass).
//
// With threads (core/parallel.hpp) the voxels are computed in parallel chunks of nodes and the
// lists are linked in parallel parts, each part owning a range of voxels and visiting the nodes
// in decreasing order (skipping chunks of nodes with no voxel in its range), so each list is
// built by one thread exactly as with one thread. The lists never depend on the thread count.
#pragma once

#include "core/types.hpp"

#include <cstddef>
#include <cstdint>
#include <iterator>
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

// voxel_of for many points of one grid: the same result, faster. The range test is done on
// t = (x - c) / v in double (floor(t) >= lo exactly when t >= lo, and floor(t) < lo + dims
// exactly when t < lo + dims, the bounds being integers), which also rejects NaN; floor is then
// taken by truncation with a correction, valid because t is known to lie in int range. No libm
// call (without SSE4.1, std::floor is one) and one branch per point.
class VoxelIndexer {
 public:
  explicit VoxelIndexer(const GridGeometry& g) {
    inv_ = 1.0 / g.voxel;
    for (int a = 0; a < 3; ++a) {
      c_[a] = g.center[a];
      ilo_[a] = g.lo[a];
      lo_[a] = g.lo[a];
      hi_[a] = static_cast<double>(g.lo[a]) + g.dims[a];
    }
    dx_ = g.dims.x();
    dxy_ = g.dims.x() * g.dims.y();
  }
  int operator()(const Vec3& p) const {
    const double t0 = (p[0] - c_[0]) * inv_, t1 = (p[1] - c_[1]) * inv_, t2 = (p[2] - c_[2]) * inv_;
    // Non-short-circuit: one well-predicted branch instead of six.
    const bool in = (t0 >= lo_[0]) & (t0 < hi_[0]) & (t1 >= lo_[1]) & (t1 < hi_[1]) &
                    (t2 >= lo_[2]) & (t2 < hi_[2]);
    if (!in) return -1;
    return (ifloor(t0) - ilo_[0]) + dx_ * (ifloor(t1) - ilo_[1]) + dxy_ * (ifloor(t2) - ilo_[2]);
  }
  // out[k] = (*this)(p[k]) for k < n, several points at a time by the SIMD kernel of the active
  // instruction set (core/simd/kernels.hpp: the same operations, floor(t) - lo and the index
  // formed exactly in double, so the same results).
  void operator()(const Vec3* p, std::size_t n, int* out) const;

 private:
  static int ifloor(double t) {
    const int i = static_cast<int>(t);  // truncation toward zero
    return i - (t < i);
  }
  double c_[3], lo_[3], hi_[3], inv_;
  int ilo_[3], dx_, dxy_;
};

class VoxelData {
 public:
  // The nodes of one voxel, in increasing index order: a singly linked list threaded through
  // the listed nodes (next_), so a fill is one pass that pushes each node onto its voxel's
  // list (nodes visited in decreasing order), with no counting, prefix sum or scatter.
  class NodeList {
   public:
    class iterator {
     public:
      using iterator_category = std::forward_iterator_tag;
      using value_type = int;
      using difference_type = std::ptrdiff_t;
      using pointer = const int*;
      using reference = int;
      iterator() = default;
      iterator(const int* next, int base, int k) : next_(next), base_(base), k_(k) {}
      int operator*() const { return base_ + k_; }
      iterator& operator++() {
        k_ = next_[k_];
        return *this;
      }
      iterator operator++(int) {
        iterator t = *this;
        ++*this;
        return t;
      }
      bool operator==(const iterator& o) const { return k_ == o.k_; }
      bool operator!=(const iterator& o) const { return k_ != o.k_; }

     private:
      const int* next_ = nullptr;
      int base_ = 0, k_ = -1;
    };
    NodeList(const int* next, int base, int first) : next_(next), base_(base), first_(first) {}
    iterator begin() const { return iterator(next_, base_, first_); }
    iterator end() const { return iterator(next_, base_, -1); }
    int size() const {
      int n = 0;
      for (int k = first_; k >= 0; k = next_[k]) ++n;
      return n;
    }

   private:
    const int* next_;
    int base_, first_;
  };

  // Reserves room for grids of up to `max_voxels` voxels and `max_nodes` listed nodes. The only
  // place that allocates; called at initialisation and when the region is rebuilt.
  void allocate(long long max_voxels, int max_nodes);

  // Lists the nodes [node_begin, node_end) of x in the voxels of g. Nodes outside g are left
  // out. g.num_voxels() must not exceed the allocated capacity, nor node_end - node_begin the
  // allocated node count. The same as prepare() then link().
  void fill(const GridGeometry& g, const Points& x, int node_begin, int node_end);
  // The two halves of fill(): prepare() empties the last fill's voxels and computes every
  // node's voxel (in parallel chunks); link() then builds the lists (in parallel parts, each
  // owning a range of voxels).
  void prepare(const GridGeometry& g, const Points& x, int node_begin, int node_end);
  void link();

  const GridGeometry& geometry() const { return geom_; }
  long long capacity() const { return static_cast<long long>(head_.size()); }
  // Memory the grid holds (capacity of every array), bytes.
  long long bytes() const;
  bool occupied(int cell) const { return head_[cell] >= 0; }
  NodeList nodes(int cell) const { return NodeList(next_.data(), base_, head_[cell]); }
  // Non-empty voxels and nodes listed (those inside the region) in the last fill.
  int occupied_count() const { return opened_; }
  int listed_nodes() const { return listed_; }

 private:
  static constexpr int kMaxLinkParts = 64;
  static constexpr std::size_t kChunk = 4096;  // nodes per chunk of prepare()
  void clear();  // empties every voxel the last fill set
  int link_parts() const;
  void link_part(int part, int parts);  // concurrently for every part < parts, then link_done
  void link_done(int parts);

  GridGeometry geom_;
  int base_ = 0;                // node_begin of the last fill: list entries are node - base_
  int count_ = 0;               // node_end - node_begin of the last prepare()
  std::vector<int> head_;       // per voxel of the capacity: first node (local index), -1 empty
  std::vector<int> next_;       // per listed node: the next node of its voxel, -1 = last
  std::vector<int> node_cell_;  // voxel of each node of the range in the last fill, -1 = outside
  std::vector<unsigned> chunk_lo_;  // per chunk of kChunk nodes: smallest voxel (~0u: none)
  std::vector<int> chunk_hi_;       // per chunk: largest voxel (-1: none)
  int listed_ = 0, opened_ = 0;
  int part_listed_[kMaxLinkParts] = {}, part_opened_[kMaxLinkParts] = {};
};

}  // namespace harness
