// Wall-clock timing of the harness's own figures (steady_clock, microseconds).
#pragma once

#include <chrono>

namespace harness {

using Clock = std::chrono::steady_clock;

inline double us_between(Clock::time_point a, Clock::time_point b) {
  return std::chrono::duration<double, std::micro>(b - a).count();
}
inline double us_since(Clock::time_point t0) { return us_between(t0, Clock::now()); }

}  // namespace harness
