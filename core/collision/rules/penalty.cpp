// The linear penalty: F = k max(0, depth) along the push's outward normal (Push::depth,
// Push::normal, directions.hpp says where they come from), so no force acts across a gap and a
// pressed contact has a static equilibrium. Its stiffness is k along the normal.
#include "core/collision/responses/force_rule.hpp"

#include "core/collision/responses/force_rules.hpp"
#include "core/device/contact_kernels.hpp"

#include <cmath>

namespace harness {

namespace {
double force(RuleStep& s, const std::vector<double>& p, std::vector<double>& out) {
  return penalty_contact_forces(s.pushes, p[0], out);
}
double stiffness(const std::vector<double>& p, double, double) { return p[0]; }
}  // namespace

HARNESS_FORCE_RULE(penalty) {
  ForceRuleDef r;
  r.name = "penalty";
  r.form = RuleForm::object;
  r.doc = "k times the depth below the host's surface along its outward normal, reactions shared barycentrically";
  r.parameters = {{"stiffness", 0.0, 1e12, std::nan(""), "N/m", "Stiffness k per contact"}};
  r.depth = true;
  r.force = force;
  r.stiffness = stiffness;
  r.device = dev::kForcePenalty;
  return r;
}

}  // namespace harness
