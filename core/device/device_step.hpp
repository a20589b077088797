// The step on a device (`harness run --device cuda`, `harness bench --device cuda`): the state of a
// built Simulation flattened into plain arrays (DevicePlan), stepped by the kernel bodies of
// kernels.hpp and contact_kernels.hpp on the CPU ("cpu": one thread, the test executor of those
// bodies, ctest gpu_kernels_*) or on a GPU ("cuda": the same bodies in CUDA kernels, one CUDA
// graph per step; built only where CMake finds a CUDA compiler, HARNESS_CUDA).
//
// What a device steps: effects springs (every law), damping (dashpots, mass damping), gravity,
// pins, drivers, pressure, loads and contact; the symplectic Euler integrator at the scene's dt
// (no substeps); contact pairs with the detector "voxel" (line or plane, constant or penalty
// force, any region, host_nodes, two_sided) or "voxel_exact" (line, constant or penalty force).
// Anything else is refused when the plan is made: an InputError naming the scene key, never run
// elsewhere in silence. Not on a device: the energy audit, settling, the periodic stability
// check (the guard checks dt once, when the Simulation is built), measurements; the run checks
// that the state stays finite.
#pragma once

#include "core/simulation.hpp"

#include <memory>
#include <string>
#include <vector>

namespace harness {

class DeviceStep {
 public:
  virtual ~DeviceStep() = default;
  // n steps of the scene's dt. Throws std::runtime_error when the state became non-finite or a
  // grid outgrew its allocation (checked every `check_every` steps and at the end of each call).
  virtual void step(int n) = 0;
  // Waits for the device (step() may return before the GPU is done).
  virtual void synchronize() = 0;
  // The state into w (positions, velocities, kinematic flags of drivers): w is the Simulation's
  // world the plan was made from.
  virtual void download(World& w) = 0;
  virtual int steps_taken() const = 0;
  // Contacts of pair p in the last step (both ways).
  virtual int contacts(int pair) = 0;
  virtual std::string device_name() const = 0;
  // Microseconds of one device-to-device copy of `bytes` bytes (the median of `reps`); -1 where the
  // device is the CPU executor (the bench's `copy` row).
  virtual double copy_us(std::size_t bytes, int reps) { (void)bytes, (void)reps; return -1.0; }
};

// Throws InputError naming the scene key of the first thing a device cannot step.
void check_device_support(const Simulation& sim);
// "cpu" (the kernel bodies on one CPU thread) or "cuda". Throws InputError for an unknown device,
// for "cuda" in a program built without CUDA, and what check_device_support throws.
std::unique_ptr<DeviceStep> make_device_step(const Simulation& sim, const std::string& device);
// Whether this program was built with the CUDA backend.
bool cuda_built();
// The listed host nodes up to which a contact direction's lists are made by sorting keys rather
// than by a counting sort over its voxels (contact_kernels.hpp, kKeysMax by default); the tests set
// 0 to run the counting sort on the bundled scenes. Read when a device step is made.
void set_device_keys_max(int n);

}  // namespace harness
