// A Hertz-like penalty (not the paper's method): F = k max(0, depth)^exponent along the push's
// outward normal, the law of two elastic spheres pressed together at exponent 1.5 (Hertz 1882;
// Johnson, Contact Mechanics, 1985, ch. 4), k in N/m^exponent. Exponent 1 is the linear penalty.
// Its stiffness is dF/d depth = k exponent depth^(exponent - 1).
#include "core/collision/responses/force_rule.hpp"

#include <algorithm>
#include <cmath>

namespace harness {

namespace {
double force(RuleStep& s, const std::vector<double>& p, std::vector<double>& out) {
  out.resize(s.pushes.size());
  double largest = 0.0;
  for (std::size_t i = 0; i < s.pushes.size(); ++i) {
    Push& q = s.pushes[i];
    q.n = q.normal;
    const double f = q.depth > 0.0 ? p[0] * std::pow(q.depth, p[1]) : 0.0;
    out[i] = std::isfinite(f) && q.normal.squaredNorm() > 0.0 ? f : 0.0;
    largest = std::max(largest, out[i]);
  }
  return largest;
}
double stiffness(const std::vector<double>& p, double depth, double) {
  return depth > 0.0 ? p[0] * p[1] * std::pow(depth, p[1] - 1.0) : 0.0;
}
}  // namespace

HARNESS_FORCE_RULE(hertz) {
  ForceRuleDef r;
  r.name = "hertz";
  r.form = RuleForm::object;
  r.doc = "k times the depth to a power (1.5: two elastic spheres, Hertz), along the host's outward normal";
  r.parameters = {{"stiffness", 0.0, 1e15, std::nan(""), "N/m^exponent", "Stiffness k per contact"},
                  {"exponent", 1.0, 3.0, 1.5, "", "The depth's power"}};
  r.depth = true;
  r.force = force;
  r.stiffness = stiffness;
  return r;
}

}  // namespace harness
