#include "core/run/progress.hpp"

#include <unistd.h>

#include <chrono>
#include <cstdio>

namespace harness {

ProgressLine::ProgressLine(bool on) : on_(on), tty_(on && isatty(2)) {}

void ProgressLine::update(const Simulation& sim) {
  if (!on_) return;
  const Scene& sc = sim.scene();
  const int s = sim.step_index(), n = sc.steps;
  const auto now = Clock::now();
  const double elapsed = std::chrono::duration<double>(now - start_).count();
  const bool settling = s > n;
  const int budget = settling ? sc.settle.max_steps : n;
  const int done = settling ? s - n : s;
  const double frac = budget > 0 ? static_cast<double>(done) / budget : 1.0;
  char what[160];
  if (settling)
    std::snprintf(what, sizeof what, "%s: settling, step %d (+%d of at most %d), residual %.3g", sc.name.c_str(), s,
                  done, budget, sim.residual());
  else
    std::snprintf(what, sizeof what, "%s: step %d/%d, ETA %.0f s", sc.name.c_str(), s, n,
                  frac > 0.0 ? elapsed * (1.0 - frac) / frac : 0.0);
  if (tty_) {
    if (now - last_ > std::chrono::milliseconds(200)) {
      last_ = now;
      std::fprintf(stderr, "\r%s (%.0f us/step)   ", what, sim.last().step_us);
    }
    return;
  }
  const int tenth = static_cast<int>(10.0 * frac + 1e-9);
  if (tenth > last_tenth_ || settling != was_settling_) {
    last_tenth_ = settling != was_settling_ ? 0 : tenth;
    was_settling_ = settling;
    std::fprintf(stderr, "harness: %s, %d %%, %.1f s\n", what, 10 * tenth, elapsed);
  }
}

double ProgressLine::elapsed() const { return std::chrono::duration<double>(Clock::now() - start_).count(); }

void ProgressLine::finish() {
  if (tty_ && !finished_) std::fprintf(stderr, "\n");
  finished_ = true;
}

}  // namespace harness
