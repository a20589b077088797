// docs/outputs.md is what `harness outputs` prints (core/run/outputs_doc.cpp): the column table,
// the verdicts and the summary keys as the code has them. Regenerate with
// `build/bin/harness outputs > docs/outputs.md`. tests/cli/test_outputs.sh checks the summary keys
// a run writes against the same table.
#include "core/run/columns.hpp"
#include "core/run/outputs_doc.hpp"

#include <catch2/catch.hpp>

#include <fstream>
#include <set>
#include <sstream>
#include <string>

using namespace harness;

TEST_CASE("docs/outputs.md is the page the code generates", "[outputs][docs]") {
  std::ifstream in(std::string(HARNESS_SOURCE_DIR) + "/docs/outputs.md");
  REQUIRE(in);
  std::ostringstream ss;
  ss << in.rdbuf();
  // Byte for byte: a column, verdict or key added without regenerating the page fails here.
  CHECK(ss.str() == outputs_markdown());
}

TEST_CASE("the column table: unique names, steps.csv's contract first, every wall time in timing.csv", "[outputs]") {
  std::set<std::string> names;
  for (const Column& c : steps_columns()) {
    CHECK(names.insert(c.name).second);
    CHECK(std::string(c.doc).size() > 5);
    const std::string n = c.name;
    const bool wall_time = n.rfind("t_", 0) == 0 && n.size() > 3 && n.substr(n.size() - 3) == "_us";
    CHECK(c.timing == wall_time);
  }
  // The contract's leading columns (DESIGN: steps.csv keeps them in this order, the t_*_us ones in timing.csv).
  const char* contract[] = {"step", "time", "pair", "detector", "contacts", "kinetic_energy", "true_pen_guest",
                            "true_pen_host", "tp", "fp", "fn", "max_depth", "mean_depth", "surfaces_intersect",
                            "fcl_pairs"};
  std::size_t i = 0;
  for (const Column& c : steps_columns()) {
    if (c.timing) continue;
    if (i == std::size(contract)) break;
    CHECK(std::string(c.name) == contract[i]);
    ++i;
  }
  CHECK(i == std::size(contract));
  std::set<std::string> keys;
  for (const KeyDoc& k : summary_docs()) CHECK(keys.insert(k.key).second);
}
