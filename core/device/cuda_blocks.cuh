// The CUDA executor's own kernels (cuda_step.cu): the one-block phases of a small contact pair
// (boxes, grids and lists; reactions), voxel_exact's search one warp per guest node, and the last
// kernel of a step (the pushes applied, the nodes integrated, the step's index advanced).
// Included by cuda_step.cu alone.
#pragma once

#include "core/device/plan_data.hpp"

namespace harness::dev {
namespace {

constexpr int kBlock = 512;  // the one-block kernels' threads

// out[0..n) = exclusive prefix sums of in[0..n), by one block (contiguous chunks per thread).
__device__ void block_scan(const int* in, int* out, int n) {
  __shared__ int sums[kBlock];
  const int T = blockDim.x, t = threadIdx.x;
  const int chunk = (n + T - 1) / T, b = min(n, t * chunk), e = min(n, b + chunk);
  int s = 0;
  for (int k = b; k < e; ++k) s += in[k];
  sums[t] = s;
  __syncthreads();
  for (int off = 1; off < T; off *= 2) {
    const int v = t >= off ? sums[t - off] : 0;
    __syncthreads();
    sums[t] += v;
    __syncthreads();
  }
  int run = t ? sums[t - 1] : 0;
  for (int k = b; k < e; ++k) {
    const int c = in[k];
    out[k] = run;
    run += c;
  }
  __syncthreads();
}

// The box of x[begin, end) by one block: every thread's fold, merged in the warp, then by warp.
__device__ void block_box(const double* x, int begin, int end, double* out) {
  __shared__ double s[kBlock / 32][6];
  double lohi[6] = {INFINITY, INFINITY, INFINITY, -INFINITY, -INFINITY, -INFINITY};
  for (int i = begin + threadIdx.x; i < end; i += blockDim.x) bounds_fold(x, i, lohi);
  for (int o = 16; o > 0; o >>= 1) {
    double other[6];
    for (int k = 0; k < 6; ++k) other[k] = __shfl_down_sync(0xffffffffu, lohi[k], o);
    bounds_merge(lohi, other);
  }
  if ((threadIdx.x & 31) == 0)
    for (int k = 0; k < 6; ++k) s[threadIdx.x >> 5][k] = lohi[k];
  __syncthreads();
  if (threadIdx.x == 0) {
    for (int w = 1; w < static_cast<int>(blockDim.x >> 5); ++w) bounds_merge(s[0], s[w]);
    for (int k = 0; k < 6; ++k) out[k] = s[0][k] + 0.0;
  }
  __syncthreads();
}

// The keys path by one block: every listed node's (voxel, node) key, a bitonic sort in shared
// memory (the keys are distinct: one order), then the sorted voxels and nodes.
__device__ void block_keys(const DirView& v, const double* x) {
  __shared__ unsigned long long k[kKeysMax];
  int n = 1;
  while (n < v.listed) n <<= 1;
  for (int i = threadIdx.x; i < n; i += blockDim.x) k[i] = i < v.listed ? fill_key(v, x, i) : ~0ull;
  __syncthreads();
  for (int size = 2; size <= n; size <<= 1)
    for (int stride = size >> 1; stride > 0; stride >>= 1) {
      for (int i = threadIdx.x; i < n; i += blockDim.x) {
        const int j = i ^ stride;
        if (j > i) {
          const bool up = (i & size) == 0;
          const unsigned long long a = k[i], b = k[j];
          if ((a > b) == up) k[i] = b, k[j] = a;
        }
      }
      __syncthreads();
    }
  for (int i = threadIdx.x; i < v.listed; i += blockDim.x) key_store(v, k[i], i);
  if (threadIdx.x == 0) *v.contacts = 0;
  __syncthreads();
}
__global__ void dir_keys_block(DirView v, const double* x) { block_keys(v, x); }

__device__ void block_fill(const DirView& v, const double* x) {
  if (v.scell) return block_keys(v, x);
  for (int j = threadIdx.x; j < v.listed; j += blockDim.x) fill_count(v, x, j);
  __syncthreads();
  block_scan(v.cnt, v.start, static_cast<int>(v.G->capacity) + 1);
  for (int j = threadIdx.x; j < v.listed; j += blockDim.x) fill_place(v, j);
  __syncthreads();
  for (int j = threadIdx.x; j < v.listed; j += blockDim.x) fill_sort(v, j);
  if (threadIdx.x == 0) *v.contacts = 0;
  __syncthreads();
}

// A small pair's boxes, grids and lists, by one block (the large pairs' path: bounds_partial,
// pair_geometry and a launch per phase).
__global__ void pair_fill_block(const double* x, int a0, int a1, int b0, int b1, DirView fwd, DirView rev, bool two,
                                int* error) {
  __shared__ double box[2][6];
  block_box(x, a0, a1, box[0]);
  block_box(x, b0, b1, box[1]);
  if (threadIdx.x == 0) {
    grid_update(*fwd.G, box[0], box[0] + 3, box[1], box[1] + 3);
    if (fwd.G->error) *error = 1;
    if (two) {
      grid_update(*rev.G, box[1], box[1] + 3, box[0], box[0] + 3);
      if (rev.G->error) *error = 1;
    }
  }
  __syncthreads();
  block_fill(fwd, x);
  if (two) block_fill(rev, x);
}

__device__ void block_react(const DirView& v) {
  for (int j = threadIdx.x; j < v.guest_size; j += blockDim.x) react_count(v, j);
  __syncthreads();
  block_scan(v.rc, v.rstart, v.host_size + 1);
  for (int j = threadIdx.x; j < v.guest_size; j += blockDim.x) react_place(v, j);
  __syncthreads();
  for (int j = threadIdx.x; j < v.guest_size; j += blockDim.x) react_sort(v, j);
  __syncthreads();
}
__global__ void pair_react_block(DirView fwd, DirView rev, bool two) {
  block_react(fwd);
  if (two) block_react(rev);
}

// voxel_exact's search, one warp per guest node: lane l takes the candidates l, l + 32, ... of the
// node's candidate sequence (contact_kernels.hpp's for_candidates, duplicates included), keeping
// its least box bound and its nearest candidate (each with the least sequence index among its
// ties); the warp then selects as voxel_exact_push does: the least-bound candidate if it is at the
// least distance, else the first candidate at it. The same face, so the same bits.
__device__ inline bool better(double a, int ia, double b, int ib) { return a < b || (a == b && ia < ib); }

__global__ void guest_exact_warp(DirView D, const double* x) {
  const int lane = threadIdx.x & 31;
  const int warps = (gridDim.x * blockDim.x) >> 5;
  for (int j = (blockIdx.x * blockDim.x + threadIdx.x) >> 5; j < D.guest_size; j += warps) {
    Push& P = D.push[j];
    int ijk[3];
    const int cell = guest_cell(D, x, j, ijk);
    if (cell < 0) {
      if (lane == 0) P.count = 0, P.mag = 0.0;
      continue;
    }
    const int g = D.guest_begin + j;
    const V3 p = load3(x, g);
    double bb = INFINITY, bb_d2 = INFINITY;  // the lane's least bound, and its candidate's distance
    int bb_i = 0x7fffffff;
    Nearest bb_n, nn;  // the least-bound candidate's and the nearest candidate's closest points
    int nn_i = 0x7fffffff;
    int idx = 0;  // the candidate sequence's index of the block's next node's first face
    for_block_nodes(D, ijk, [&](int node) {
      const int u = node - D.host_begin;
      const int f0 = D.vf_start[u], m = D.vf_start[u + 1] - f0;
      for (int k = (lane - idx % 32 + 32) % 32; k < m; k += 32) {
        const int f = D.vf_faces[f0 + k], i = idx + k;
        const double b = face_bound(D, x, f, p);
        const Nearest e = eval_candidate(D, x, f, p);
        if (better(b, i, bb, bb_i)) bb = b, bb_i = i, bb_d2 = e.d2, bb_n = e;
        if (better(e.d2, i, nn.d2, nn_i)) nn = e, nn_i = i;
      }
      idx += m;
    });
    // The warp's least bound (first) and least distance, each with the least index among ties.
    double fb = bb, fd2 = bb_d2, md = nn.d2;
    int fi = bb_i, mi = nn_i;
    for (int o = 16; o > 0; o >>= 1) {
      const double ob = __shfl_xor_sync(0xffffffffu, fb, o), od2 = __shfl_xor_sync(0xffffffffu, fd2, o);
      const int oi = __shfl_xor_sync(0xffffffffu, fi, o);
      if (better(ob, oi, fb, fi)) fb = ob, fi = oi, fd2 = od2;
      const double omd = __shfl_xor_sync(0xffffffffu, md, o);
      const int omi = __shfl_xor_sync(0xffffffffu, mi, o);
      if (better(omd, omi, md, mi)) md = omd, mi = omi;
    }
    const int win = fd2 == md ? fi : mi;  // the winner's sequence index
    const bool mine_first = fi == bb_i && win == fi, mine_near = win == nn_i && win != fi;
    const unsigned who = __ballot_sync(0xffffffffu, mine_first || mine_near);
    const int src = who ? __ffs(who) - 1 : 0;
    Nearest w = mine_first ? bb_n : nn;
    w.d2 = __shfl_sync(0xffffffffu, w.d2, src);
    w.face = __shfl_sync(0xffffffffu, w.face, src);
    w.feature = __shfl_sync(0xffffffffu, w.feature, src);
    w.q.x = __shfl_sync(0xffffffffu, w.q.x, src), w.q.y = __shfl_sync(0xffffffffu, w.q.y, src);
    w.q.z = __shfl_sync(0xffffffffu, w.q.z, src);
    for (int k = 0; k < 3; ++k) w.w[k] = __shfl_sync(0xffffffffu, w.w[k], src);
    if (lane == 0) {
      P.count = 0, P.mag = 0.0;
      if (who && exact_contact(D, x, g, w, P)) finish_push(D, P);
    }
  }
}

// Up to kApplyPairs pairs' forces applied (in pair order), then every node integrated; the last
// thread's last act advances the device's step index.
constexpr int kApplyPairs = 4;
struct ApplyArgs {
  int pairs = 0;
  DirView fwd[kApplyPairs], rev[kApplyPairs];
  bool two[kApplyPairs] = {};
  int a0[kApplyPairs] = {}, a1[kApplyPairs] = {}, b0[kApplyPairs] = {}, b1[kApplyPairs] = {};
};
__global__ void apply_integrate(ApplyArgs A, NodeView N, double dt, int* bad, int* step) {
  for (int i = blockIdx.x * blockDim.x + threadIdx.x; i < N.n; i += gridDim.x * blockDim.x) {
    for (int p = 0; p < A.pairs; ++p)
      if ((i >= A.a0[p] && i < A.a1[p]) || (i >= A.b0[p] && i < A.b1[p]))
        apply_pair(A.fwd[p], A.two[p] ? &A.rev[p] : nullptr, N.f, i);
    integrate_node(N, dt, i, bad);
  }
  if (blockIdx.x == 0 && threadIdx.x == 0) ++*step;  // nothing in this kernel reads it
}

}  // namespace
}  // namespace harness::dev
