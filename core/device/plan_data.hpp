// The arrays of a DevicePlan (plan.hpp): plain data, no Eigen, so that the CUDA translation unit
// (cuda_step.cu) includes it without the CPU's headers.
#pragma once

#include "core/device/contact_kernels.hpp"
#include "core/device/kernels.hpp"

#include <vector>

namespace harness::dev {

struct DirPlan {
  GridState grid;  // as built at rest
  int host = -1, guest = -1;
  int host_begin = 0, host_size = 0, host_surface = 0, listed_begin = 0, listed = 0;
  int guest_begin = 0, guest_size = 0;
  int detector = kDetVoxel, eliminator = kElimLine, force_rule = kForceConstant;
  double force = 0.0, stiffness = 0.0;
  bool invert = false;
  bool keys = false;  // the keys path (contact_kernels.hpp: listed <= the plan's keys_max)
  std::vector<int> faces, vf_start, vf_faces, adjacent;
};

struct PairPlan {
  DirPlan fwd;
  bool two_sided = false;
  DirPlan rev;
  int a_begin = 0, a_end = 0, b_begin = 0, b_end = 0;  // the host's and the guest's node ranges
};

struct DevicePlan {
  int n = 0;
  double dt = 0.0;
  int step0 = 0;  // steps the Simulation had taken
  std::vector<double> x, v, m, inv_m, kin_v, mass_damping;
  std::vector<unsigned char> kind;
  // Springs, node-centric (kernels.hpp's SpringsView).
  std::vector<int> he_start, he_split, he_other, node_law;
  std::vector<double> he_rest, he_stiff;
  std::vector<Law> laws;
  bool springs = false, dashpots = false, damping = false, external = false, gravity = false;
  double g[3] = {0.0, 0.0, 0.0};
  std::vector<int> pf_start, pf_face, face_v, face_p, p_ramp;
  std::vector<double> p_from, p_to;
  std::vector<int> ld_start, ld_load, ld_count, ld_ramp;
  std::vector<double> ld_force;
  std::vector<int> dr_node, dr_start, dr_driver, dr_from, dr_to;
  std::vector<double> dr_vel;
  std::vector<PairPlan> pairs;
};

// The CUDA executor (cuda_step.cu), behind a plain interface: the DeviceStep of a program built
// with CUDA wraps it (host_step.cpp).
class CudaRunner {
 public:
  virtual ~CudaRunner() = default;
  virtual void step(int n) = 0;  // throws std::runtime_error: non-finite state, grid overflow
  virtual void synchronize() = 0;
  virtual void download(double* x, double* v, double* kin_v, unsigned char* kind) = 0;
  virtual int contacts(int pair) = 0;
  virtual int steps_taken() const = 0;
  virtual const char* name() const = 0;
  virtual double copy_us(std::size_t bytes, int reps) = 0;
};
CudaRunner* make_cuda_runner(const DevicePlan& plan);  // throws std::runtime_error without a GPU

}  // namespace harness::dev
