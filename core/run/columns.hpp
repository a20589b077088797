// steps.csv: one column table (name and formatter) writes both the header and every row, so a
// new column is one line in steps_columns() (columns.cpp) and header and rows cannot drift.
// The leading columns are fixed by the project's contract (docs/architecture.md, "Outputs");
// a column is empty on rows where its quantity was not measured or does not apply.
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
  void (*write)(const CsvField& out, const StepRow& row);  // writes nothing for an empty field
};

const std::vector<Column>& steps_columns();

class StepsWriter {
 public:
  explicit StepsWriter(const std::string& path);  // writes the header
  ~StepsWriter();
  StepsWriter(const StepsWriter&) = delete;
  StepsWriter& operator=(const StepsWriter&) = delete;
  void row(const StepRow& r);
  void close();  // throws std::runtime_error when the file could not be written

 private:
  std::string path_;
  std::FILE* f_ = nullptr;
};

}  // namespace harness
