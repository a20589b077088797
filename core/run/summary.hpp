// summary.json of a run (docs/outputs.md): written last, atomically, so that a
// folder without it is an interrupted run.
#pragma once

#include "core/run/recorder.hpp"
#include "core/run/report.hpp"
#include "core/simulation.hpp"

#include <nlohmann/json.hpp>

#include <map>
#include <string>

namespace harness {

// summary.json of a run with its outcome (report.hpp); the keys read back are named in
// summary_keys.hpp.
nlohmann::json summary_json(const Simulation& sim, const Recorder& rec, const RunOutcome& outcome,
                            const std::map<std::string, std::string>& versions);
// summary.json's error against the compared reference: "compare" and per pair
// "error_vs_reference" (compare.hpp); the final errors go into `outcome` too. Throws
// ComparisonError (after writing "compare") when an error cannot be computed.
void add_comparison(nlohmann::json& summary, const Simulation& sim, const Recorder& rec, const Comparison& cmp,
                    RunOutcome& outcome);
// With --compare-also: per pair "error_vs_reference_also" (summary_keys.hpp), the figures against
// the second reference on the same steps as the first's. Throws ComparisonError as add_comparison.
void add_comparison_also(nlohmann::json& summary, const Simulation& sim, const Recorder& rec, const Comparison& cmp,
                         const WindowSpan& span);
// A figure as summary.json writes it: the number, or null when it is not finite.
nlohmann::json number_or_null(double v);
// Writes DIR/summary.json through a temporary file and a rename.
void write_summary(const std::string& dir, const nlohmann::json& summary);
// DIR/penetration_episodes.csv: one row per episode of true penetration (recorder.hpp).
void write_episodes(const std::string& dir, const Simulation& sim, const Recorder& rec);

std::string compiler_version();
std::string eigen_version();

}  // namespace harness
