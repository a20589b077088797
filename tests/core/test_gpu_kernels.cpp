// The device step's kernel bodies (core/device/kernels.hpp, contact_kernels.hpp) run on the CPU
// (the "cpu" executor: the launches of cuda_step.cu as loops) against the CPU's own step, on the
// bundled scenes with the detectors a device steps. The GPU compiles these same bodies.
#include "core/device/device_step.hpp"
#include "core/scene/scene.hpp"
#include "core/simulation.hpp"
#include "core/state_hash.hpp"

#include <catch2/catch.hpp>

#include <string>
#include <utility>
#include <vector>

using namespace harness;

namespace {

std::string bundled(const char* name) { return std::string(HARNESS_SOURCE_DIR) + "/experiments/scenes/" + name + ".json"; }

using Overrides = std::vector<std::pair<std::string, std::string>>;

// The largest node distance (m) between the CPU's step and the device kernels' after `steps`.
double device_vs_cpu(const Scene& scene, int steps, int* contacts = nullptr) {
  SimulationOptions so;
  so.audit = false;
  Simulation cpu(scene, so), base(scene, so);
  std::unique_ptr<DeviceStep> dev = make_device_step(base, "cpu");
  int found = 0;
  for (int k = 0; k < steps; ++k) {
    cpu.step();
    dev->step(1);
    if (!cpu.pairs().empty()) found += dev->contacts(0);
  }
  dev->download(base.world());
  if (contacts) *contacts = found;
  double d = 0.0;
  for (int i = 0; i < cpu.world().num_nodes(); ++i) d = std::max(d, (cpu.world().x[i] - base.world().x[i]).norm());
  return d;
}

Overrides with(Overrides o) {
  o.insert(o.begin(), {"references.solvers", "[]"});
  return o;
}

}  // namespace

TEST_CASE("gpu_kernels_scenes: the device kernels step the bundled scenes as the CPU does", "[device]") {
  struct Case {
    const char* scene;
    Overrides o;
    int steps;
  };
  const std::vector<Case> cases = {
      // The completed model (voxel_exact, penalty, both ways): the accurate method a device runs.
      {"sphere_collision", with({{"contacts.0.detector", "\"voxel_exact\""}}), 2500},
      {"cylinder_press", with({{"contacts.0.detector", "\"voxel_exact\""}}), 600},
      {"implant_expansion", with({{"contacts.0.detector", "\"voxel_exact\""}}), 600},
      // The paper's model: the line rule with a constant force, the plane rule with the penalty.
      {"sphere_collision", with({{"contacts.0.detector", "\"voxel\""}, {"contacts.0.force", "0.001"},
                                 {"contacts.0.two_sided", "false"}}), 2500},
      {"implant_expansion", with({{"contacts.0.detector", "\"voxel\""}, {"contacts.0.eliminator", "\"plane\""}}), 600},
      {"cylinder_press", with({{"contacts.0.detector", "\"voxel\""}, {"contacts.0.region", "\"overlap\""},
                               {"contacts.0.host_nodes", "\"surface\""}}), 600},
  };
  // Both ways of making the voxels' lists: sorted keys (the bundled scenes' host lists are short)
  // and the counting sort over the voxels (the large scenes' way, forced here).
  for (int keys_max : {4096, 0}) {
    set_device_keys_max(keys_max);
    for (const Case& c : cases) {
      const Scene scene = load_scene(bundled(c.scene), c.o);
      int contacts = 0;
      const double d = device_vs_cpu(scene, c.steps, &contacts);
      INFO(c.scene << " " << c.o.back().first << " = " << c.o.back().second << ", keys_max " << keys_max
                   << ": max node distance " << d << " m, " << contacts << " contacts over the steps");
      CHECK(contacts > 0);  // the contact kernels were exercised
      // The same operations in the same order: the same bits.
      CHECK(d == 0.0);
    }
  }
  set_device_keys_max(4096);
}

TEST_CASE("gpu_kernels_effects: gravity, pressure, loads, drivers and every law on the device kernels", "[device]") {
  const std::string text = R"({"name":"all","time":{"dt":2e-5,"steps":0},
    "effects":["springs","damping","gravity","pins","drivers","pressure","loads"],
    "gravity":[0.3,-0.2,-9.81],
    "bodies":[
      {"name":"a","shape":{"type":"sphere","center":[0,0,0],"radius":0.01,"subdivisions":2,"fill":"shell"},
       "material":{"density":1000,"stiffness":50,"law":"cubic","nonlinearity":2.0,"damping":0.001,"mass_damping":3},
       "pressure":{"from":0,"to":200,"ramp_steps":50},
       "drivers":[{"select":{"side":"-x"},"velocity":[0.01,0,0],"from_step":5,"to_step":40}]},
      {"name":"b","shape":{"type":"box","min":[0.02,0,0],"max":[0.03,0.01,0.01],"cells":[3,3,3]},
       "material":{"density":1000,"stiffness":80,"law":"exponential","nonlinearity":3.0,"damping":0.002},
       "pins":[{"side":"-z"}],
       "loads":[{"select":{"side":"+z"},"force":[0,0,0.05],"ramp_steps":30}]},
      {"name":"c","shape":{"type":"box","min":[-0.03,0,0],"max":[-0.02,0.01,0.01],"cells":[2,2,2]},
       "material":{"density":1000,"stiffness":60,"law":"linear"}}]})";
  const Scene scene = parse_scene(text, "all.json");
  CHECK(device_vs_cpu(scene, 120) == 0.0);
}

TEST_CASE("gpu_kernels_refusals: what a device cannot step is refused with its key", "[device]") {
  auto message = [](const Overrides& o) {
    SimulationOptions so;
    so.audit = false;
    Simulation sim(load_scene(bundled("sphere_collision"), with(o)), so);
    try {
      make_device_step(sim, "cpu");
    } catch (const InputError& e) {
      return std::string(e.what());
    }
    return std::string("accepted");
  };
  CHECK(message({{"contacts.0.detector", "\"hash\""}}).find("contacts.0.detector") != std::string::npos);
  CHECK(message({{"contacts.0.detector", "\"voxel\""}, {"contacts.0.force", "\"auto\""}}).find("contacts.0.force") !=
        std::string::npos);
  // A force rule without a device kernel (core/collision/rules/hertz.cpp), never a substitute.
  CHECK(message({{"contacts.0.detector", "\"voxel\""}, {"contacts.0.force", R"({"rule":"hertz","stiffness":10})"}})
            .find("contacts.0.force: ") != std::string::npos);
  CHECK(message({{"contacts.0.detector", "\"voxel\""}, {"contacts.0.eliminator", "\"projection\""}})
            .find("contacts.0.eliminator") != std::string::npos);
  CHECK(message({{"contacts.0.detector", "\"voxel_exact\""}, {"time.integrator", "\"implicit_euler\""}})
            .find("time.integrator") != std::string::npos);
  SimulationOptions so;
  Simulation sim(load_scene(bundled("sphere_collision"), with({{"contacts.0.detector", "\"voxel\""}})), so);
  CHECK_THROWS_AS(make_device_step(sim, "tpu"), InputError);
  if (!cuda_built()) CHECK_THROWS_AS(make_device_step(sim, "cuda"), InputError);
}
