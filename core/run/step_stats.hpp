// Per-step wall times as a referee reads them: the mean, the median, the 99th percentile (nearest
// rank) and the maximum, for a run's summary (summary.cpp) and a device run's (experiments/
// device_run.cpp) alike, with the real-time factors against the scene's dt (simulated time per
// wall time: dt / step time; at least 1 is real time).
#pragma once

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <numeric>
#include <vector>

namespace harness {

// The q-quantile of v by nearest rank (q in (0, 1]); NaN for an empty v.
inline double percentile(std::vector<double> v, double q) {
  if (v.empty()) return std::nan("");
  std::sort(v.begin(), v.end());
  const auto rank = static_cast<std::size_t>(std::ceil(q * static_cast<double>(v.size())));
  return v[std::min(v.size() - 1, rank > 0 ? rank - 1 : 0)];
}

struct StepStats {
  double mean = std::nan(""), median = std::nan(""), p99 = std::nan(""), max = std::nan("");
  std::size_t n = 0;  // steps timed
};

// NaN figures for no steps.
inline StepStats step_stats(const std::vector<double>& us) {
  StepStats s;
  s.n = us.size();
  if (us.empty()) return s;
  s.mean = std::accumulate(us.begin(), us.end(), 0.0) / static_cast<double>(us.size());
  s.median = percentile(us, 0.5);
  s.p99 = percentile(us, 0.99);
  s.max = *std::max_element(us.begin(), us.end());
  return s;
}

// dt / t: the real-time factor of a step of t microseconds at dt seconds (NaN unless t > 0).
inline double realtime_factor(double dt, double t_us) { return t_us > 0.0 ? dt * 1e6 / t_us : std::nan(""); }

}  // namespace harness
