#include "experiments/bench.hpp"
#include "experiments/device_run.hpp"

#include "core/clock.hpp"
#include "core/collision/detectors/hash.hpp"
#include "core/collision/detectors/voxel.hpp"
#include "core/collision/detectors/voxel_exact.hpp"
#include "core/cpu.hpp"
#include "core/parallel.hpp"
#include "core/scene/scene.hpp"
#include "core/run/recorder.hpp"
#include "core/simd/kernels.hpp"
#include "core/simulation.hpp"
#include "core/spring_forces.hpp"

#ifdef HARNESS_HAVE_REFERENCE
#include "reference/reference.hpp"
#endif

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstring>
#include <functional>
#include <map>

#if defined(__x86_64__) && defined(__GNUC__)
#include <immintrin.h>
#endif
#include <memory>
#include <stdexcept>
#include <string>

#ifdef _OPENMP
#include <omp.h>
#endif

namespace harness {

double median_of(std::vector<double> v) {
  std::sort(v.begin(), v.end());
  const std::size_t n = v.size();
  return n % 2 ? v[n / 2] : 0.5 * (v[n / 2 - 1] + v[n / 2]);
}

// The generated contact scene of about n nodes per body (bench.hpp).
Scene make_bench_scene(long long n, bool scene_laws) {
  using nlohmann::json;
  const double s = 1e-3;  // host lattice spacing, m
  const int a = std::max(4, static_cast<int>(std::lround(std::cbrt(4.0 * static_cast<double>(n)))) - 1);
  const int c = std::max(2, static_cast<int>(std::lround(a / 4.0)));
  const int seg = std::max(8, static_cast<int>(std::lround(std::sqrt(static_cast<double>(n)))));
  const int rings = std::max(1, static_cast<int>(std::lround(static_cast<double>(n - 2) / seg)) - 1);
  const double W = a * s, D = c * s;
  const double pi = std::acos(-1.0);
  const double R = 0.15 * W, len = 2.0 * pi * R;  // guest cylinder: square cells
  const double zc = D + 0.8 * R - 0.0173 * s;     // lowest 0.2 R inside the layer
  const json mat = scene_laws ? json{{"density", 1000}, {"stiffness", 100}, {"law", "exponential"}, {"nonlinearity", 3.0},
                                      {"damping", 0.0005}, {"mass_damping", 20}}
                              : json{{"density", 1000}, {"stiffness", 100}, {"law", "cubic"}, {"nonlinearity", 2.0}};
  const json effects = scene_laws ? json{"springs", "damping", "gravity", "pins", "contact"}
                                  : json{"springs", "pins", "contact"};
  json doc = {
      {"name", "bench_" + std::to_string(n)},
      {"time", {{"dt", 1e-6}, {"steps", 0}}},
      {"effects", effects},
      {"bodies",
       {{{"name", "layer"},
         {"shape", {{"type", "box"}, {"min", {-0.5 * W, -0.5 * W, 0.0}}, {"max", {0.5 * W, 0.5 * W, D}},
                    {"cells", {a, a, c}}}},
         {"material", mat},
         {"pins", {{{"side", "-z"}}}}},
        {{"name", "shell"},
         {"shape", {{"type", "cylinder"}, {"center", {0.3137 * s, -0.1171 * s, zc}}, {"axis", {1, 0, 0}},
                    {"radius", R}, {"length", len}, {"segments", seg}, {"rings", rings}, {"fill", "shell"}}},
         {"material", mat}}}},
      {"contacts",
       {{{"host", "layer"}, {"guest", "shell"}, {"detector", "voxel"}, {"region", "half"},
         {"margin", 1}, {"eliminator", "line"}, {"force", 1e-4}}}},
      {"references", {{"solvers", json::array()}}}};
  return scene_from_json(doc, "bench_" + std::to_string(n), ".");
}


namespace {

using nlohmann::json;

double seconds_since(Clock::time_point t0) {
  return std::chrono::duration<double>(Clock::now() - t0).count();
}

struct Row {
  std::string method;
  long long nodes = 0;
  int threads = 1;
  double us = 0.0;
  long long bytes = 0;
  int reps = 0;
  std::string note;
};

// One timed variant: a function (one repetition), the thread count it runs with, and what runs
// untimed before every call (may be empty).
struct Timed {
  std::function<void()> fn;
  int threads = 1;
  std::function<void()> reset;
};

// Median times of each variant's fn in microseconds, the variants taking turns repetition by
// repetition: a slow phase of the shared machine then hits every variant alike, and the ratios of
// these medians (speed-ups, the audit's share) hold. One warm-up call per variant; when a first
// call takes longer than `single` seconds, the first calls are the measurements (reps = 1).
std::vector<double> time_steps(const std::vector<Timed>& v, const BenchOptions& o, double single,
                               std::vector<int>& reps) {
  const std::size_t K = v.size();
  if (K == 0) return {};
  std::vector<std::vector<double>> t(K);
  std::vector<double> out(K);
  reps.assign(K, 1);
  bool slow = false;
  auto call = [&](std::size_t c) {
    set_threads(v[c].threads);
    if (v[c].reset) v[c].reset();
    const auto t0 = Clock::now();
    v[c].fn();
    return seconds_since(t0) * 1e6;
  };
  for (std::size_t c = 0; c < K; ++c) {
    out[c] = call(c);
    slow = slow || out[c] > single * 1e6;
  }
  if (slow) return out;
  const auto start = Clock::now();
  while (static_cast<int>(t[0].size()) < o.min_reps || seconds_since(start) < o.min_seconds * static_cast<double>(K)) {
    for (std::size_t c = 0; c < K; ++c) t[c].push_back(call(c));
    if (t[0].size() >= 200000) break;
  }
  for (std::size_t c = 0; c < K; ++c) {
    reps[c] = static_cast<int>(t[c].size());
    out[c] = median_of(t[c]);
  }
  return out;
}

// Streaming passes (bench.hpp). Bits are summed as integers: exact, and the compiler cannot drop
// the loads. Four independent sums (AVX2 where the processor has it), so that the loop, not a
// chain of additions, is never what limits a pass over data in cache: the bound stays a bound.
// Words of any type read through a type that may alias it.
typedef std::uint64_t word_t __attribute__((may_alias));

std::uint64_t sum_words_scalar(const word_t* p, std::size_t n) {
  std::uint64_t s0 = 0, s1 = 0, s2 = 0, s3 = 0;
  std::size_t i = 0;
  for (; i + 4 <= n; i += 4) s0 += p[i], s1 += p[i + 1], s2 += p[i + 2], s3 += p[i + 3];
  for (; i < n; ++i) s0 += p[i];
  return (s0 + s1) + (s2 + s3);
}

#if defined(__x86_64__) && defined(__GNUC__)
__attribute__((target("avx2"))) std::uint64_t sum_words_avx2(const word_t* p, std::size_t n) {
  __m256i a = _mm256_setzero_si256(), b = a, c = a, d = a;
  std::size_t i = 0;
  for (; i + 16 <= n; i += 16) {
    a = _mm256_add_epi64(a, _mm256_loadu_si256(reinterpret_cast<const __m256i*>(p + i)));
    b = _mm256_add_epi64(b, _mm256_loadu_si256(reinterpret_cast<const __m256i*>(p + i + 4)));
    c = _mm256_add_epi64(c, _mm256_loadu_si256(reinterpret_cast<const __m256i*>(p + i + 8)));
    d = _mm256_add_epi64(d, _mm256_loadu_si256(reinterpret_cast<const __m256i*>(p + i + 12)));
  }
  alignas(32) std::uint64_t lanes[4];
  _mm256_store_si256(reinterpret_cast<__m256i*>(lanes), _mm256_add_epi64(_mm256_add_epi64(a, b), _mm256_add_epi64(c, d)));
  _mm256_zeroupper();
  return lanes[0] + lanes[1] + lanes[2] + lanes[3] + sum_words_scalar(p + i, n - i);
}
#endif

std::uint64_t sum_words(const void* data, std::size_t n) {
  const auto* p = static_cast<const word_t*>(data);
#if defined(__x86_64__) && defined(__GNUC__)
  if (isa() >= Isa::avx2) return sum_words_avx2(p, n);
#endif
  return sum_words_scalar(p, n);
}

__attribute__((noinline)) std::uint64_t stream_positions(const World& w) {
  const std::size_t words = 3 * w.x.size();
  const double* p = w.x.data()->data();
  const int T = threads_for(words / 3);
  std::uint64_t total = 0;
#pragma omp parallel for num_threads(T) schedule(static, 1) reduction(+ : total)
  for (int t = 0; t < T; ++t) {
    std::size_t b, e;
    split_range(words, T, t, b, e);
    total += sum_words(p + b, e - b);
  }
  return total;
}

__attribute__((noinline)) std::uint64_t stream_step(World& w) {
  const std::size_t ns = w.springs.size(), n = w.x.size();
  const Edge* ends = w.springs.ends.data();
  const double* rest = w.springs.rest.data();
  const int T = threads_for(n);
  std::uint64_t total = 0;
#pragma omp parallel num_threads(T) reduction(+ : total)
  {
    int t = 0;
#ifdef _OPENMP
    t = omp_get_thread_num();
#endif
    std::size_t b, e;
    split_range(ns, T, t, b, e);
    // Springs: rest lengths and ends (two ints, one word) summed as words.
    static_assert(sizeof(Edge) == sizeof(std::uint64_t), "an edge is two ints");
    std::uint64_t sum = sum_words(rest + b, e - b) + sum_words(ends + b, e - b);
    split_range(n, T, t, b, e);
    const double h = 0.0;  // leaves the state as it is, but every value is read and written
    for (std::size_t i = b; i < e; ++i) {
      if (w.kinematic[i] != Kinematic::free) continue;
      w.v[i] += (h * w.inv_m[i]) * w.f[i];
      w.x[i] += h * w.v[i];
    }
    total += sum;
  }
  return total;
}

// Sum over the T parts of n items (split_range) of part(begin, end), one thread each; T as the
// streaming passes take it (threads_for of the node count).
template <class Part>
double split_sum(const World& w, std::size_t n, Part&& part) {
  const int T = threads_for(w.x.size());
  double total = 0.0;
#pragma omp parallel num_threads(T) reduction(+ : total)
  {
    int t = 0;
#ifdef _OPENMP
    t = omp_get_thread_num();
#endif
    std::size_t b, e;
    split_range(n, T, t, b, e);
    total += part(b, e);
  }
  return total;
}

// The force pass's arithmetic floor: one square root and one division per spring (of its rest
// length) in the pass's lanes, the springs split over the threads as stream_step splits them.
__attribute__((noinline)) double arith_floor(const World& w) {
  const double* rest = w.springs.rest.data();
  const simd::Kernels& k = simd::kernels();
  return split_sum(w, w.springs.size(), [&](std::size_t b, std::size_t e) { return k.sqrt_div(rest + b, e - b); });
}

// The force pass's floor: both ends of every spring read as the pass reads them (the node-sorted
// upper half-edges), one square root and one division each; the half-edges split over the threads.
__attribute__((noinline)) double pass_floor(const World& w, const SpringGather& g) {
  const double* x = w.x.data()->data();
  const simd::Kernels& k = simd::kernels();
  return split_sum(w, static_cast<std::size_t>(g.up_start[g.nodes]), [&](std::size_t b, std::size_t e) {
    return k.pass_floor(x, g.up_self.data() + b, g.up_other.data() + b, e - b);
  });
}

}  // namespace

const std::vector<std::string>& bench_methods() {
  static const std::vector<std::string> names = {"voxel_detect", "voxel_detect_eliminate", "voxel_exact_detect",
                                                 "voxel_exact_detect_eliminate", "hash_detect",
                                                 "hash_detect_cell_x0.5", "hash_detect_cell_x2", "hash_detect_cell_x4",
                                                 "stream_positions", "step", "step_audited", "stream_step", "arith_floor", "pass_floor",
                                                 "step_order_scene", "step_order_rcm", "step_order_morton",
                                                 "step_shuffled_order_scene", "step_shuffled_order_rcm",
                                                 "step_shuffled_order_morton", "step_scene_laws", "fcl", "cgal",
                                                 "bullet_collide"};
  return names;
}

namespace {

// One size of the bench: the scene of n nodes per body and its rows, written as they are timed.
class BenchSize {
 public:
  BenchSize(long long n, const BenchOptions& opt, std::FILE* out) : n_(n), opt_(opt), out_(out) {
    SimulationOptions so;
    so.audit = false;  // the step as the kernels take it (the energy audit only reads the state)
    const auto tb = Clock::now();
    sim_ = std::make_unique<Simulation>(make_bench_scene(n), so);
    World& w = sim_->world();
    if (opt.progress)
      std::fprintf(stderr, "bench: %lld nodes per body: built in %.1f s (%d + %d nodes, %zu springs)\n", n,
                   seconds_since(tb), w.bodies[0].size(), w.bodies[1].size(), w.springs.size());
    col_ = sim_->pairs().at(0).collision.get();
    contacts_ = col_->detect(w);
    const auto& vd = dynamic_cast<const VoxelDetector&>(col_->detector());
    voxels_ = vd.grid().geometry().num_voxels();
    grid_bytes_ = vd.grid().bytes();
  }

  void core_rows() {
    World& w = sim_->world();
    volatile std::uint64_t sink = 0;
    const long long node_bytes = 24LL * w.num_nodes();
    const long long step_bytes = 16LL * static_cast<long long>(w.springs.size()) +
                                 (24 * 3 + 8 + 1 + 2 * 24) * static_cast<long long>(w.num_nodes());
    const std::vector<int>& T = opt_.threads;
    measure("voxel_detect", T, [&] { col_->detect(w); }, grid_bytes_, "grid bytes");
    measure("voxel_detect_eliminate", T, [&] { col_->step(w, sim_->scene().dt); }, grid_bytes_, "grid bytes");
    measure("stream_positions", T, [&] { sink = sink + stream_positions(w); }, node_bytes, "bytes read");
    // stream_step first: the step's rows carry their ratio to it (the same thread count, this run).
    measure("stream_step", T, [&] { sink = sink + stream_step(w); }, step_bytes, "bytes read and written");
    volatile double fsink = 0.0;
    measure("arith_floor", T, [&] { fsink = fsink + arith_floor(w); }, 8LL * static_cast<long long>(w.springs.size()),
            "one square root and one division per spring (force pass lanes)");
    SpringGather gather;
    gather.build(w);
    measure("pass_floor", T, [&] { fsink = fsink + pass_floor(w, gather); },
            8LL * static_cast<long long>(w.springs.size()) + node_bytes,
            "both ends of every spring loaded as the force pass loads them; one square root and one division");
    if (wanted("step") || wanted("step_audited")) {
      // Steps move the bodies (the penalties push the guest out: fewer contacts, a faster step):
      // every repetition starts from the initial state (restored untimed), the one every other
      // row is timed on, so the figure does not depend on how many repetitions there were. A
      // repetition is kEvery steps (one stability check each, as in a run), divided by their
      // number: the step's cost with its periodic guard, not the median step without it. Before
      // each repetition (untimed) one step on the repetition's thread count, then the initial
      // state again: the variants take turns, and a step's data left in other threads' caches by
      // the last one would otherwise be charged to the first timed step (a run keeps one count).
      // step_audited: the same step with the energy audit a run keeps (work, kinetic energy and
      // residual in the update pass every step; the springs' energy read, as the recorder reads
      // it, on the steps kEnergyEvery divides, from those steps' force pass); the two take turns
      // too, so that their ratio, the audit's share, is measured side by side.
      SimulationOptions so;
      so.audit = true;
      Simulation audited(sim_->scene(), so);
      audited.energy_read_every(kEnergyEvery);  // as a run's recorder tells it
      static_assert(kEnergyEvery % StabilityGuard::kEvery == 0 || StabilityGuard::kEvery % kEnergyEvery == 0);
      const std::string reps = "; repetitions of " + std::to_string(StabilityGuard::kEvery) +
                               " steps (one stability check) after an untimed step on their thread count";
      Method plain{"step", [&] {
                     for (int k = 0; k < StabilityGuard::kEvery; ++k) sim_->step();
                   }, starter(*sim_), "per step from the initial state" + reps};
      Method with_audit{"step_audited", [&] {
                          for (int k = 0; k < StabilityGuard::kEvery; ++k) {
                            audited.step();
                            if (audited.step_index() % kEnergyEvery == 0) (void)audited.energy();
                          }
                        }, starter(audited),
                        "per step with the energy audit (the springs' energy read every " +
                            std::to_string(kEnergyEvery) + " steps) from the initial state" + reps};
      const Points x0 = w.x, v0 = w.v;
      measure_together(plain, with_audit, T, 0, StabilityGuard::kEvery);
      std::copy(x0.begin(), x0.end(), w.x.begin());
      std::copy(v0.begin(), v0.end(), w.v.begin());
    }
  }

  // The node order (node_order.hpp) against the step row's (kDefaultNodeOrder): the same scene laid
  // out in another order, and with its nodes first shuffled (each body's surface and interior apart:
  // a mesh file's arbitrary numbering) then laid out in each order. Each variant is timed side by
  // side with the default layout's step (their repetitions taking turns, one thread), and its row's
  // note gives their ratio: a slow phase of the machine does not decide it. One variant's world at a
  // time (at 10^6 nodes per body a world and its force pass take gigabytes).
  void order_rows() {
    struct Variant {
      NodeOrder order;
      unsigned long long seed;
    };
    std::vector<Variant> variants;
    for (NodeOrder o : {NodeOrder::scene, NodeOrder::rcm, NodeOrder::morton})
      if (o != kDefaultNodeOrder) variants.push_back({o, 0});
    for (NodeOrder o : {NodeOrder::scene, NodeOrder::rcm, NodeOrder::morton}) variants.push_back({o, 20261127});
    const std::string reps = "; repetitions of " + std::to_string(StabilityGuard::kEvery) +
                             " steps after an untimed step on one thread taking turns with the step row's layout (" +
                             node_order_name(kDefaultNodeOrder) + ")";
    for (const Variant& v : variants) {
      const std::string name = std::string(v.seed ? "step_shuffled_order_" : "step_order_") + node_order_name(v.order);
      if (!wanted(name)) continue;
      SimulationOptions so;
      so.audit = false;
      so.layout.order = v.order;
      so.layout.shuffle_seed = v.seed;
      Simulation other(sim_->scene(), so);
      const Points x0 = sim_->world().x, v0 = sim_->world().v;
      std::vector<Timed> t = {{[&] { for (int k = 0; k < StabilityGuard::kEvery; ++k) sim_->step(); }, 1, starter(*sim_)},
                              {[&] { for (int k = 0; k < StabilityGuard::kEvery; ++k) other.step(); }, 1, starter(other)}};
      std::vector<int> nrep;
      const std::vector<double> us = time_steps(t, opt_, 1e30, nrep);
      std::copy(x0.begin(), x0.end(), sim_->world().x.begin());
      std::copy(v0.begin(), v0.end(), sim_->world().v.begin());
      char ratio[160];
      std::snprintf(ratio, sizeof ratio, "; %.3f x the step row's layout side by side (%.1f against %.1f us)",
                    us[1] / us[0], us[1] / StabilityGuard::kEvery, us[0] / StabilityGuard::kEvery);
      emit_row(name, 1, us[1] / StabilityGuard::kEvery, nrep[1], 0,
               std::string("per step from the initial state; nodes ") + (v.seed ? "shuffled then " : "") + "laid out in " +
                   node_order_name(v.order) + " order" + reps + ratio);
    }
  }

  // The step on what users run (make_bench_scene's scene_laws: the bundled scenes' exponential law,
  // dashpots, mass damping and gravity) on the same lattice, timed side by side with the step row
  // (repetitions taking turns, one thread, each from its initial state); its row's note gives their
  // ratio and its ns_per_spring is set against pass_floor like the step's (tables/bench.md).
  void scene_laws_row() {
    if (!wanted("step_scene_laws")) return;
    SimulationOptions so;
    so.audit = false;
    Simulation laws(make_bench_scene(n_, true), so);
    const Points x0 = sim_->world().x, v0 = sim_->world().v;
    std::vector<Timed> t = {{[&] { for (int k = 0; k < StabilityGuard::kEvery; ++k) sim_->step(); }, 1, starter(*sim_)},
                            {[&] { for (int k = 0; k < StabilityGuard::kEvery; ++k) laws.step(); }, 1, starter(laws)}};
    std::vector<int> nrep;
    const std::vector<double> us = time_steps(t, opt_, 1e30, nrep);
    std::copy(x0.begin(), x0.end(), sim_->world().x.begin());
    std::copy(v0.begin(), v0.end(), sim_->world().v.begin());
    char ratio[200];
    std::snprintf(ratio, sizeof ratio, "; %.3f x the step row side by side (%.1f against %.1f us)", us[1] / us[0],
                  us[1] / StabilityGuard::kEvery, us[0] / StabilityGuard::kEvery);
    emit_row("step_scene_laws", 1, us[1] / StabilityGuard::kEvery, nrep[1], 0,
             std::string("per step from the initial state with the bundled scenes' law and effects (exponential "
                         "law of nonlinearity 3; dashpots 0.0005; mass damping 20; gravity); repetitions of ") +
                 std::to_string(StabilityGuard::kEvery) + " steps taking turns with the step row" + ratio);
  }

  // The paper's grid with the exact narrow phase (detectors/voxel_exact.hpp) on the same state and
  // pair: its own automatic voxel size (the paper's unless the band would not be positive), the
  // scene's line eliminator and constant force for the eliminate row.
  void voxel_exact_rows() {
    if (!wanted("voxel_exact_detect") && !wanted("voxel_exact_detect_eliminate")) return;
    World& w = sim_->world();
    ContactSpec spec = sim_->pairs().at(0).spec;
    spec.detector = "voxel_exact";
    Collision c(w, spec);
    const int found = c.detect(w);
    const auto& d = dynamic_cast<const VoxelExactDetector&>(c.detector());
    char note[160];
    std::snprintf(note, sizeof note, "grid bytes; voxel %.3g mm; %d contacts (%d beyond the band); L_max %.3g mm",
                  1e3 * d.voxel_size(), found, d.beyond_band(), 1e3 * d.longest_edge());
    const std::vector<int>& T = opt_.threads;
    measure("voxel_exact_detect", T, [&] { c.detect(w); }, d.grid().bytes(), note);
    measure("voxel_exact_detect_eliminate", T, [&] { c.step(w, sim_->scene().dt); }, d.grid().bytes(), note);
  }

  // Spatial hashing (detectors/hash.hpp) on the same state and pair: the automatic cell (hash_detect)
  // and the cell swept to 0.5, 2 and 4 times it. One thread (the detector is serial).
  void hash_rows() {
    set_threads(1);
    World& w = sim_->world();
    ContactSpec spec = sim_->pairs().at(0).spec;
    spec.detector = "hash";
    spec.cell_size = 0.0;
    const Collision automatic(w, spec);
    const double cell = dynamic_cast<const HashDetector&>(automatic.detector()).cell_size();
    for (const auto& [method, f] : {std::pair<const char*, double>{"hash_detect", 1.0}, {"hash_detect_cell_x0.5", 0.5},
                                    {"hash_detect_cell_x2", 2.0}, {"hash_detect_cell_x4", 4.0}}) {
      if (!wanted(method)) continue;
      spec.cell_size = f * cell;
      Collision c(w, spec);
      char note[96];
      std::snprintf(note, sizeof note, "cell %.3g mm (%g x the automatic %.3g mm); single-threaded", 1e3 * spec.cell_size,
                    f, 1e3 * cell);
      measure(method, {1}, [&] { c.detect(w); }, 0, note);
    }
  }

  void reference_rows() {
#ifdef HARNESS_HAVE_REFERENCE
    World& w = sim_->world();
    const Body& host = w.bodies[0];
    const Body& guest = w.bodies[1];
    volatile std::uint64_t sink = 0;
    if (wanted("fcl")) {
      FclSurface a, b;
      a.set_topology(host.n_surface, host.faces);
      b.set_topology(guest.n_surface, guest.faces);
      std::vector<TrianglePair> pairs;
      measure("fcl", {1}, [&] {
        a.update(&w.x[host.begin]);
        b.update(&w.x[guest.begin]);
        intersecting_pairs(a, b, pairs, false);
        sink = sink + pairs.size();
      }, 0, "refit + all triangle pairs; single-threaded library", opt_.single_rep_seconds);
    }
    if (wanted("cgal")) {
      CgalSurface s;
      s.set_topology(host.n_surface, host.faces);
      measure("cgal", {1}, [&] {
        s.update(&w.x[host.begin]);
        int inside = 0;
        for (int i = guest.begin; i < guest.end; ++i) inside += s.strictly_inside(w.x[i]);
        sink = sink + static_cast<std::uint64_t>(inside);
      }, 0, "tree rebuild + inside test of every guest node; single-threaded library", opt_.single_rep_seconds);
    }
    if (wanted("bullet_collide")) {
      const auto tb = Clock::now();
      BulletCollisionBench bullet(w, 0, 1);
      char note[160];
      std::snprintf(note, sizeof note, "tree refit (predictMotion at rest) + VF_SS pass; margins 0.05 x mean surface "
                    "edge; face trees inserted; single-threaded library; built in %.1f s", seconds_since(tb));
      measure("bullet_collide", {1}, [&] { sink = sink + static_cast<std::uint64_t>(bullet.collide()); }, 0, note,
              opt_.single_rep_seconds);
    }
#endif
  }

 private:
  // An untimed reset before each repetition: the initial state, one step on the repetition's
  // thread count (its data then sits in that count's caches), the initial state again.
  static std::function<void()> starter(Simulation& sim) {
    World& sw = sim.world();
    auto x0 = std::make_shared<Points>(sw.x), v0 = std::make_shared<Points>(sw.v);
    return [&sim, x0, v0] {
      for (int pass = 0; pass < 2; ++pass) {
        std::copy(x0->begin(), x0->end(), sim.world().x.begin());
        std::copy(v0->begin(), v0->end(), sim.world().v.begin());
        if (pass == 0) sim.step();
      }
    };
  }
  bool wanted(const std::string& m) const {
    return opt_.methods.empty() || std::find(opt_.methods.begin(), opt_.methods.end(), m) != opt_.methods.end();
  }
  void emit(const Row& r) {
    const World& w = sim_->world();
    // ns per spring (the step's and the stream's: how far the step is from the pass over its data)
    // and, for the step, its ratio to stream_step of the same run and thread count.
    const double ns_spring = 1e3 * r.us / static_cast<double>(std::max<std::size_t>(1, w.springs.size()));
    if (r.method == "stream_step") stream_us_[r.threads] = r.us;
    char ratio[32] = "";
    if ((r.method == "step" || r.method == "step_audited") && stream_us_.count(r.threads) && stream_us_[r.threads] > 0.0)
      std::snprintf(ratio, sizeof ratio, "%.3f", r.us / stream_us_[r.threads]);
    // The note quoted (it may hold commas); the device and the machine, read from the system.
    std::fprintf(out_, "%s,%lld,%d,%.3f,%lld,%d,%d,%d,%zu,%d,%lld,\"%s\",%.4f,%s,cpu,\"%s\"\n", r.method.c_str(), r.nodes,
                 r.threads, r.us, r.bytes, r.reps, w.bodies[0].size(), w.bodies[1].size(), w.springs.size(), contacts_,
                 voxels_, r.note.c_str(), ns_spring, ratio, machine_.c_str());
    std::fflush(out_);
    if (opt_.progress)
      std::fprintf(stderr, "bench: %-22s %8lld nodes %d thr %14.1f us/step (%d reps)\n", r.method.c_str(), r.nodes,
                   r.threads, r.us, r.reps);
  }
  // One row per thread count of `counts` (time_steps: the counts take turns).
  // `reset` (untimed) runs before every timed call.
  void measure(const std::string& method, const std::vector<int>& counts, const std::function<void()>& fn,
               long long bytes, const std::string& note, double single = 1e30, int per_rep = 1,
               const std::function<void()>& reset = {}) {
    if (!wanted(method)) return;
    std::vector<Timed> v;
    for (int c : counts) v.push_back({fn, c, reset});
    std::vector<int> reps;
    const std::vector<double> us = time_steps(v, opt_, single, reps);
    for (std::size_t c = 0; c < counts.size(); ++c) emit_row(method, counts[c], us[c] / per_rep, reps[c], bytes, note);
  }
  // Two methods measured together, their repetitions (and thread counts) taking turns: rows for a
  // ratio of the two that a slow phase of the machine does not decide (step_audited / step).
  struct Method {
    std::string name;
    std::function<void()> fn, reset;
    std::string note;
  };
  void measure_together(const Method& a, const Method& b, const std::vector<int>& counts, long long bytes,
                        int per_rep) {
    std::vector<Timed> v;
    const bool wa = wanted(a.name), wb = wanted(b.name);
    for (int c : counts) {
      if (wa) v.push_back({a.fn, c, a.reset});
      if (wb) v.push_back({b.fn, c, b.reset});
    }
    if (v.empty()) return;
    std::vector<int> reps;
    std::vector<double> us = time_steps(v, opt_, 1e30, reps);
    std::size_t k = 0;
    for (int c : counts) {
      for (const Method* m : {&a, &b}) {
        if (!wanted(m->name)) continue;
        emit_row(m->name, c, us[k] / per_rep, reps[k], bytes, m->note);
        ++k;
      }
    }
  }
  void emit_row(const std::string& method, int threads, double us, int reps, long long bytes, const std::string& note) {
    Row r;
    r.method = method;
    r.nodes = n_;
    r.threads = threads;
    r.bytes = bytes;
    r.note = note;
    r.us = us;
    r.reps = reps;
    emit(r);
  }

  long long n_;
  const BenchOptions& opt_;
  std::FILE* out_;
  std::unique_ptr<Simulation> sim_;
  Collision* col_ = nullptr;
  int contacts_ = 0;
  long long voxels_ = 0, grid_bytes_ = 0;
  std::map<int, double> stream_us_;
  std::string machine_ = machine_string();  // stream_step's time per thread count, this size
};

}  // namespace

int run_bench(const BenchOptions& opt) {
  std::vector<long long> sizes = opt.sizes;
  if (sizes.empty()) {
    sizes = {1000, 10000, 100000};
    if (!opt.quick) sizes.push_back(1000000);
  }
  std::FILE* out = std::fopen(opt.out.c_str(), "w");
  if (!out) throw std::runtime_error("cannot write " + opt.out);
  std::fprintf(out,
               "method,nodes,threads,us_per_step,bytes,reps,host_nodes,guest_nodes,springs,contacts,voxels,note,"
               "ns_per_spring,step_over_stream,device,machine\n");
  std::fflush(out);
  const int threads_before = threads();
  for (long long n : sizes) {
    BenchSize b(n, opt, out);
    b.core_rows();
    b.order_rows();
    b.scene_laws_row();
    b.voxel_exact_rows();
    set_threads(1);
    if (opt.references) b.reference_rows();
    b.hash_rows();  // last: its large tables (0.5x cells at 10^6 nodes) must not disturb the others' timings
  }
  set_threads(threads_before);
  const bool ok = std::ferror(out) == 0;
  if (std::fclose(out) != 0 || !ok) throw std::runtime_error("cannot write " + opt.out);
  return 0;
}

}  // namespace harness
