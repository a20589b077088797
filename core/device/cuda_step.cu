// The CUDA executor of the device step (device_step.hpp): the plan's arrays resident on the GPU,
// each kernel body of kernels.hpp and contact_kernels.hpp launched over its indices (grid-stride
// loops), the grids' and the reactions' prefix sums by CUB, and one step's launches captured once
// as a CUDA graph that every step replays. The step's index lives on the device (a one-thread
// kernel advances it), so the graph's parameters never change. Deterministic: the atomic adds
// only count, and every list they fill is sorted before it is read (contact_kernels.hpp).
#include "core/device/plan_data.hpp"

#include <cub/device/device_scan.cuh>
#include <cuda_runtime.h>

#include <algorithm>
#include <memory>
#include <stdexcept>
#include <string>
#include <vector>

namespace harness::dev {

namespace {

void check(cudaError_t e, const char* what) {
  if (e != cudaSuccess) throw std::runtime_error(std::string("CUDA: ") + what + ": " + cudaGetErrorString(e));
}

template <class T>
struct Buf {
  T* p = nullptr;
  std::size_t n = 0;
  Buf() = default;
  Buf(const Buf&) = delete;
  Buf& operator=(const Buf&) = delete;
  ~Buf() {
    if (p) cudaFree(p);
  }
  void alloc(std::size_t count) {
    n = count;
    if (count == 0) return;
    check(cudaMalloc(reinterpret_cast<void**>(&p), count * sizeof(T)), "cudaMalloc");
    check(cudaMemset(p, 0, count * sizeof(T)), "cudaMemset");
  }
  void upload(const std::vector<T>& v) {
    alloc(v.size());
    if (!v.empty()) check(cudaMemcpy(p, v.data(), v.size() * sizeof(T), cudaMemcpyHostToDevice), "upload");
  }
};

template <class F>
__global__ void each(int n, F f) {
  for (int i = blockIdx.x * blockDim.x + threadIdx.x; i < n; i += gridDim.x * blockDim.x) f(i);
}

constexpr int kBoundsBlocks = 64;

// Partial boxes of two node ranges (blockIdx.y: 0 = [a0, a1), 1 = [b0, b1)).
__global__ void bounds_partial(const double* x, int a0, int a1, int b0, int b1, double* part) {
  __shared__ double s[256][6];
  const int begin = blockIdx.y == 0 ? a0 : b0, end = blockIdx.y == 0 ? a1 : b1;
  double lohi[6] = {INFINITY, INFINITY, INFINITY, -INFINITY, -INFINITY, -INFINITY};
  for (int i = begin + blockIdx.x * blockDim.x + threadIdx.x; i < end; i += gridDim.x * blockDim.x) bounds_fold(x, i, lohi);
  for (int k = 0; k < 6; ++k) s[threadIdx.x][k] = lohi[k];
  __syncthreads();
  for (int w = blockDim.x / 2; w > 0; w /= 2) {
    if (threadIdx.x < w) bounds_merge(s[threadIdx.x], s[threadIdx.x + w]);
    __syncthreads();
  }
  if (threadIdx.x == 0)
    for (int k = 0; k < 6; ++k) part[(blockIdx.y * gridDim.x + blockIdx.x) * 6 + k] = s[0][k];
}

// The pair's boxes from the partials, then each direction's grid (one thread).
__global__ void pair_geometry(const double* part, int blocks, GridState* fwd, GridState* rev, int* error) {
  double box[2][6];
  for (int b = 0; b < 2; ++b) {
    for (int a = 0; a < 3; ++a) box[b][a] = INFINITY, box[b][3 + a] = -INFINITY;
    for (int k = 0; k < blocks; ++k) bounds_merge(box[b], part + (b * blocks + k) * 6);
    for (int a = 0; a < 6; ++a) box[b][a] = box[b][a] + 0.0;
  }
  grid_update(*fwd, box[0], box[0] + 3, box[1], box[1] + 3);
  if (fwd->error) *error = 1;
  if (rev) {
    grid_update(*rev, box[1], box[1] + 3, box[0], box[0] + 3);
    if (rev->error) *error = 1;
  }
}

}  // namespace
}  // namespace harness::dev

#include "core/device/cuda_blocks.cuh"

namespace harness::dev {
namespace {

struct DirDev {
  Buf<GridState> grid;
  Buf<int> cnt, start, cellof, slot, sorted, scell, rc, rstart, rrec, rslot, faces, vf_start, vf_faces, adjacent, contacts;
  Buf<Push> push;
  DirView v;
  long long capacity = 0;

  void make(const DirPlan& p) {
    grid.alloc(1);
    check(cudaMemcpy(grid.p, &p.grid, sizeof(GridState), cudaMemcpyHostToDevice), "grid");
    capacity = p.grid.capacity;
    if (!p.keys) {  // the counting sort's arrays over the voxels (the keys path has none)
      cnt.alloc(static_cast<std::size_t>(capacity) + 1);
      start.alloc(static_cast<std::size_t>(capacity) + 1);
    }
    cellof.alloc(p.listed), slot.alloc(p.listed), sorted.alloc(p.listed);
    if (p.keys) scell.alloc(p.listed);
    push.alloc(p.guest_size);
    rc.alloc(p.host_size + 1), rstart.alloc(p.host_size + 1);
    rrec.alloc(3 * static_cast<std::size_t>(p.guest_size) + 1), rslot.alloc(4 * static_cast<std::size_t>(p.guest_size) + 1);
    faces.upload(p.faces), vf_start.upload(p.vf_start), vf_faces.upload(p.vf_faces), adjacent.upload(p.adjacent);
    contacts.alloc(1);
    v.G = grid.p;
    v.host_begin = p.host_begin, v.host_size = p.host_size, v.host_surface = p.host_surface;
    v.listed_begin = p.listed_begin, v.listed = p.listed;
    v.guest_begin = p.guest_begin, v.guest_size = p.guest_size;
    v.detector = p.detector, v.eliminator = p.eliminator, v.force_rule = p.force_rule;
    v.force = p.force, v.stiffness = p.stiffness, v.invert = p.invert;
    v.cnt = cnt.p, v.start = start.p, v.cellof = cellof.p, v.slot = slot.p, v.sorted = sorted.p;
    v.scell = p.keys ? scell.p : nullptr;
    v.nfaces = static_cast<int>(p.faces.size() / 3);
    v.faces = faces.p, v.vf_start = vf_start.p, v.vf_faces = vf_faces.p, v.adjacent = adjacent.p;
    v.push = push.p;
    v.rc = rc.p, v.rstart = rstart.p, v.rrec = rrec.p, v.rslot = rslot.p;
    v.contacts = contacts.p;
  }
};

class Runner final : public CudaRunner {
 public:
  explicit Runner(const DevicePlan& P) : P_(P), steps0_(P.step0) {
    int count = 0;
    if (cudaGetDeviceCount(&count) != cudaSuccess || count == 0) throw std::runtime_error("no CUDA device is available");
    cudaDeviceProp prop{};
    check(cudaGetDeviceProperties(&prop, 0), "cudaGetDeviceProperties");
    name_ = prop.name;
    sms_ = prop.multiProcessorCount;
    check(cudaStreamCreateWithFlags(&stream_, cudaStreamNonBlocking), "stream");
    x_.upload(P.x), v_.upload(P.v), m_.upload(P.m), inv_m_.upload(P.inv_m), kin_v_.upload(P.kin_v);
    md_.upload(P.mass_damping), kind_.upload(P.kind);
    f_.alloc(P.x.size());
    he_start_.upload(P.he_start), he_split_.upload(P.he_split), he_other_.upload(P.he_other);
    he_rest_.upload(P.he_rest), he_stiff_.upload(P.he_stiff), node_law_.upload(P.node_law), laws_.upload(P.laws);
    pf_start_.upload(P.pf_start), pf_face_.upload(P.pf_face), face_v_.upload(P.face_v), face_p_.upload(P.face_p);
    p_ramp_.upload(P.p_ramp), p_from_.upload(P.p_from), p_to_.upload(P.p_to);
    ld_start_.upload(P.ld_start), ld_load_.upload(P.ld_load), ld_count_.upload(P.ld_count), ld_ramp_.upload(P.ld_ramp);
    ld_force_.upload(P.ld_force);
    dr_node_.upload(P.dr_node), dr_start_.upload(P.dr_start), dr_driver_.upload(P.dr_driver);
    dr_from_.upload(P.dr_from), dr_to_.upload(P.dr_to), dr_vel_.upload(P.dr_vel);
    step_.upload(std::vector<int>{P.step0});
    flags_.alloc(2);  // 0: non-finite state, 1: a grid outgrew its allocation
    part_.alloc(2 * kBoundsBlocks * 6);

    S_.start = he_start_.p, S_.split = he_split_.p, S_.other = he_other_.p, S_.rest = he_rest_.p;
    S_.stiff = he_stiff_.p, S_.law = node_law_.p, S_.laws = laws_.p;
    N_.n = P.n, N_.x = x_.p, N_.v = v_.p, N_.f = f_.p, N_.m = m_.p, N_.inv_m = inv_m_.p, N_.kind = kind_.p;
    N_.kin_v = kin_v_.p, N_.mass_damping = md_.p;
    N_.springs = P.springs, N_.dashpots = P.dashpots, N_.damping = P.damping, N_.external = P.external;
    N_.gravity = P.gravity;
    for (int k = 0; k < 3; ++k) N_.g[k] = P.g[k];
    N_.pf_start = pf_start_.p, N_.pf_face = pf_face_.p, N_.face_v = face_v_.p, N_.face_p = face_p_.p;
    N_.p_from = p_from_.p, N_.p_to = p_to_.p, N_.p_ramp = p_ramp_.p;
    N_.ld_start = ld_start_.p, N_.ld_load = ld_load_.p, N_.ld_force = ld_force_.p, N_.ld_count = ld_count_.p;
    N_.ld_ramp = ld_ramp_.p;
    D_.nodes = static_cast<int>(P.dr_node.size()), D_.node = dr_node_.p, D_.start = dr_start_.p;
    D_.driver = dr_driver_.p, D_.from = dr_from_.p, D_.to = dr_to_.p, D_.vel = dr_vel_.p;

    dirs_.resize(2 * P.pairs.size());
    std::size_t scan_n = 1;
    for (std::size_t p = 0; p < P.pairs.size(); ++p) {
      dirs_[2 * p] = std::make_unique<DirDev>();
      dirs_[2 * p]->make(P.pairs[p].fwd);
      if (P.pairs[p].two_sided) {
        dirs_[2 * p + 1] = std::make_unique<DirDev>();
        dirs_[2 * p + 1]->make(P.pairs[p].rev);
      }
      for (int d = 0; d < 2; ++d)
        if (dirs_[2 * p + d]) {
          const DirDev& dd = *dirs_[2 * p + d];
          scan_n = std::max(scan_n, static_cast<std::size_t>(dd.capacity) + 1);
          scan_n = std::max(scan_n, static_cast<std::size_t>(dd.v.host_size) + 1);
        }
    }
    check(cub::DeviceScan::ExclusiveSum(nullptr, scan_bytes_, static_cast<int*>(nullptr), static_cast<int*>(nullptr),
                                        static_cast<int>(scan_n), stream_),
          "cub temp size");
    scan_tmp_.alloc(scan_bytes_ + 16);
    capture();
  }

  ~Runner() override {
    if (exec_) cudaGraphExecDestroy(exec_);
    if (graph_) cudaGraphDestroy(graph_);
    if (stream_) cudaStreamDestroy(stream_);
  }

  void step(int n) override {
    for (int k = 0; k < n; ++k) {
      check(cudaGraphLaunch(exec_, stream_), "cudaGraphLaunch");
      ++taken_;
      if (taken_ % kCheckEvery == 0) check_flags();
    }
  }
  void synchronize() override {
    check(cudaStreamSynchronize(stream_), "synchronize");
  }
  void download(double* x, double* v, double* kin_v, unsigned char* kind) override {
    synchronize();
    check_flags();
    const std::size_t b = P_.x.size() * sizeof(double);
    check(cudaMemcpy(x, x_.p, b, cudaMemcpyDeviceToHost), "download x");
    check(cudaMemcpy(v, v_.p, b, cudaMemcpyDeviceToHost), "download v");
    check(cudaMemcpy(kin_v, kin_v_.p, b, cudaMemcpyDeviceToHost), "download kin_v");
    check(cudaMemcpy(kind, kind_.p, P_.kind.size(), cudaMemcpyDeviceToHost), "download kind");
  }
  int contacts(int pair) override {
    synchronize();
    int total = 0;
    for (int d = 0; d < 2; ++d) {
      const auto& dd = dirs_[2 * static_cast<std::size_t>(pair) + d];
      if (!dd) continue;
      int c = 0;
      check(cudaMemcpy(&c, dd->contacts.p, sizeof(int), cudaMemcpyDeviceToHost), "contacts");
      total += c;
    }
    return total;
  }
  int steps_taken() const override { return taken_; }
  const char* name() const override { return name_.c_str(); }
  double copy_us(std::size_t bytes, int reps) override {
    Buf<char> a, b;
    a.alloc(bytes), b.alloc(bytes);
    cudaEvent_t e0, e1;
    check(cudaEventCreate(&e0), "event"), check(cudaEventCreate(&e1), "event");
    std::vector<float> ms;
    for (int r = 0; r < reps + 1; ++r) {
      check(cudaEventRecord(e0, stream_), "record");
      check(cudaMemcpyAsync(b.p, a.p, bytes, cudaMemcpyDeviceToDevice, stream_), "copy");
      check(cudaEventRecord(e1, stream_), "record");
      check(cudaEventSynchronize(e1), "sync");
      float t = 0.0f;
      check(cudaEventElapsedTime(&t, e0, e1), "elapsed");
      if (r > 0) ms.push_back(t);  // the first copy warms up
    }
    cudaEventDestroy(e0), cudaEventDestroy(e1);
    std::sort(ms.begin(), ms.end());
    return 1000.0 * ms[ms.size() / 2];
  }

 // (public: nvcc's extended lambdas need a public enclosing function)
  static constexpr int kCheckEvery = 100;

  template <class F>
  void launch(int n, F f) {
    if (n <= 0) return;
    const int blocks = std::max(1, std::min((n + 255) / 256, 16 * sms_));
    each<<<blocks, 256, 0, stream_>>>(n, f);
  }
  void scan(const int* in, int* out, int n) {
    std::size_t bytes = scan_bytes_;
    check(cub::DeviceScan::ExclusiveSum(scan_tmp_.p, bytes, in, out, n, stream_), "scan");
  }

  void check_flags() {
    int flags[2] = {0, 0};
    check(cudaMemcpy(flags, flags_.p, sizeof(flags), cudaMemcpyDeviceToHost), "flags");
    if (flags[1]) throw std::runtime_error("device: a contact grid outgrew its allocation (the host grew past twice its size)");
    if (flags[0]) throw std::runtime_error("device: the state became non-finite within the last " + std::to_string(kCheckEvery) + " steps");
  }

  void direction(DirDev& d) {
    const DirView v = d.v;
    const double* x = x_.p;
    if (v.scell) {
      dir_keys_block<<<1, kBlock, 0, stream_>>>(v, x);
    } else {  // the counting sort over the voxels
      launch(v.listed, [=] __device__(int j) { fill_count(v, x, j); });
      scan(v.cnt, v.start, static_cast<int>(d.capacity) + 1);
      launch(v.listed, [=] __device__(int j) { fill_place(v, j); });
      launch(v.listed, [=] __device__(int j) { fill_sort(v, j); });
      check(cudaMemsetAsync(v.contacts, 0, sizeof(int), stream_), "memset");
    }
    lookup(d);
    launch(v.guest_size, [=] __device__(int j) { react_count(v, j); });
    scan(v.rc, v.rstart, v.host_size + 1);
    launch(v.guest_size, [=] __device__(int j) { react_place(v, j); });
    launch(v.guest_size, [=] __device__(int j) { react_sort(v, j); });
  }

  // Whether a pair is small enough for the one-block kernels (its grids' scans and lists).
  bool small(std::size_t p) const {
    for (int d = 0; d < 2; ++d) {
      const auto& dd = dirs_[2 * p + d];
      if (!dd) continue;
      if (!dd->v.scell || dd->v.host_size > (1 << 16) || dd->v.guest_size > (1 << 16)) return false;
    }
    return true;
  }

  void lookup(DirDev& d) {
    const DirView v = d.v;
    const double* x = x_.p;
    if (v.detector == kDetVoxelExact) {
      const int blocks = std::max(1, std::min((v.guest_size * 32 + 255) / 256, 16 * sms_));
      guest_exact_warp<<<blocks, 256, 0, stream_>>>(v, x);
    } else {
      launch(v.guest_size, [=] __device__(int j) { guest_push(v, x, j); });
    }
  }

  // One step's launches, recorded into the graph. The step's index is *step + 1 until the last
  // kernel advances it.
  void record() {
    int* stepp = step_.p;
    const NodeView N = N_;
    const SpringsView S = S_;
    const DriversView D = D_;
    launch(D.nodes, [=] __device__(int d) { drive_node(D, N, *stepp + 1, d); });
    launch(N.n, [=] __device__(int i) { node_forces(S, N, *stepp + 1, i); });
    ApplyArgs A;
    for (std::size_t p = 0; p < P_.pairs.size(); ++p) {
      const PairPlan& pp = P_.pairs[p];
      DirDev& fwd = *dirs_[2 * p];
      DirDev* rev = pp.two_sided ? dirs_[2 * p + 1].get() : nullptr;
      if (small(p)) {
        pair_fill_block<<<1, kBlock, 0, stream_>>>(x_.p, pp.a_begin, pp.a_end, pp.b_begin, pp.b_end, fwd.v,
                                                   rev ? rev->v : DirView{}, rev != nullptr, flags_.p + 1);
        lookup(fwd);
        if (rev) lookup(*rev);
        pair_react_block<<<1, kBlock, 0, stream_>>>(fwd.v, rev ? rev->v : DirView{}, rev != nullptr);
      } else {
        const int blocks = std::max(1, std::min(kBoundsBlocks, (std::max(pp.a_end - pp.a_begin, pp.b_end - pp.b_begin) + 255) / 256));
        bounds_partial<<<dim3(blocks, 2), 256, 0, stream_>>>(x_.p, pp.a_begin, pp.a_end, pp.b_begin, pp.b_end, part_.p);
        pair_geometry<<<1, 1, 0, stream_>>>(part_.p, blocks, fwd.grid.p, rev ? rev->grid.p : nullptr, flags_.p + 1);
        direction(fwd);
        if (rev) direction(*rev);
      }
      const int q = A.pairs;
      if (q == kApplyPairs) {  // more pairs than one kernel's arguments hold: apply these now
        flush_apply(A);
        A = ApplyArgs{};
      }
      const int k = A.pairs++;
      A.fwd[k] = fwd.v, A.rev[k] = rev ? rev->v : DirView{}, A.two[k] = rev != nullptr;
      A.a0[k] = pp.a_begin, A.a1[k] = pp.a_end, A.b0[k] = pp.b_begin, A.b1[k] = pp.b_end;
    }
    const int blocks = std::max(1, std::min((N.n + 255) / 256, 16 * sms_));
    apply_integrate<<<blocks, 256, 0, stream_>>>(A, N, P_.dt, flags_.p, stepp);
  }
  // Applies the pairs of A without integrating (more than kApplyPairs pairs).
  void flush_apply(const ApplyArgs& A) {
    const ApplyArgs B = A;
    double* f = f_.p;
    launch(N_.n, [=] __device__(int i) {
      for (int p = 0; p < B.pairs; ++p)
        if ((i >= B.a0[p] && i < B.a1[p]) || (i >= B.b0[p] && i < B.b1[p]))
          apply_pair(B.fwd[p], B.two[p] ? &B.rev[p] : nullptr, f, i);
    });
  }

  void capture() {
    check(cudaStreamBeginCapture(stream_, cudaStreamCaptureModeGlobal), "begin capture");
    record();
    check(cudaGetLastError(), "a launch while capturing");
    check(cudaStreamEndCapture(stream_, &graph_), "end capture");
    check(cudaGraphInstantiate(&exec_, graph_, 0), "instantiate");
  }

 private:
  DevicePlan P_;
  int steps0_ = 0, taken_ = 0, sms_ = 1;
  std::string name_;
  cudaStream_t stream_ = nullptr;
  cudaGraph_t graph_ = nullptr;
  cudaGraphExec_t exec_ = nullptr;
  Buf<double> x_, v_, m_, inv_m_, kin_v_, md_, f_, he_rest_, he_stiff_, p_from_, p_to_, ld_force_, dr_vel_, part_;
  Buf<unsigned char> kind_;
  Buf<int> he_start_, he_split_, he_other_, node_law_, pf_start_, pf_face_, face_v_, face_p_, p_ramp_,
      ld_start_, ld_load_, ld_count_, ld_ramp_, dr_node_, dr_start_, dr_driver_, dr_from_, dr_to_, step_, flags_;
  Buf<Law> laws_;
  Buf<char> scan_tmp_;
  std::size_t scan_bytes_ = 0;
  SpringsView S_;
  NodeView N_;
  DriversView D_;
  std::vector<std::unique_ptr<DirDev>> dirs_;
};

}  // namespace

CudaRunner* make_cuda_runner(const DevicePlan& plan) { return new Runner(plan); }

}  // namespace harness::dev
