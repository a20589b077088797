// Episodes of true penetration (run/recorder.hpp, penetration_episodes.csv): a node that goes
// through the other body ends its episode on the far side, which is a failure (tunnelled), not an
// elimination; a node that goes through between two measured steps, never found inside, makes a
// tunnelled episode of its own; one pushed back out where it came in is not tunnelled.
#include "core/run/run_scene.hpp"
#include "core/scene/scene.hpp"
#include "reference/reference.hpp"

#include <catch2/catch.hpp>

#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

#include <unistd.h>

using namespace harness;
namespace fs = std::filesystem;

namespace {

struct EpisodeRow {
  std::string body;
  int first = 0, last = 0, open = 0, tunnelled = 0;
};

// A small sphere (the guest) flying at 1 m/s along x through a host sphere of radius 10 mm, no
// forces at all (no effects): it goes straight through. `every`: the references' sampling.
// `drivers`: the guest's drivers (JSON list; with them the effect drivers is listed).
std::vector<EpisodeRow> fly_through(int every, double vx, int steps, const std::string& tag,
                                    const std::string& drivers = "[]") {
  const std::string text = R"({
    "time": {"dt": 1e-4, "steps": )" + std::to_string(steps) + R"(},
    "effects": )" + (drivers == "[]" ? "[]" : "[\"drivers\"]") + R"(,
    "bodies": [
      {"name": "host", "shape": {"type": "sphere", "radius": 0.01, "subdivisions": 2}},
      {"name": "guest", "shape": {"type": "sphere", "center": [-0.03, 0, 0], "radius": 0.001, "subdivisions": 0},
       "velocity": [)" + std::to_string(vx) + R"(, 0, 0], "drivers": )" + drivers + R"(}
    ],
    "contacts": [{"host": "host", "guest": "guest"}],
    "references": {"solvers": ["cgal"], "every": )" + std::to_string(every) + R"(}
  })";
  const fs::path dir = fs::temp_directory_path() / ("harness_episodes_" + tag + "_" + std::to_string(::getpid()));
  RunOptions opt;
  opt.measurer = make_reference_measurer;
  opt.exact_detectors = make_exact_detector;
  opt.out_dir = dir.string();
  REQUIRE(run_scene(parse_scene(text, "fly_through.json"), opt) == 0);
  std::ifstream in(dir / "penetration_episodes.csv");
  REQUIRE(in);
  std::string line;
  std::getline(in, line);
  REQUIRE(line == "pair,body,node,first_step,last_step,steps,open,tunnelled");
  std::vector<EpisodeRow> out;
  while (std::getline(in, line)) {
    std::vector<std::string> f;
    std::string cell;
    for (char ch : line + ",") {
      if (ch == ',') f.push_back(cell), cell.clear();
      else cell += ch;
    }
    REQUIRE(f.size() == 8);
    out.push_back({f[1], std::stoi(f[3]), std::stoi(f[4]), std::stoi(f[6]), std::stoi(f[7])});
  }
  fs::remove_all(dir);
  return out;
}

}  // namespace

TEST_CASE("episodes: a node that goes through the other body ends its episode tunnelled", "[episodes][cgal]") {
  // Sampled every step: each guest node is found inside, then leaves on the far side.
  const auto eps = fly_through(1, 1.0, 600, "every1");
  int guest = 0, through = 0, open = 0;
  for (const EpisodeRow& e : eps)
    if (e.body == "guest") ++guest, through += e.tunnelled, open += e.open;
  CHECK(guest > 0);
  CHECK(through == guest);  // every one went through
  CHECK(open == 0);
  for (const EpisodeRow& e : eps)
    if (e.body == "guest") CHECK(e.last > e.first);  // seen inside over several steps
}

TEST_CASE("episodes: a passage between two measured steps is a tunnelled episode of its own", "[episodes][cgal]") {
  // Sampled every 400 steps (40 mm of travel): the 21 mm host is crossed between two samples.
  const auto eps = fly_through(400, 1.0, 800, "every400");
  int guest = 0, through = 0;
  for (const EpisodeRow& e : eps)
    if (e.body == "guest") {
      ++guest, through += e.tunnelled;
      CHECK(e.first == e.last);  // never found inside: no measured length
      CHECK(e.open == 0);
    }
  CHECK(guest > 0);
  CHECK(through == guest);
}

TEST_CASE("episodes: a node that leaves where it came in is not tunnelled", "[episodes][cgal]") {
  // Driven in at 1 m/s for 250 steps (25 mm: 5 mm past the host's surface), then back out the way it
  // came: its episodes close on the side they began, none tunnelled, none open.
  const auto back = fly_through(1, 0.0, 600, "back",
                                R"([{"select": {"all": true}, "velocity": [1, 0, 0], "from_step": 1, "to_step": 250},
                                    {"select": {"all": true}, "velocity": [-1, 0, 0], "from_step": 251, "to_step": 600}])");
  int guest = 0;
  for (const EpisodeRow& e : back)
    if (e.body == "guest") {
      ++guest;
      CHECK(e.tunnelled == 0);
      CHECK(e.open == 0);
    }
  CHECK(guest > 0);
}
