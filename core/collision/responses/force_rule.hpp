// The force rules' registry: how large each contact's push is (the eliminator gives its
// direction and the host nodes that take the reaction, collision_eliminator.hpp). A rule is one
// source file under core/collision/rules/ that defines itself with a line HARNESS_FORCE_RULE(stem)
// (stem: a C++ name, usually the file's): its name, how a scene writes it, its parameters with ranges and
// defaults (the key table, the schema and docs/scenes.md pick them up), its force, its stiffness
// and its device kernel. CMake lists those lines and generates the call of every rule's maker
// (build/generated/force_rule_list.hpp), so adding a rule touches no other hand-written file;
// nothing here depends on a static registrar surviving the static library's link.
//
// How a scene writes a rule (contacts.N.force):
//   a number      the rule of form `number` (the paper's constant force), its one parameter;
//   a word        the rule of form `word` named by it ("auto");
//   an object     {"rule": NAME, PARAMETER: value, ...}, rule by default "penalty"; the
//                 parameters are NAME's own, each within its range, a missing one its default.
#pragma once

#include "core/collision/responses/collision_eliminator.hpp"

#include <string>
#include <vector>

namespace harness {

enum class RuleForm { number, word, object };
// The rule an object without "rule" names ({"stiffness": k}, the scene format's penalty).
inline constexpr const char* kDefaultObjectRule = "penalty";

struct RuleParameter {
  const char* name;
  double lo, hi;    // closed range
  double fallback;  // NaN: required
  const char* unit;
  const char* doc;
};

// What a rule's force sees in one (sub)step.
struct RuleStep {
  const World& w;
  std::vector<Push>& pushes;  // the eliminator's; a rule may set each push's direction n
  double h;                   // the (sub)step, s
  double length;              // the grid's voxel, or the host's mean spring rest length without one, m
  const ContactSpec& spec;    // the pair's other keys (separation_time, ...)
  std::vector<int>& share;    // scratch, one int per world node, left all zero
};

struct ForceRuleDef {
  const char* name = "";
  RuleForm form = RuleForm::object;
  const char* doc = "";  // one sentence for the scene reference
  std::vector<RuleParameter> parameters;
  // The eliminator also computes each push's contact normal and depth below the host's surface
  // (Push::normal, Push::depth: penalty_depth), which a rule of depth needs.
  bool depth = false;
  // out[i] the magnitude (N, >= 0, finite) of push i, out resized; returns the largest (0 without
  // pushes). `p` holds the parameters in the rule's order.
  double (*force)(RuleStep& s, const std::vector<double>& p, std::vector<double>& out) = nullptr;
  // The contact's stiffness along the push's direction n (N/m, >= 0): the block k n n^T between
  // the guest node and its hosts (weights w_k), which the stability guard and the implicit step
  // read. `depth` is the push's (m); `magnitude` its force this step. nullptr: the rule reports
  // none (explicit integrators only see it through the substeps it needs). Where the true tangent
  // is indefinite (a constant force along the line's or the plane's direction: F/d (I - n n^T),
  // which softens) its positive part is zero, so those rules report none.
  double (*stiffness)(const std::vector<double>& p, double depth, double magnitude) = nullptr;
  // The device kernel that runs this rule (core/device/contact_kernels.hpp: kForce*, its one
  // parameter the first), or -1: `--device` refuses the rule naming the key.
  int device = -1;
};

// Every rule, in the folder's order (file names sorted).
const std::vector<ForceRuleDef>& force_rules();
// The rule of that name, or nullptr.
const ForceRuleDef* find_force_rule(const std::string& name);
// The rule a scene's number or word names (its form), or nullptr.
const ForceRuleDef* rule_of_form(RuleForm form, const std::string& word = "");
// The pair's rule (spec.force_rule; std::logic_error when unknown).
const ForceRuleDef& force_rule_of(const ContactSpec& spec);
// The value of a parameter of the pair's rule (std::logic_error when the rule has none of that name).
double rule_parameter(const ContactSpec& spec, const std::string& name);

// Sets the pair's rule and its parameters (by name; missing ones their defaults). Throws
// std::invalid_argument naming the parameter when one is unknown, missing without a default, or
// out of range.
void set_force_rule(ContactSpec& spec, const std::string& name,
                    const std::vector<std::pair<std::string, double>>& parameters = {});

// The force rules as docs/scenes.md lists them ("Force rules"; `harness rules` prints it): one
// row per rule, what a scene writes, its parameters, whether it reports a stiffness, the device.
std::string force_rules_markdown();

// One rule's definition, in its own file under core/collision/rules/ (STEM.cpp):
//   HARNESS_FORCE_RULE(STEM) { ForceRuleDef r; r.name = ...; return r; }
#define HARNESS_FORCE_RULE(stem) ForceRuleDef make_force_rule_##stem()

}  // namespace harness
