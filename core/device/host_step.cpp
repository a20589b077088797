// The CPU executor of the device's kernel bodies ("cpu"): every launch of cuda_step.cu as a loop
// over the same indices, in index order, on one thread (its atomic adds plain adds). It is how the
// CPU build tests the arithmetic the GPU runs (ctest gpu_kernels_*), and what `--device cpu` runs.
#include "core/device/device_step.hpp"
#include "core/device/plan.hpp"

#include <algorithm>
#include <stdexcept>

namespace harness {

namespace dev {

namespace {

struct DirBuffers {
  GridState grid;
  std::vector<int> cnt, start, cellof, slot, sorted, scell, rc, rstart, rrec, rslot;
  std::vector<unsigned long long> keys;
  std::vector<Push> push;
  int contacts = 0;
  const DirPlan* plan = nullptr;

  void make(const DirPlan& p) {
    plan = &p;
    grid = p.grid;
    if (!p.keys) {  // the counting sort's arrays over the voxels (the keys path has none)
      cnt.assign(static_cast<std::size_t>(grid.capacity) + 1, 0);
      start.assign(cnt.size(), 0);
    }
    cellof.assign(static_cast<std::size_t>(p.listed), -1);
    slot.assign(static_cast<std::size_t>(p.listed), -1);
    sorted.assign(static_cast<std::size_t>(p.listed), -1);
    if (p.keys) scell.assign(static_cast<std::size_t>(p.listed), kNoCell), keys.resize(static_cast<std::size_t>(p.listed));
    push.assign(static_cast<std::size_t>(p.guest_size), Push{});
    rc.assign(static_cast<std::size_t>(p.host_size) + 1, 0);
    rstart.assign(static_cast<std::size_t>(p.host_size) + 1, 0);
    rrec.assign(3 * static_cast<std::size_t>(p.guest_size) + 1, 0);
    rslot.assign(4 * static_cast<std::size_t>(p.guest_size) + 1, 0);
  }
  DirView view() {
    const DirPlan& p = *plan;
    DirView v;
    v.G = &grid;
    v.host_begin = p.host_begin, v.host_size = p.host_size, v.host_surface = p.host_surface;
    v.listed_begin = p.listed_begin, v.listed = p.listed;
    v.guest_begin = p.guest_begin, v.guest_size = p.guest_size;
    v.detector = p.detector, v.eliminator = p.eliminator, v.force_rule = p.force_rule;
    v.force = p.force, v.stiffness = p.stiffness, v.invert = p.invert;
    v.cnt = cnt.data(), v.start = start.data(), v.cellof = cellof.data(), v.slot = slot.data();
    v.sorted = sorted.data();
    v.scell = p.keys ? scell.data() : nullptr;
    v.nfaces = static_cast<int>(p.faces.size() / 3);
    v.faces = p.faces.data(), v.vf_start = p.vf_start.data(), v.vf_faces = p.vf_faces.data();
    v.adjacent = p.adjacent.data();
    v.push = push.data();
    v.rc = rc.data(), v.rstart = rstart.data(), v.rrec = rrec.data(), v.rslot = rslot.data();
    v.contacts = &contacts;
    return v;
  }
};

void exclusive_scan(const int* in, int* out, int n) {
  int s = 0;
  for (int i = 0; i < n; ++i) {
    const int c = in[i];
    out[i] = s;
    s += c;
  }
}

template <class T>
const T* ptr(const std::vector<T>& v) {
  return v.empty() ? nullptr : v.data();
}

}  // namespace

class HostStep final : public DeviceStep {
 public:
  explicit HostStep(const Simulation& sim) : P_(make_plan(sim)), step_(P_.step0) {
    f_.assign(P_.x.size(), 0.0);
    S_.start = ptr(P_.he_start), S_.split = ptr(P_.he_split), S_.other = ptr(P_.he_other);
    S_.rest = ptr(P_.he_rest), S_.stiff = ptr(P_.he_stiff), S_.law = ptr(P_.node_law), S_.laws = ptr(P_.laws);
    N_.n = P_.n;
    N_.x = P_.x.data(), N_.v = P_.v.data(), N_.f = f_.data(), N_.m = ptr(P_.m), N_.inv_m = ptr(P_.inv_m);
    N_.kind = P_.kind.data(), N_.kin_v = P_.kin_v.data(), N_.mass_damping = ptr(P_.mass_damping);
    N_.springs = P_.springs, N_.dashpots = P_.dashpots, N_.damping = P_.damping, N_.external = P_.external;
    N_.gravity = P_.gravity;
    for (int k = 0; k < 3; ++k) N_.g[k] = P_.g[k];
    N_.pf_start = ptr(P_.pf_start), N_.pf_face = ptr(P_.pf_face), N_.face_v = ptr(P_.face_v), N_.face_p = ptr(P_.face_p);
    N_.p_from = ptr(P_.p_from), N_.p_to = ptr(P_.p_to), N_.p_ramp = ptr(P_.p_ramp);
    N_.ld_start = ptr(P_.ld_start), N_.ld_load = ptr(P_.ld_load), N_.ld_force = ptr(P_.ld_force);
    N_.ld_count = ptr(P_.ld_count), N_.ld_ramp = ptr(P_.ld_ramp);
    D_.nodes = static_cast<int>(P_.dr_node.size());
    D_.node = ptr(P_.dr_node), D_.start = ptr(P_.dr_start), D_.driver = ptr(P_.dr_driver);
    D_.from = ptr(P_.dr_from), D_.to = ptr(P_.dr_to), D_.vel = ptr(P_.dr_vel);
    dirs_.resize(2 * P_.pairs.size());
    for (std::size_t p = 0; p < P_.pairs.size(); ++p) {
      dirs_[2 * p].make(P_.pairs[p].fwd);
      if (P_.pairs[p].two_sided) dirs_[2 * p + 1].make(P_.pairs[p].rev);
    }
  }

  void step(int n) override {
    for (int k = 0; k < n; ++k) one_step();
  }
  void synchronize() override {}
  void download(World& w) override {
    for (int i = 0; i < P_.n; ++i)
      for (int k = 0; k < 3; ++k) w.x[i][k] = P_.x[3 * i + k], w.v[i][k] = P_.v[3 * i + k], w.kin_v[i][k] = P_.kin_v[3 * i + k];
    for (int i = 0; i < P_.n; ++i) w.kinematic[i] = static_cast<Kinematic>(P_.kind[i]);
  }
  int steps_taken() const override { return step_ - P_.step0; }
  int contacts(int pair) override {
    const std::size_t p = static_cast<std::size_t>(pair);
    return dirs_[2 * p].contacts + (P_.pairs[p].two_sided ? dirs_[2 * p + 1].contacts : 0);
  }
  std::string device_name() const override { return "cpu (device kernels, one thread)"; }

 private:
  void box(int begin, int end, double out[6]) const {
    for (int a = 0; a < 3; ++a) out[a] = INFINITY, out[3 + a] = -INFINITY;
    for (int i = begin; i < end; ++i) bounds_fold(P_.x.data(), i, out);
    for (int a = 0; a < 6; ++a) out[a] = out[a] + 0.0;
  }

  void direction(DirBuffers& B, const double hb[6], const double gb[6]) {
    grid_update(B.grid, hb, hb + 3, gb, gb + 3);
    if (B.grid.error) throw std::runtime_error("device: a contact grid outgrew its allocation (the host grew past twice its size)");
    const DirView v = B.view();
    const double* x = P_.x.data();
    if (v.scell) {  // the keys path: (voxel, node) sorted
      for (int j = 0; j < v.listed; ++j) B.keys[j] = fill_key(v, x, j);
      std::sort(B.keys.begin(), B.keys.end());
      for (int j = 0; j < v.listed; ++j) key_store(v, B.keys[j], j);
    } else {  // the counting sort over the voxels
      for (int j = 0; j < v.listed; ++j) fill_count(v, x, j);
      exclusive_scan(v.cnt, v.start, static_cast<int>(B.grid.capacity) + 1);
      for (int j = 0; j < v.listed; ++j) fill_place(v, j);
      for (int j = 0; j < v.listed; ++j) fill_sort(v, j);
    }
    B.contacts = 0;
    for (int j = 0; j < v.guest_size; ++j) guest_push(v, x, j);
    for (int j = 0; j < v.guest_size; ++j) react_count(v, j);
    exclusive_scan(v.rc, v.rstart, v.host_size + 1);
    for (int j = 0; j < v.guest_size; ++j) react_place(v, j);
    for (int j = 0; j < v.guest_size; ++j) react_sort(v, j);
  }

  void one_step() {
    const int s = ++step_;
    for (int d = 0; d < D_.nodes; ++d) drive_node(D_, N_, s, d);
    for (int i = 0; i < P_.n; ++i) node_forces(S_, N_, s, i);
    for (std::size_t p = 0; p < P_.pairs.size(); ++p) {
      const PairPlan& pp = P_.pairs[p];
      double a[6], b[6];
      box(pp.a_begin, pp.a_end, a);
      box(pp.b_begin, pp.b_end, b);
      direction(dirs_[2 * p], a, b);
      if (pp.two_sided) direction(dirs_[2 * p + 1], b, a);
      const DirView fwd = dirs_[2 * p].view();
      const DirView rev = pp.two_sided ? dirs_[2 * p + 1].view() : DirView{};
      for (int i = pp.a_begin; i < pp.a_end; ++i) apply_pair(fwd, pp.two_sided ? &rev : nullptr, f_.data(), i);
      for (int i = pp.b_begin; i < pp.b_end; ++i) apply_pair(fwd, pp.two_sided ? &rev : nullptr, f_.data(), i);
    }
    int bad = 0;
    for (int i = 0; i < P_.n; ++i) integrate_node(N_, P_.dt, i, &bad);
    if (bad) throw std::runtime_error("device: the state became non-finite at step " + std::to_string(s));
  }

  DevicePlan P_;
  int step_ = 0;
  std::vector<double> f_;
  SpringsView S_;
  NodeView N_;
  DriversView D_;
  std::vector<DirBuffers> dirs_;
};

}  // namespace dev

#ifndef HARNESS_HAVE_CUDA
bool cuda_built() { return false; }
#else
bool cuda_built() { return true; }

namespace {
// The CUDA executor behind DeviceStep.
class CudaStep final : public DeviceStep {
 public:
  explicit CudaStep(const Simulation& sim) : n_(sim.world().num_nodes()) {
    const dev::DevicePlan plan = dev::make_plan(sim);
    r_.reset(dev::make_cuda_runner(plan));
  }
  void step(int n) override { r_->step(n); }
  void synchronize() override { r_->synchronize(); }
  void download(World& w) override {
    std::vector<double> x(3 * static_cast<std::size_t>(n_)), v(x.size()), kv(x.size());
    std::vector<unsigned char> kind(static_cast<std::size_t>(n_));
    r_->download(x.data(), v.data(), kv.data(), kind.data());
    for (int i = 0; i < n_; ++i) {
      for (int k = 0; k < 3; ++k) w.x[i][k] = x[3 * i + k], w.v[i][k] = v[3 * i + k], w.kin_v[i][k] = kv[3 * i + k];
      w.kinematic[i] = static_cast<Kinematic>(kind[i]);
    }
  }
  int steps_taken() const override { return r_->steps_taken(); }
  int contacts(int pair) override { return r_->contacts(pair); }
  std::string device_name() const override { return r_->name(); }
  double copy_us(std::size_t bytes, int reps) override { return r_->copy_us(bytes, reps); }

 private:
  int n_;
  std::unique_ptr<dev::CudaRunner> r_;
};
}  // namespace
#endif

std::unique_ptr<DeviceStep> make_device_step(const Simulation& sim, const std::string& device) {
  if (device == "cpu") return std::make_unique<dev::HostStep>(sim);
  if (device == "cuda") {
#ifdef HARNESS_HAVE_CUDA
    try {
      return std::make_unique<CudaStep>(sim);
    } catch (const std::runtime_error& e) {
      if (dynamic_cast<const InputError*>(&e)) throw;
      throw InputError("--device cuda", e.what());
    }
#else
    throw InputError("--device", "this program was built without CUDA (CMake found no CUDA compiler, or HARNESS_CUDA=off)");
#endif
  }
  throw InputError("--device", "unknown device '" + device + "' (cpu, cuda)");
}

}  // namespace harness
