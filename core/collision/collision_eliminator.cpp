#include "core/collision/collision_eliminator.hpp"

#include "core/collision/eliminators.hpp"

#include <algorithm>
#include <cmath>
#include <stdexcept>

namespace harness {

std::unique_ptr<CollisionEliminator> make_eliminator(EliminatorKind kind) {
  switch (kind) {
    case EliminatorKind::line: return std::make_unique<LineEliminator>();
    case EliminatorKind::plane: return std::make_unique<PlaneEliminator>();
  }
  throw std::invalid_argument("unknown eliminator kind");
}

namespace {
const Vec3& velocity(const World& w, int i) {
  const bool kin = i < static_cast<int>(w.kinematic.size()) && w.kinematic[i] &&
                   i < static_cast<int>(w.kin_v.size());
  return kin ? w.kin_v[i] : w.v[i];
}
bool is_kinematic(const World& w, int i) {
  return i < static_cast<int>(w.kinematic.size()) && w.kinematic[i];
}
// max that ignores a non-finite candidate.
void raise(double& m, double candidate) {
  if (std::isfinite(candidate) && candidate > m) m = candidate;
}
}  // namespace

double auto_contact_forces(const World& w, const CollisionDetector& det,
                           const std::vector<Contact>& contacts, double dt, double separation_speed,
                           std::vector<double>& out) {
  out.resize(contacts.size());
  double largest = 0.0;
  for (std::size_t i = 0; i < contacts.size(); ++i) {
    const Contact& c = contacts[i];
    out[i] = 0.0;
    int h = -1;
    if (det.nearest_hosts(w, c, 1, &h) < 1 || !(dt > 0.0)) continue;
    const bool kg = is_kinematic(w, c.guest), kh = is_kinematic(w, h);
    if (kg && kh) continue;  // neither can move: nothing to stop
    const Vec3 r = w.x[c.guest] - w.x[h];
    const double len = r.norm();
    const Vec3 dv = velocity(w, c.guest) - velocity(w, h);
    // Relative acceleration from the forces accumulated so far (kinematic nodes: none).
    const Vec3 da = (kg ? Vec3::Zero() : Vec3(w.inv_m[c.guest] * w.f[c.guest])) -
                    (kh ? Vec3::Zero() : Vec3(w.inv_m[h] * w.f[h]));
    // Separating speed along u expected at the end of the step without contact force.
    double predicted;
    if (len > 0.0) {
      const Vec3 u = r / len;
      predicted = dv.dot(u) + dt * da.dot(u);
    } else {
      predicted = -(dv.norm() + dt * da.norm());
    }
    const double mu = kg ? w.m[h] : kh ? w.m[c.guest] : w.m[c.guest] * w.m[h] / (w.m[c.guest] + w.m[h]);
    double f = 0.0;
    raise(f, mu * std::max(0.0, separation_speed - predicted) / dt);
    out[i] = f;
    largest = std::max(largest, f);
  }
  return largest;
}

}  // namespace harness
