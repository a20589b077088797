#include "experiments/device_run.hpp"

#include "core/clock.hpp"
#include "core/device/device_step.hpp"
#include "core/run/machine.hpp"
#include "core/run/output_dir.hpp"
#include "core/run/step_stats.hpp"
#include "core/state_hash.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <numeric>
#include <string>
#include <thread>
#include <vector>

namespace harness {

namespace {

void write_json(const std::string& path, const nlohmann::json& j) {
  const std::string tmp = path + ".tmp";
  {
    std::ofstream o(tmp);
    o << j.dump(2) << "\n";
  }
  std::filesystem::rename(tmp, path);
}

// The step times' record (mean, median, p99, max) and the real-time factors against the scene's dt.
void add_timing(nlohmann::json& j, const std::vector<double>& us, double dt) {
  const StepStats st = step_stats(us);
  auto zero_nan = [](double v) { return std::isfinite(v) ? v : 0.0; };
  j["timing_us"] = {{"mean", zero_nan(st.mean)},
                    {"median", zero_nan(st.median)},
                    {"p99", zero_nan(st.p99)},
                    {"max", zero_nan(st.max)},
                    {"steps_timed", st.n},
                    {"what", "per step, each step waited for (graph launch to completion)"}};
  j["budget_us"] = dt * 1e6;
  j["realtime_factor_mean"] = zero_nan(realtime_factor(dt, st.mean));
  j["realtime_factor_p99"] = zero_nan(realtime_factor(dt, st.p99));
}

// The CPU's own step over the same steps from the same start (a fresh Simulation), against the
// device's final state.
nlohmann::json cpu_check(const Scene& scene, const SimulationOptions& so, const World& device_state, int steps) {
  Simulation cpu(scene, so);
  const auto t0 = Clock::now();
  for (int k = 0; k < steps; ++k) cpu.step();
  const double cpu_s = us_since(t0) * 1e-6;
  double dmax = 0.0, vmax = 0.0;
  bool identical = true;
  for (int i = 0; i < cpu.world().num_nodes(); ++i) {
    dmax = std::max(dmax, (cpu.world().x[i] - device_state.x[i]).norm());
    vmax = std::max(vmax, (cpu.world().v[i] - device_state.v[i]).norm());
    identical = identical && cpu.world().x[i] == device_state.x[i] && cpu.world().v[i] == device_state.v[i];
  }
  return {{"steps", steps},
          {"max_node_distance_m", dmax},
          {"max_velocity_difference_m_s", vmax},
          {"bit_identical", identical},
          {"cpu_state_hash", state_hash(cpu.world())},
          {"cpu_us_per_step", 1e6 * cpu_s / std::max(1, steps)}};
}

// DIR/state.csv: every node's position and velocity, 17 digits.
void write_state(const std::string& path, const World& w) {
  std::ofstream st(path);
  st << "node,x,y,z,vx,vy,vz\n";
  st.precision(17);
  for (int i = 0; i < w.num_nodes(); ++i) {
    const Vec3 &x = w.x[i], &v = w.v[i];
    st << i << ',' << x[0] << ',' << x[1] << ',' << x[2] << ',' << v[0] << ',' << v[1] << ',' << v[2] << '\n';
  }
}

}  // namespace

int run_on_device(const Scene& scene, const DeviceRunOptions& o) {
  SimulationOptions so;
  so.exact_detectors = o.exact_detectors;
  so.audit = false;
  so.layout.order = NodeOrder::scene;  // state.csv lists the world's nodes: the scene's numbering
  Simulation sim(scene, so);
  std::unique_ptr<DeviceStep> dev = make_device_step(sim, o.device);  // InputError: exit 2, nothing written
  std::filesystem::create_directories(o.out_dir);
  const int steps = scene.steps;
  nlohmann::json j;
  j["scene"] = scene.name;
  j["device"] = dev->device_name();
  j["machine"] = machine_info();
  j["threads"] = 1;
  j["dt"] = scene.dt;
  j["steps_requested"] = steps;
  j["not_on_device"] = {"energy audit", "settling (time.settle)", "periodic stability check", "measurements (references)"};
  std::vector<double> us;
  us.reserve(static_cast<std::size_t>(std::max(steps, 0)));
  std::string status = "ok", error;
  int code = 0;
  try {
    dev->step(3);  // untimed: the first launches load the kernels
    dev->synchronize();
    for (int k = 3; k < steps; ++k) {
      const auto t0 = Clock::now();
      dev->step(1);
      dev->synchronize();
      us.push_back(us_since(t0));
      if (o.progress && (k + 1) % 1000 == 0) std::fprintf(stderr, "\rdevice: step %d / %d", k + 1, steps);
    }
    if (o.progress) std::fprintf(stderr, "\n");
    dev->download(sim.world());
  } catch (const std::runtime_error& e) {
    status = "error", error = e.what(), code = 3;
  }
  j["status"] = status;
  j["error"] = error;
  j["steps_run"] = dev->steps_taken();
  add_timing(j, us, scene.dt);
  nlohmann::json pairs = nlohmann::json::array();
  if (code == 0)
    for (std::size_t p = 0; p < sim.pairs().size(); ++p) pairs.push_back({{"pair", sim.pairs()[p].label}, {"contacts_last", dev->contacts(static_cast<int>(p))}});
  j["pairs"] = pairs;
  j["state_hash"] = state_hash(sim.world());
  if (o.check_cpu && code == 0) j["cpu_check"] = cpu_check(scene, so, sim.world(), dev->steps_taken());
  write_state(o.out_dir + "/state.csv", sim.world());
  write_json(o.out_dir + "/summary.json", j);
  std::fprintf(stderr, "device %s: %s, %d steps, %.2f us/step mean, %.2f p99, real-time factor %.3f (mean) %.3f (p99)%s\n",
               dev->device_name().c_str(), status.c_str(), dev->steps_taken(), j["timing_us"]["mean"].get<double>(),
               j["timing_us"]["p99"].get<double>(), j["realtime_factor_mean"].get<double>(), j["realtime_factor_p99"].get<double>(),
               j.contains("cpu_check") ? (", cpu max node distance " + std::to_string(j["cpu_check"]["max_node_distance_m"].get<double>()) + " m").c_str() : "");
  return code;
}

}  // namespace harness

#include "experiments/bench.hpp"

namespace harness {

int run_device_bench(const BenchOptions& o) {
  std::vector<long long> sizes = o.sizes;
  if (sizes.empty()) sizes = {1000, 10000, 100000, 1000000, 10000000};
  std::FILE* out = std::fopen(o.out.c_str(), "w");
  if (!out) throw InputError(o.out, "cannot write the bench CSV");
  std::fprintf(out, "method,nodes,threads,us_per_step,bytes,reps,host_nodes,guest_nodes,springs,contacts,voxels,note,"
                    "ns_per_spring,step_over_stream,device,machine\n");
  const std::string machine = machine_string();
  for (long long n : sizes) {
    const auto tb = Clock::now();
    SimulationOptions so;
    so.audit = false;
    Simulation sim(make_bench_scene(n), so);
    const World& w = sim.world();
    std::unique_ptr<DeviceStep> dev = make_device_step(sim, o.device);
    const long long springs = static_cast<long long>(w.springs.size());
    const long long step_bytes = 16LL * springs + (24 * 3 + 8 + 1 + 2 * 24) * static_cast<long long>(w.num_nodes());
    if (o.progress)
      std::fprintf(stderr, "bench --device: %lld nodes per body: built in %.1f s (%d nodes, %lld springs) on %s\n", n,
                   us_since(tb) * 1e-6, w.num_nodes(), springs, dev->device_name().c_str());
    // Batches of K steps, each batch waited for at its end; the median batch's time per step. The
    // steps move the bodies little (dt far below the limit, as the CPU bench's).
    dev->step(5);
    dev->synchronize();
    int K = 1;
    for (;;) {  // a batch of at least ~2 ms
      const auto t0 = Clock::now();
      dev->step(K);
      dev->synchronize();
      if (us_since(t0) > 2000.0 || K >= 4096) break;
      K *= 2;
    }
    std::vector<double> per;
    const auto tr = Clock::now();
    while (per.size() < 5 || (us_since(tr) * 1e-6 < o.min_seconds && per.size() < 200)) {
      const auto t0 = Clock::now();
      dev->step(K);
      dev->synchronize();
      per.push_back(us_since(t0) / K);
    }
    std::sort(per.begin(), per.end());
    const double step_us = per[per.size() / 2];
    const double copy_us = dev->copy_us(static_cast<std::size_t>(step_bytes / 2), 20);
    const int contacts = dev->contacts(0);
    const std::string name = dev->device_name();
    std::fprintf(out, "step,%lld,1,%.4f,%lld,%zu,%d,%d,%lld,%d,,%s,%.5f,%s,\"%s\",\"%s\"\n", n, step_us, step_bytes,
                 per.size() * static_cast<std::size_t>(K), w.bodies[0].size(), w.bodies[1].size(), springs, contacts,
                 ("per step over batches of " + std::to_string(K) + " steps (CUDA graph)").c_str(),
                 1000.0 * step_us / static_cast<double>(springs),
                 copy_us > 0.0 ? std::to_string(step_us / copy_us).c_str() : "", name.c_str(), machine.c_str());
    if (copy_us > 0.0)
      std::fprintf(out, "copy,%lld,1,%.4f,%lld,21,%d,%d,%lld,,,%s,%.5f,,\"%s\",\"%s\"\n", n, copy_us, step_bytes,
                   w.bodies[0].size(), w.bodies[1].size(), springs,
                   "one device-to-device copy of half the step's bytes (reads and writes them all)",
                   1000.0 * copy_us / static_cast<double>(springs), name.c_str(), machine.c_str());
    std::fflush(out);
    if (o.progress)
      std::fprintf(stderr, "bench --device: %lld nodes: step %.2f us (%.4f ns/spring), copy %.2f us, step/copy %.2f\n", n,
                   step_us, 1000.0 * step_us / static_cast<double>(springs), copy_us, copy_us > 0 ? step_us / copy_us : 0.0);
  }
  std::fclose(out);
  return 0;
}

}  // namespace harness
