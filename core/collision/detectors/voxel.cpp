#include "core/collision/detectors/voxel.hpp"

#include "core/parallel.hpp"
#include "core/device/contact_kernels.hpp"

#include <algorithm>

namespace harness {

void VoxelDetector::initialize(const World& w, const ContactSpec& spec) {
  init_.initialize(w, spec, grid_);
  guest_ = spec.guest;
  const Body& hb = w.bodies[spec.host];
  fill_begin_ = hb.begin;
  fill_end_ = spec.host_nodes == HostNodes::surface ? hb.begin + hb.n_surface : hb.end;
}

// Calls emit(node, voxel) for every node of [begin, end) whose voxel is occupied (`occupied`),
// in node order; voxels are computed in batches (VoxelIndexer, vectorised) on the stack.
template <class Emit, class Occupied>
void VoxelDetector::lookup(const VoxelIndexer& idx, const Points& x, int begin, int end, Emit&& emit,
                           Occupied&& occupied) const {
  constexpr int kBatch = 256;
  int cells[kBatch];
  for (int b = begin; b < end; b += kBatch) {
    const int m = std::min(kBatch, end - b);
    idx(x.data() + b, static_cast<std::size_t>(m), cells);
    for (int k = 0; k < m; ++k)
      if (cells[k] >= 0 && occupied(cells[k])) emit(b + k, cells[k]);
  }
}

void VoxelDetector::detect(const World& w, std::vector<Contact>& out) {
  out.clear();
  const GridGeometry g = init_.update(w, grid_);
  const Body& gb = w.bodies[guest_];
  const VoxelIndexer idx(g);
  grid_.fill(g, w.x, fill_begin_, fill_end_);  // in parallel parts when the grid is large
  if (grid_.listed_nodes() == 0) return;
  const std::size_t n = static_cast<std::size_t>(gb.size());
  const int T = threads_for(n, 16384);
  auto occupied = [&](int cell) { return grid_.occupied(cell); };
  if (T == 1) {
    lookup(idx, w.x, gb.begin, gb.end, [&](int i, int cell) { out.push_back(Contact{i, cell}); }, occupied);
    return;
  }
  // Parallel lookup: each chunk writes its contacts into its own part of the scratch list; the
  // parts are then appended in chunk order, so the contacts are those of one thread, in guest
  // node order. Chunks are handed out dynamically, several per thread, so that a thread the
  // system deschedules delays one small chunk.
  if (scratch_.size() < n) scratch_.resize(n);  // once, on the first parallel detection
  const int L = std::min(64, 4 * T);
  int found[64] = {};
#pragma omp parallel for num_threads(T) if(T > 1) schedule(dynamic, 1)
  for (int c = 0; c < L; ++c) {
    std::size_t b, e;
    split_range(n, L, c, b, e);
    Contact* dst = scratch_.data() + b;
    int m = 0;
    lookup(idx, w.x, gb.begin + static_cast<int>(b), gb.begin + static_cast<int>(e),
           [&](int i, int cell) { dst[m++] = Contact{i, cell}; }, occupied);
    found[c] = m;
  }
  for (int c = 0; c < L; ++c) {
    std::size_t b, e;
    split_range(n, L, c, b, e);
    out.insert(out.end(), scratch_.begin() + static_cast<std::ptrdiff_t>(b),
               scratch_.begin() + static_cast<std::ptrdiff_t>(b) + found[c]);
  }
}

namespace {

// Keeps out[0..n) sorted by (distance, index), at most k entries. k is small (1 or 3 in the
// eliminators), so insertion with recomputed distances beats any heap structure.
inline void offer(const World& w, const Vec3& p, int node, int k, int* out, int& n) {
  const double d = (w.x[node] - p).squaredNorm();
  auto before = [&](int other) {
    const double e = (w.x[other] - p).squaredNorm();
    return d < e || (d == e && node < other);
  };
  if (n == k && !before(out[n - 1])) return;
  int j = n < k ? n++ : k - 1;
  while (j > 0 && before(out[j - 1])) {
    out[j] = out[j - 1];
    --j;
  }
  out[j] = node;
}

}  // namespace

int VoxelDetector::nearest_hosts(const World& w, const Contact& c, int k, int* out) const {
  if (k <= 0 || c.key < 0 || c.key >= grid_.geometry().num_voxels()) return 0;
  const Vec3& p = w.x[c.guest];
  int n = 0;
  if (k == 1) {  // offer's rule with the best distance kept (each node's distance computed once)
    int best = -1;
    double e = 0.0;
    for (int node : grid_.nodes(c.key)) {
      const double d = (w.x[node] - p).squaredNorm();
      if (best < 0 || d < e || (d == e && node < best)) best = node, e = d;
    }
    if (best < 0) return 0;
    out[0] = best;
    return 1;
  }
  const GridGeometry& g = grid_.geometry();
  const Vec3i ijk = voxel_ijk(g, c.key);
  for (int dz = -1; dz <= 1; ++dz) {
    const int z = ijk.z() + dz;
    if (z < 0 || z >= g.dims.z()) continue;
    for (int dy = -1; dy <= 1; ++dy) {
      const int y = ijk.y() + dy;
      if (y < 0 || y >= g.dims.y()) continue;
      for (int dx = -1; dx <= 1; ++dx) {
        const int x = ijk.x() + dx;
        if (x < 0 || x >= g.dims.x()) continue;
        const int cell = x + g.dims.x() * (y + g.dims.y() * z);
        if (!grid_.occupied(cell)) continue;
        for (int node : grid_.nodes(cell)) offer(w, p, node, k, out, n);
      }
    }
  }
  return n;
}

HARNESS_DETECTOR(voxel) {
  DetectorDef d;
  d.name = "voxel";
  d.doc = "the paper's local grid: power-of-two voxels over the area of interest, attached to the host and moving with its bounding-box centre, each a list of the host's nodes; a guest node in a voxel that lists any is in contact";
  d.make = [] { return std::unique_ptr<CollisionDetector>(std::make_unique<VoxelDetector>()); };
  d.device = dev::kDetVoxel;
  return d;
}

}  // namespace harness
