// The paper's rule: one force F (N) for every contact, tuned by hand so that it beats the
// deformation forces. A scene writes it as a number: "force": 0.003.
#include "core/collision/responses/force_rule.hpp"

#include "core/device/contact_kernels.hpp"

#include <cmath>

namespace harness {

namespace {
double force(RuleStep& s, const std::vector<double>& p, std::vector<double>& out) {
  out.assign(s.pushes.size(), p[0]);  // capacity reserved by Collision: no allocation
  return s.pushes.empty() ? 0.0 : p[0];
}
}  // namespace

HARNESS_FORCE_RULE(constant) {
  ForceRuleDef r;
  r.name = "constant";
  r.form = RuleForm::number;
  r.doc = "the paper's constant force, the same F for every contact along the eliminator's direction";
  r.parameters = {{"force", 0.0, 1e12, std::nan(""), "N", "Force F per contact"}};
  r.force = force;
  r.device = dev::kForceConstant;
  return r;
}

}  // namespace harness
