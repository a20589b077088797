// steps.csv and timing.csv: one column table (name, description, formatter, whether it is a
// wall time) writes both files' headers and every row, and docs/outputs.md (`harness outputs`),
// so a new column is one line in steps_columns() (columns.cpp) and header, rows and docs cannot
// drift. steps.csv holds what a reproduced state reproduces (the columns that are not wall
// times, in the table's order); timing.csv holds the wall times (t_*_us), keyed by step and pair,
// so a rerun that reproduces the state changes timing.csv only. A column is empty on rows where
// its quantity was not measured or does not apply.
#pragma once

#include "core/measure.hpp"
#include "core/run/recorder.hpp"
#include "core/simulation.hpp"

#include <cstdio>
#include <string>
#include <vector>

namespace harness {

// What one row describes: the state after step sim.step_index(), one contact pair (or none).
struct StepRow {
  const Simulation& sim;
  const Pair* pair = nullptr;        // null: a scene without contact pairs
  const Measurement* m = nullptr;    // null: the references did not run this step
  const PairStepFigures* fig = nullptr;  // null likewise (run/recorder.hpp)
  double kinetic_energy = 0.0;       // J
  double potential_energy = 0.0;     // J
};

// Writes one field (no separator) into a CSV line.
class CsvField {
 public:
  explicit CsvField(std::FILE* f) : f_(f) {}
  void g9(double v) const { std::fprintf(f_, "%.9g", v); }    // quantities
  void us(double v) const { std::fprintf(f_, "%.3f", v); }    // times, microseconds
  void integer(long long v) const { std::fprintf(f_, "%lld", v); }
  void text(const std::string& s) const { std::fputs(s.c_str(), f_); }

 private:
  std::FILE* f_;
};

struct Column {
  const char* name;
  const char* doc;  // one line: what it is, with its unit
  void (*write)(const CsvField& out, const StepRow& row);  // writes nothing for an empty field
  bool timing = false;  // a wall time: timing.csv, not steps.csv
};

// Every column, in order (steps.csv's, then timing.csv's, each keeps this order).
const std::vector<Column>& steps_columns();
// The keys timing.csv repeats from steps.csv so its rows can be joined to them.
inline constexpr const char* kTimingKeys[] = {"step", "pair"};

// docs/outputs.md: the columns of steps.csv and timing.csv, the stability verdicts and the key
// paths of summary.json, as the code has them (`harness outputs`; a test keeps the committed page
// equal to it).
std::string outputs_markdown();

// DIR/steps.csv and DIR/timing.csv, written row by row.
class StepsWriter {
 public:
  StepsWriter(const std::string& steps_path, const std::string& timing_path);  // writes the headers
  ~StepsWriter();
  StepsWriter(const StepsWriter&) = delete;
  StepsWriter& operator=(const StepsWriter&) = delete;
  void row(const StepRow& r);
  void close();  // throws std::runtime_error when a file could not be written

 private:
  struct File {
    std::string path;
    std::FILE* f = nullptr;
  };
  File steps_, timing_;
};

}  // namespace harness
