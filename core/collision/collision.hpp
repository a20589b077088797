// Collision: the paper's wrapper, one per contact pair, with one interface for the simulation:
// it owns the pair's detector (make_detector, detectors/) and eliminator (make_eliminator,
// responses/), and each step detects, then eliminates with the pair's force rule
// (responses/force_rule.hpp, one file per rule under rules/), adding the penalty forces into World::f. It runs after every
// other force of the step (the contact effect is last in the effect table), because the
// automatic force is derived from them.
#pragma once

#include "core/clock.hpp"
#include "core/scene/contact_spec.hpp"
#include "core/collision/detectors/collision_detector.hpp"
#include "core/collision/responses/collision_eliminator.hpp"
#include "core/collision/responses/volume.hpp"
#include "core/world.hpp"

#include <functional>
#include <memory>
#include <string>
#include <utility>
#include <vector>

namespace harness {

struct ForceRuleDef;

// What a pair did in one step (summed over its substeps; `contacts` averaged over them).
struct PairStep {
  int contacts = 0;             // contacts detected
  double detect_us = 0.0;       // wall time of detection, microseconds (steady_clock)
  double eliminate_us = 0.0;    // wall time of elimination, force rule included
  double force = 0.0;           // largest force magnitude of a contact, N
  // Contacts found beyond the detector's guaranteed band (both ways; averaged over substeps like
  // `contacts`); -1 when the detector has no band (CollisionDetector::beyond_band).
  int beyond_band = -1;
};

// The one check of a pair's bodies (whoever makes its detectors: Collision, below): host and
// guest are bodies of `w`, and different ones. Throws std::invalid_argument. (The scene loader
// checks the names a scene gives, with their key paths.) A spec not made from the key table
// (ContactSpec::made) throws std::logic_error: a bug of the caller's.
void check_pair(const World& w, const ContactSpec& spec);

// A contact response given by the program instead of the pair's force rule (the Python module's
// callable, harness.Simulation(response=...)): each (sub)step, after detection and the eliminator's
// pushes (their directions, depths, hosts and weights), it adds its forces per world node into
// `f` (zeros on entry, one row per node of w), N. It reports no stiffness: the stability guard
// does not see it and the implicit step refuses it (Simulation). It may throw; the step then fails.
using ContactResponse = std::function<void(const World& w, const std::vector<Push>& pushes, double h, Points& f)>;
// A response and the name its runs record (summary.json pairs[].response).
struct OwnResponse {
  std::string name;
  ContactResponse force;
};

class Collision {
 public:
  // The automatic force separates a contact at v_sep = L / separation_time (ContactSpec; its
  // default is the key table's row contact.separation_time), L the voxel size (see
  // auto_contact_forces): a pair resting in one voxel leaves it in about this time, a few cm/s
  // for millimetre voxels. A physical time, so that the rule depends on dt only through the
  // integration.

  // Checks the pair (check_pair), makes its detector and configures it once on the current (rest)
  // positions. Throws std::invalid_argument for a detector this program cannot make, bad body
  // indices, a negative margin, a non-finite or negative force, a bad voxel size, or a region
  // above kMaxVoxels.
  Collision(const World& w, ContactSpec spec, ExactDetectorMaker exact = nullptr);

  // Detect, then eliminate, in a (sub)step of h seconds (StepContext::h; the automatic force
  // separates a contact within it).
  PairStep step(World& w, double h);
  // A response instead of the force rule (ContactResponse; empty: the force rule). Refused
  // (std::invalid_argument) for a projecting pair, which has no forces.
  void set_response(OwnResponse r);
  bool has_response() const { return static_cast<bool>(response_); }
  const std::string& response_name() const { return response_name_; }
  // Projection (eliminator "projection"), after the position update: detect, then move the
  // penetrating nodes to the surface (responses/projection.hpp). step() does nothing for it.
  PairStep project(World& w, double h);
  bool projects() const { return elim_->projects; }
  // The volume response's last restriction (responses/volume.hpp): the bound and the moves.
  const VolumeStep& volume_step() const { return volume_step_; }
  // Detection only (tests, benchmarks, measurement); returns the number of contacts.
  int detect(const World& w);
  // The next step()'s detection, made now (from the positions alone, which nothing changes before
  // that step() in the same substep), in ahead_parts() parts that may run on different threads
  // at once (this way round; the other way round when two-sided), while the force pass runs on
  // the others. The step's detect_us is the sum of the parts' times. None for a projection pair
  // (it detects after integration).
  // ahead_done(), once every part is done (on one thread), hands them to the next step().
  int ahead_parts() const { return projects() ? 0 : reverse_ ? 2 : 1; }
  void detect_ahead(const World& w, int part);
  void ahead_done() { ahead_ = true; }

  // The guest nodes detected this step (with two_sided, the host nodes detected the other way
  // round are in reverse_contacts()).
  const std::vector<Contact>& contacts() const { return contacts_; }
  const std::vector<Contact>& reverse_contacts() const { return reverse_contacts_; }
  double voxel_size() const { return detector_->voxel_size(); }
  // The pair's length scale L: the voxel size, or the host's mean spring rest length for a
  // detector without a grid (the automatic force's, RuleStep::length).
  double length() const { return detector_->voxel_size() > 0.0 ? detector_->voxel_size() : length_scale_; }
  // The pair's force rule (the registry's; a response of its own runs under the penalty's pushes).
  const ForceRuleDef& rule() const { return *rule_; }
  int rebuilds() const { return detector_->rebuilds(); }
  const ContactSpec& spec() const { return spec_; }
  const CollisionDetector& detector() const { return *detector_; }
  // The two-sided pair's other-way detector; null for a one-sided pair.
  const CollisionDetector* reverse_detector() const { return reverse_.get(); }
  const CollisionEliminator& eliminator() const { return *eliminator_; }
  // The last step's pushes and their magnitudes (N): the contact forces applied.
  const std::vector<Push>& pushes() const { return pushes_; }
  const std::vector<double>& magnitudes() const { return magnitude_; }
  bool stepped() const { return stepped_; }  // step() ran at least once
  // Sum over nodes of the last step()'s forces (or the last project()'s equivalent forces
  // m dx / h^2) dotted with dx (one vector per node), J: the energy audit's contact work.
  double work(const World& w, const Points& dx) const;

 private:
  void detect_all(const World& w);  // this way round, and the other when two-sided
  void all_pushes(const World& w);
  // Marks the pair stepped and fills its contacts and timings (detection t0..t1, the rest t1..now).
  PairStep finish(PairStep s, double detect_us, Clock::time_point t1);

  ContactSpec spec_{};
  const ForceRuleDef* rule_ = nullptr;
  const EliminatorDef* elim_ = nullptr;
  // The volume response: its restriction runs in project() itself (responses/volume.hpp).
  bool volume() const { return spec_.eliminator == "volume"; }
  std::unique_ptr<CollisionDetector> detector_;
  std::unique_ptr<CollisionEliminator> eliminator_;
  std::vector<Contact> contacts_;  // reserved for every guest node: no growth per step
  std::vector<Push> pushes_;       // direction and reactions per contact (same capacity)
  std::vector<double> magnitude_;  // force per contact, N (same capacity)
  double length_scale_ = 0.0;      // m, for the automatic force without a grid
  std::vector<int> share_;         // per node: contacts leaning on it (scratch, all zero)
  // two_sided: the same pair seen the other way round (host and guest swapped), for the reverse
  // detector's configuration and the eliminator; its contacts are host nodes inside the guest.
  ContactSpec reverse_spec_{};
  std::unique_ptr<CollisionDetector> reverse_;
  std::vector<Contact> reverse_contacts_;
  std::vector<Push> reverse_pushes_;
  bool stepped_ = false;
  bool ahead_ = false;         // detect_ahead() done: step() takes its contacts
  double ahead_us_[2] = {0.0, 0.0};  // and their times
  double projected_h_ = 0.0;  // the substep of the last project()
  VolumeStep volume_step_;    // eliminator volume: the last restriction
  ContactResponse response_;  // set_response: replaces the force rule
  std::string response_name_;
  Points response_f_;         // its last forces per node (work())
  double volume_pixel_ = 0.0;  // and its images' pixel (set once, at rest)
};

// One contact pair of the scene. `collision` exists only when the scene lists "contact";
// without it the pair is still measured by the references (penetration without contact).
struct Pair {
  Pair(const ContactSpec& s, std::string l) : spec(s), label(std::move(l)) {}
  const ContactSpec& spec;  // the scene's (Scene::contacts[i].spec, owned by the simulation)
  std::string label;  // contacts.N.label ("host/guest")
  std::unique_ptr<Collision> collision;
  // Set when a peer engine (engine.hpp) handles this pair's contact: its contact model's name
  // (collision is then null; last.contacts and last.detect_us come from the engine).
  const char* engine_contact = nullptr;
  PairStep last;      // the last step
};

}  // namespace harness
