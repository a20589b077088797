// Progress of a run on stderr: on a terminal one updating line with an ETA; otherwise (a batch
// log) one line at every tenth of the steps and every tenth of the settling budget, which logs
// keep.
#pragma once

#include "core/clock.hpp"
#include "core/simulation.hpp"

namespace harness {

class ProgressLine {
 public:
  explicit ProgressLine(bool on);
  ~ProgressLine() { finish(); }
  ProgressLine(const ProgressLine&) = delete;
  ProgressLine& operator=(const ProgressLine&) = delete;

  // After each step.
  void update(const Simulation& sim);
  // Wall time since the run started, s.
  double elapsed() const;
  // Ends the terminal's line (once).
  void finish();

 private:
  bool on_, tty_;
  bool finished_ = false;
  int last_tenth_ = 0;
  bool was_settling_ = false;
  Clock::time_point start_ = Clock::now(), last_ = Clock::now();
};

}  // namespace harness
