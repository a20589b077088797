#include "core/run/report.hpp"

#include <cmath>
#include <cstdio>

namespace harness {

RunOutcome run_outcome(const Simulation& sim, const Recorder& rec, const RunStatus& status) {
  RunOutcome o;
  o.status = status;
  o.steps_run = sim.step_index();
  o.residual = sim.residual();
  o.stability = sim.stats().stability;
  o.judged = rec.judge(sim, sim.scene().settle.present && status.settled);
  o.verdict = status.status == "ok" || status.status == "interrupted" ? o.judged.verdict : "failed";
  for (std::size_t p = 0; p < sim.pairs().size(); ++p) {
    PairOutcome po;
    po.tunnelled = rec.tunnel_count(p);
    po.measured = rec.totals()[p].measured;
    po.true_pen_final = rec.totals()[p].true_pen_final;
    o.pairs.push_back(po);
  }
  return o;
}

std::vector<std::string> end_warnings(const RunOutcome& o) {
  std::vector<std::string> out;
  for (std::size_t p = 0; p < o.pairs.size(); ++p) {
    const int g = o.pairs[p].tunnelled.guest, h = o.pairs[p].tunnelled.host;
    if (g > 0)
      out.push_back("contacts." + std::to_string(p) + ": " + std::to_string(g) +
                    " guest nodes tunnelled through the host (entered through one side, left through the other)");
    if (h > 0)
      out.push_back("contacts." + std::to_string(p) + ": " + std::to_string(h) +
                    " host nodes tunnelled through the guest (entered through one side, left through the other)");
  }
  const StabilityJudgement& j = o.judged;
  char b[320];
  if (o.verdict == verdict_name(Verdict::injects)) {
    std::snprintf(b, sizeof b,
                  "contacts: contact keeps putting energy in over the final window (steps %d-%d): per time scale "
                  "(%.3g s) %.3g of the energy the bodies store (limit %g)",
                  j.span.from, j.span.to, j.time_scale, j.contact_input_share, kContactInputShare);
    out.push_back(b);
  } else if (o.verdict == verdict_name(Verdict::grows)) {
    std::snprintf(b, sizeof b,
                  "time: the state grows over the final window (steps %d-%d): its largest kinetic energy rose %.3g times "
                  "from the first half to the second",
                  j.span.from, j.span.to, j.growth);
    out.push_back(b);
  } else if (o.verdict == verdict_name(Verdict::chatters)) {
    std::snprintf(b, sizeof b,
                  "contacts: nodes chatter over the final window (steps %d-%d): %.3g mm about their mean, above %.3g mm "
                  "(%s)",
                  j.span.from, j.span.to, 1e3 * j.inputs.chatter_amplitude, 1e3 * j.inputs.chatter_length,
                  j.inputs.chatter_length_from.c_str());
    out.push_back(b);
  }
  return out;
}

void print_end_line(const Simulation& sim, const RunOutcome& o, const std::string& dir, double wall_s) {
  std::string pen, err;
  long long tunnelled = 0;
  for (const PairOutcome& p : o.pairs) {
    if (p.measured) pen += ", " + std::to_string(p.true_pen_final) + " penetrating nodes";
    const long long tun = static_cast<long long>(p.tunnelled.guest) + p.tunnelled.host;
    tunnelled += tun;
    if (tun > 0) pen += ", " + std::to_string(tun) + " tunnelled";
    if (p.compared) {
      char b[160];
      std::snprintf(b, sizeof b, ", pos_err_max %.3g mm", 1e3 * p.errors.pos_err_max);
      err += b;
      const WindowStat& w = p.pos_err_max_window;
      if (w.n > 0 && std::isfinite(w.mean)) {
        std::snprintf(b, sizeof b, " (window mean %.3g, max %.3g, amplitude %.3g mm)", 1e3 * w.mean, 1e3 * w.max,
                      1e3 * w.amplitude());
        err += b;
      }
    }
  }
  std::string settle;
  if (sim.scene().settle.present) settle = o.status.settled ? ", settled" : ", not settled";
  // A run whose nodes went through the other body is not a working contact, however stable: said
  // beside its stability (harness sweep --baseline also says "no better than no force").
  std::string verdict = ", " + o.verdict + (tunnelled > 0 ? " but tunnels" : "");
  if (std::isfinite(o.judged.inputs.chatter_amplitude)) {
    char b[120];
    std::snprintf(b, sizeof b, " (chatter %.3g of %.3g mm)", 1e3 * o.judged.inputs.chatter_amplitude,
                  1e3 * o.judged.inputs.chatter_length);
    verdict += b;
  }
  std::fprintf(stderr, "harness: %s: %s, %d steps%s%s%s%s, %.1f s, %s\n", sim.scene().name.c_str(),
               o.status.status.c_str(), sim.step_index(), settle.c_str(), verdict.c_str(), pen.c_str(), err.c_str(),
               wall_s, dir.c_str());
}

}  // namespace harness
