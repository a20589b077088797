// SIGINT and SIGTERM while a run steps: the loop stops after the current step and the run writes
// its outputs with status "interrupted" (exit 128 + signal). A second signal acts as usual (the
// handlers reset themselves). The handlers live only while a StopSignals exists (run_scene's
// stepping); stop_signal() says which signal arrived (0: none).
#pragma once

#include <memory>

namespace harness {

class StopSignals {
 public:
  StopSignals();
  ~StopSignals();
  StopSignals(const StopSignals&) = delete;
  StopSignals& operator=(const StopSignals&) = delete;

 private:
  struct Saved;  // the handlers it replaced
  std::unique_ptr<Saved> saved_;
};

// SIGINT or SIGTERM when one arrived while StopSignals was installed (since its installation), else 0.
int stop_signal();

}  // namespace harness
