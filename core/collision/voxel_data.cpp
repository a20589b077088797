#include "core/collision/voxel_data.hpp"

#include "core/parallel.hpp"
#include "core/simd/kernels.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
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

// The kernels take points as three doubles each.
static_assert(sizeof(Vec3) == 3 * sizeof(double), "Vec3 is three packed doubles");

void VoxelIndexer::operator()(const Vec3* p, std::size_t n, int* out) const {
  if (n == 0) return;
  simd::VoxelGrid g;
  for (int a = 0; a < 3; ++a) g.c[a] = c_[a], g.lo[a] = lo_[a], g.hi[a] = hi_[a];
  g.inv = inv_;
  g.dx = dx_, g.dxy = dxy_;
  simd::kernels().voxel_cells(g, p->data(), n, out);
}

long long VoxelData::bytes() const {
  return static_cast<long long>((head_.capacity() + next_.capacity() + node_cell_.capacity() +
                                 chunk_lo_.capacity() + chunk_hi_.capacity()) * sizeof(int));
}

void VoxelData::allocate(long long max_voxels, int max_nodes) {
  listed_ = 0;
  opened_ = 0;
  count_ = 0;
  head_.assign(static_cast<std::size_t>(max_voxels), -1);
  next_.assign(static_cast<std::size_t>(max_nodes), -1);
  node_cell_.assign(static_cast<std::size_t>(max_nodes), -1);
  const std::size_t chunks = (static_cast<std::size_t>(max_nodes) + kChunk - 1) / kChunk;
  chunk_lo_.assign(chunks, ~0u);
  chunk_hi_.assign(chunks, -1);
}

void VoxelData::fill(const GridGeometry& g, const Points& x, int node_begin, int node_end) {
  prepare(g, x, node_begin, node_end);
  link();
}

void VoxelData::clear() {
  // Every slot the last fill can have set holds a voxel of its layout (geom_) that one of its
  // nodes lies in: all slots of that layout when they are few against the nodes (one sequential
  // pass), else the nodes' own voxels (one pass over the nodes, O(nodes) however sparse).
  const std::size_t n = static_cast<std::size_t>(count_);
  if (n == 0) return;
  const long long nv = geom_.num_voxels();
  if (nv <= 8 * static_cast<long long>(n)) {
    const std::size_t V = static_cast<std::size_t>(nv);
    const int T = threads_for(V, 65536);
#pragma omp parallel for num_threads(T) if(T > 1) schedule(static, 1)
    for (int t = 0; t < T; ++t) {
      std::size_t b, e;
      split_range(V, T, t, b, e);
      std::fill(head_.begin() + static_cast<std::ptrdiff_t>(b), head_.begin() + static_cast<std::ptrdiff_t>(e), -1);
    }
  } else {
    const int T = threads_for(n, 32768);
    const int* cell = node_cell_.data();
    // Several threads may clear one voxel, always to the same value: relaxed atomic stores.
#pragma omp parallel for num_threads(T) if(T > 1) schedule(static)
    for (std::size_t k = 0; k < n; ++k) {
      const int c = cell[k];
      if (c < 0) continue;
      __atomic_store_n(head_.data() + c, -1, __ATOMIC_RELAXED);
    }
  }
  count_ = 0;
  listed_ = 0;
  opened_ = 0;
}

void VoxelData::prepare(const GridGeometry& g, const Points& x, int node_begin, int node_end) {
  if (g.num_voxels() > capacity() || node_end - node_begin > static_cast<int>(next_.size()))
    throw std::logic_error("VoxelData::fill: grid exceeds the allocated capacity");
  clear();
  geom_ = g;
  base_ = node_begin;
  count_ = node_end - node_begin;
  const VoxelIndexer idx(g);
  const std::size_t n = static_cast<std::size_t>(count_);
  const int T = g.num_voxels() > 0 ? threads_for(n, 16384) : 1;
  const int K = static_cast<int>((n + kChunk - 1) / kChunk);
  int* cell = node_cell_.data();
  const simd::Kernels& kern = simd::kernels();
  // Chunks handed out dynamically: a thread the system deschedules delays one small chunk.
#pragma omp parallel for num_threads(T) if(T > 1) schedule(dynamic, 4)
  for (int c = 0; c < K; ++c) {
    const std::size_t b = static_cast<std::size_t>(c) * kChunk, e = std::min(n, b + kChunk);
    idx(x.data() + node_begin + b, e - b, cell + b);
    // The chunk's smallest and largest voxel (as unsigned, -1 is the largest: never the
    // smallest unless every node of the chunk is outside), for link_part to skip the chunk.
    kern.cell_range(cell + b, e - b, chunk_lo_[static_cast<std::size_t>(c)], chunk_hi_[static_cast<std::size_t>(c)]);
  }
}

int VoxelData::link_parts() const {
  // Each part reads every node's voxel once: worth it only for many nodes.
  return geom_.num_voxels() > 0 ? std::min(kMaxLinkParts, threads_for(static_cast<std::size_t>(count_), 65536))
                                : 1;
}

void VoxelData::link_part(int part, int parts) {
  // Part p owns the voxels [p V / parts, (p + 1) V / parts) and visits the nodes in decreasing
  // order: pushing onto the front leaves each list in increasing order, whatever `parts` is.
  // Chunks of nodes (prepare) with no voxel of the part are skipped: nodes outside the region,
  // and, when nearby nodes have nearby indices (lattices, layered meshes), the other parts'.
  // (A single backward pass computing the voxels too was twice as slow at 10^6 nodes: backward
  // streams over x defeat the prefetcher; node_cell_ is 4 bytes a node.)
  std::size_t vb, ve;
  split_range(static_cast<std::size_t>(geom_.num_voxels()), parts, part, vb, ve);
  const unsigned lo = static_cast<unsigned>(vb), len = static_cast<unsigned>(ve - vb);
  const int* cell = node_cell_.data();
  int* head = head_.data();
  int* next = next_.data();
  int listed = 0, opened = 0;
  const int K = static_cast<int>((static_cast<std::size_t>(count_) + kChunk - 1) / kChunk);
  for (int c = K - 1; c >= 0; --c) {
    const std::size_t ci = static_cast<std::size_t>(c);
    if (chunk_hi_[ci] < 0 || chunk_lo_[ci] >= ve || static_cast<std::size_t>(chunk_hi_[ci]) < vb) continue;
    const int b = c * static_cast<int>(kChunk);
    for (int k = std::min(count_, b + static_cast<int>(kChunk)) - 1; k >= b; --k) {
      const int v = cell[k];
      if (static_cast<unsigned>(v) - lo >= len) continue;  // -1 (outside the grid) too
      const int h = head[v];
      opened += h < 0;
      next[k] = h;
      head[v] = k;
      ++listed;
    }
  }
  part_listed_[part] = listed;
  part_opened_[part] = opened;
}

void VoxelData::link_done(int parts) {
  listed_ = opened_ = 0;
  for (int p = 0; p < parts; ++p) {
    listed_ += part_listed_[p];
    opened_ += part_opened_[p];
  }
}

void VoxelData::link() {
  const int P = link_parts();
#pragma omp parallel for num_threads(P) if(P > 1) schedule(static, 1)
  for (int p = 0; p < P; ++p) link_part(p, P);
  link_done(P);
}

}  // namespace harness
