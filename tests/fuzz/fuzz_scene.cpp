// libFuzzer target: scene loading. parse_scene on arbitrary bytes (leading lines
// "#set KEY=JSON" become --set overrides), then, when the scene parses and its bodies are
// small, the Simulation is built (bodies, selections, effects, contact grids, stability
// guard). No step is run.
//
// Mesh bodies resolve relative to tests/fuzz/corpus/ (so "off/cube.off" names a seed mesh);
// paths outside it or files above 16 KB are skipped, never read.
#include "core/collision/initializer.hpp"
#include "core/scene/scene.hpp"
#include "core/simulation.hpp"
#include "tests/fuzz/fuzz_common.hpp"

#include <cmath>
#include <cstddef>
#include <cstdint>
#include <filesystem>
#include <string>
#include <utility>
#include <vector>

namespace {

namespace fs = std::filesystem;
using namespace harness;

const std::string kCorpusDir = HARNESS_SOURCE_DIR "/tests/fuzz/corpus";
const std::string kSceneFile = kCorpusDir + "/fuzz.json";

constexpr long long kMaxNodes = 20000;        // surface or lattice nodes over all bodies
constexpr long long kMaxFillSurface = 4000;   // surface nodes of a volume-filled body
constexpr double kMaxVoxels = 4e6;            // per contact grid
constexpr std::uintmax_t kMaxMeshBytes = 16384;

// Nodes a body's generator makes before any volume fill; -1 when it must not be built.
long long surface_nodes(const ShapeSpec& s) {
  if (s.type == ShapeType::box)
    return (static_cast<long long>(s.cells[0]) + 1) * (s.cells[1] + 1) * (s.cells[2] + 1);
  if (s.type == ShapeType::sphere || s.type == ShapeType::ellipsoid) {
    if (s.subdivisions < 0 || s.subdivisions > 6) return -1;
    return 10LL * (1LL << (2 * s.subdivisions)) + 2;
  }
  if (s.type == ShapeType::cylinder) return static_cast<long long>(s.segments) * (s.rings + 1) + 2;
  // mesh
  const fs::path p = fs::path(s.path).lexically_normal();
  const std::string ps = p.string();
  if (ps.compare(0, kCorpusDir.size() + 1, kCorpusDir + "/") != 0) return -1;
  std::error_code ec;
  if (!fs::is_regular_file(p, ec)) return 0;  // the loader reports it
  const std::uintmax_t size = fs::file_size(p, ec);
  if (ec || size > kMaxMeshBytes) return -1;
  return static_cast<long long>(size / 8 + 1);
}

bool within_budget(const Scene& sc) {
  long long total = 0;
  for (const BodySpec& b : sc.bodies) {
    const long long n = surface_nodes(b.shape);
    if (n < 0) return false;
    if (b.shape.volume_fill && b.shape.type != ShapeType::box && n > kMaxFillSurface) return false;
    total += n;
    if (total > kMaxNodes) return false;
  }
  return true;
}

// Voxels of each contact grid, as Initializer::build counts them (the full box, an upper bound).
bool grids_within_budget(const Simulation& sim) {
  const World& w = sim.world();
  for (const ContactPairSpec& cp : sim.scene().contacts) {
    ContactSpec spec = cp.spec;
    spec.host = w.find_body(cp.host);
    spec.guest = w.find_body(cp.guest);
    if (spec.host < 0 || spec.guest < 0) return false;
    double v = 0.0;
    try {
      v = resolve_voxel_size(w, spec);
    } catch (const std::invalid_argument&) {
      continue;  // the real build reports it
    }
    const Body& b = w.bodies[spec.host];
    double count = 1.0;
    for (int a = 0; a < 3; ++a) {
      const double half = 0.5 * (b.rest_max[a] - b.rest_min[a]);
      count *= 2.0 * (std::floor(half / v) + 2.0 + spec.margin);
    }
    if (!(count <= kMaxVoxels)) return false;
  }
  return true;
}

void check_simulation(const Simulation& sim) {
  const World& w = sim.world();
  const std::size_t n = w.x.size();
  FUZZ_CHECK(w.v.size() == n && w.m.size() == n && w.inv_m.size() == n && w.f.size() == n);
  for (std::size_t i = 0; i < n; ++i) {
    FUZZ_CHECK(w.x[i].allFinite() && w.v[i].allFinite());
    FUZZ_CHECK(w.m[i] > 0.0 && std::isfinite(w.m[i]));
  }
  for (const Edge& e : w.springs.ends)
    FUZZ_CHECK(e[0] >= 0 && e[1] >= 0 && e[0] < static_cast<int>(n) && e[1] < static_cast<int>(n));
  FUZZ_CHECK(sim.stats().stability.substeps >= 1);
  FUZZ_CHECK(sim.stats().stability.dt_crit > 0.0);
  FUZZ_CHECK(sim.pairs().size() == sim.scene().contacts.size());
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  std::string text(reinterpret_cast<const char*>(data), size);
  std::vector<std::pair<std::string, std::string>> overrides;
  std::size_t pos = 0;
  while (text.compare(pos, 5, "#set ") == 0) {
    const std::size_t nl = text.find('\n', pos);
    if (nl == std::string::npos) break;
    const std::string line = text.substr(pos + 5, nl - pos - 5);
    const std::size_t eq = line.find('=');
    if (eq == std::string::npos || eq == 0) return 0;  // the command line rejects it
    overrides.emplace_back(line.substr(0, eq), line.substr(eq + 1));
    pos = nl + 1;
  }
  text.erase(0, pos);

  Scene scene;
  try {
    scene = parse_scene(text, kSceneFile, overrides);
  } catch (const InputError& e) {
    fuzz_note(e.what());
    return 0;
  }
  // summary.json records the resolved scene: it must serialise, and read back as itself.
  (void)scene.resolved.dump(2);
  try {
    const Scene again = scene_from_json(scene.resolved, kSceneFile, scene.dir);
    FUZZ_CHECK(again.resolved == scene.resolved);
  } catch (const InputError& e) {
    std::fprintf(stderr, "fuzz invariant failed: the resolved scene is rejected: %s\n", e.what());
    std::abort();
  }
  if (!within_budget(scene)) {
    fuzz_note("parsed; over the fuzz node budget, not built");
    return 0;
  }
  try {
    if (scene.has(kContact) && !scene.contacts.empty()) {
      // Bodies first (no contact, no guard) to size the grids before building them.
      Scene bodies_only = scene;
      bodies_only.effects &= ~static_cast<unsigned>(kContact);
      bodies_only.integrator = Integrator::implicit_euler;
      const Simulation probe(bodies_only);
      if (!grids_within_budget(probe)) {
        fuzz_note("bodies built; a contact grid is over the fuzz budget");
        return 0;
      }
    }
    const Simulation sim(scene);
    check_simulation(sim);
    fuzz_note("built: " + std::to_string(sim.world().num_nodes()) + " nodes, " +
              std::to_string(sim.world().springs.ends.size()) + " springs");
  } catch (const InputError& e) {
    fuzz_note(e.what());
    return 0;
  }
  return 0;
}
