#include "core/collision/responses/force_rules.hpp"

#include "core/parallel.hpp"

#include <algorithm>
#include <cmath>
#include <stdexcept>

namespace harness {

double penalty_contact_forces(std::vector<Push>& pushes, double k, std::vector<double>& out) {
  out.resize(pushes.size());
  double largest = 0.0;
  for (std::size_t i = 0; i < pushes.size(); ++i) {
    Push& p = pushes[i];
    p.n = p.normal;
    const double f = k * std::max(0.0, p.depth);
    out[i] = std::isfinite(f) && p.normal.squaredNorm() > 0.0 ? f : 0.0;
    largest = std::max(largest, out[i]);
  }
  return largest;
}

void scatter_pushes(Points& f_out, const std::vector<Push>& pushes, const std::vector<double>& magnitude) {
  // With threads, thread t owns the nodes of every T-th block of 4096 (blocks interleave, so the
  // host's and the guest's nodes are shared out alike) and adds, in push order, the forces on
  // its own nodes: every node receives the same additions in the same order as on one thread.
  const std::size_t n = pushes.size();
  const int T = threads_for(n, 16384);
  const unsigned parts = static_cast<unsigned>(T);
#pragma omp parallel for num_threads(T) if(T > 1) schedule(static, 1)
  for (int t = 0; t < T; ++t) {
    const unsigned me = static_cast<unsigned>(t);
    auto mine = [&](int node) { return parts == 1 || (static_cast<unsigned>(node) >> 12) % parts == me; };
    for (std::size_t i = 0; i < n; ++i) {
      const Push& p = pushes[i];
      if (p.count == 0) continue;
      const Vec3 f = magnitude[i] * p.n;
      if (mine(p.guest)) f_out[p.guest] += f;
      for (int k = 0; k < p.count; ++k)
        if (mine(p.hosts[k])) f_out[p.hosts[k]] -= p.weight[k] * f;
    }
  }
}

namespace {
bool is_kinematic(const World& w, int i) {
  return i < static_cast<int>(w.kinematic.size()) && !w.is_free(i);
}
const Vec3& velocity(const World& w, int i) { return is_kinematic(w, i) ? w.kin_v[i] : w.v[i]; }
Vec3 acceleration(const World& w, int i) {
  return is_kinematic(w, i) ? Vec3::Zero() : Vec3(w.inv_m[i] * w.f[i]);
}
double inverse_mass(const World& w, int i) { return is_kinematic(w, i) ? 0.0 : w.inv_m[i]; }
}  // namespace

double damp_contact_forces(const World& w, const std::vector<Push>& pushes, double c, std::vector<double>& out) {
  double largest = 0.0;
  for (std::size_t i = 0; i < pushes.size(); ++i) {
    const Push& p = pushes[i];
    if (p.count == 0 || !(out[i] > 0.0)) continue;
    Vec3 dv = velocity(w, p.guest);
    for (int k = 0; k < p.count; ++k) dv -= p.weight[k] * velocity(w, p.hosts[k]);
    const double f = out[i] - c * dv.dot(p.n);
    out[i] = std::isfinite(f) ? std::max(0.0, f) : out[i];
    largest = std::max(largest, out[i]);
  }
  return largest;
}

double auto_contact_forces(const World& w, const std::vector<Push>& pushes, double h,
                           double separation_speed, std::vector<double>& out, std::vector<int>& share) {
  out.assign(pushes.size(), 0.0);
  if (share.size() < w.x.size()) share.assign(w.x.size(), 0);
  for (const Push& p : pushes)
    for (int k = 0; k < p.count; ++k) ++share[p.hosts[k]];
  double largest = 0.0;
  if (h > 0.0) {
    // Each magnitude depends on its own push and on `share` alone: parallel; the largest is a
    // max, exact in any order.
    const std::size_t n = pushes.size();
    const int T = threads_for(n, 8192);
#pragma omp parallel for num_threads(T) if(T > 1) schedule(static) reduction(max : largest)
    for (std::size_t i = 0; i < n; ++i) {
      const Push& p = pushes[i];
      if (p.count == 0) continue;
      Vec3 dv = velocity(w, p.guest), da = acceleration(w, p.guest);
      double c = inverse_mass(w, p.guest);
      for (int k = 0; k < p.count; ++k) {
        const int host = p.hosts[k];
        dv -= p.weight[k] * velocity(w, host);
        da -= p.weight[k] * acceleration(w, host);
        c += p.weight[k] * p.weight[k] * share[host] * inverse_mass(w, host);
      }
      if (!(c > 0.0)) continue;  // every node kinematic: nothing can move
      const double sep = dv.dot(p.n) + h * da.dot(p.n);
      const double f = std::max(0.0, separation_speed - sep) / (h * c);
      if (std::isfinite(f)) {
        out[i] = f;
        largest = std::max(largest, f);
      }
    }
  }
  for (const Push& p : pushes)  // reset only what was touched: no O(nodes) pass
    for (int k = 0; k < p.count; ++k) share[p.hosts[k]] = 0;
  return largest;
}

}  // namespace harness
