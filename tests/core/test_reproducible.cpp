// Reproducible to the bit: the same scene on the same build gives the same state hash, run
// twice in one process (the other ways, in two processes and with one or two threads, are
// tests/cli/test_hash.sh).
#include "core/simulation.hpp"

#include <catch2/catch.hpp>

#include <filesystem>

using namespace harness;
namespace fs = std::filesystem;

TEST_CASE("every bundled scene, shortened, gives the same state hash twice in one process", "[reproducible]") {
  const fs::path root = fs::path(HARNESS_SOURCE_DIR) / "experiments" / "scenes";
  int scenes = 0;
  for (const fs::path& dir : {root, root / "hard"})
    for (const auto& e : fs::directory_iterator(dir)) {
      if (e.path().extension() != ".json") continue;
      // Only the voxel detector exists in this (core) test binary.
      Scene sc = load_scene(e.path().string(), {{"time.steps", "60"}, {"references.solvers", "[]"}});
      for (ContactPairSpec& c : sc.contacts) c.spec.detector = "voxel";
      std::string hashes[2];
      for (std::string& h : hashes) {
        Simulation sim(sc);
        for (int s = 0; s < sc.steps; ++s) sim.step();
        h = state_hash(sim.world());
      }
      INFO(e.path().filename().string());
      CHECK(hashes[0] == hashes[1]);
      ++scenes;
    }
  CHECK(scenes >= 11);
}
