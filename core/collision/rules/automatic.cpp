// `"force": "auto"`: the paper's rule that F must beat the deformation forces, applied per
// contact and per step (force_rules.hpp, auto_contact_forces, whose comment gives the rule: the force that makes the guest node
// separate from its hosts at L / separation_time by the end of the step, L the voxel size or the
// host's node spacing).
#include "core/collision/responses/force_rule.hpp"

#include "core/collision/responses/force_rules.hpp"

namespace harness {

namespace {
double force(RuleStep& s, const std::vector<double>&, std::vector<double>& out) {
  return auto_contact_forces(s.w, s.pushes, s.h, s.length / s.spec.separation_time, out, s.share);
}
}  // namespace

HARNESS_FORCE_RULE(automatic) {
  ForceRuleDef r;
  r.name = "auto";
  r.form = RuleForm::word;
  r.doc = "per contact and per step, the force that makes the guest node separate from its hosts at the voxel size "
          "(without a grid: the host's mean spring rest length) over separation_time";
  r.force = force;
  return r;
}

}  // namespace harness
