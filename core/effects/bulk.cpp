#include "core/effects/bulk.hpp"

#include "core/scene/scene.hpp"

#include <algorithm>
#include <cmath>

namespace harness {

double tet_volume(const Vec3& a, const Vec3& b, const Vec3& c, const Vec3& d) {
  return (b - a).dot((c - a).cross(d - a)) / 6.0;
}

std::vector<BulkTet> bulk_tets(const World& w) {
  std::vector<BulkTet> out;
  for (const Body& b : w.bodies) {
    const double K = b.material.bulk_modulus;
    if (!(K > 0.0)) continue;
    for (const Cell& cell : b.cells)
      for (int c = 0; c < 8; ++c) {
        BulkTet t;
        t.node = {b.begin + cell[c], b.begin + cell[c ^ 1], b.begin + cell[c ^ 2], b.begin + cell[c ^ 4]};
        t.v0 = tet_volume(w.x0[t.node[0]], w.x0[t.node[1]], w.x0[t.node[2]], w.x0[t.node[3]]);
        t.k = 0.75 * K;
        if (t.v0 != 0.0) out.push_back(t);
      }
  }
  return out;
}

namespace {

// dV/dx of the tetrahedron's 4 nodes (they sum to zero).
std::array<Vec3, 4> volume_gradient(const Vec3& a, const Vec3& b, const Vec3& c, const Vec3& d) {
  const Vec3 e1 = b - a, e2 = c - a, e3 = d - a;
  std::array<Vec3, 4> g;
  g[1] = e2.cross(e3) / 6.0;
  g[2] = e3.cross(e1) / 6.0;
  g[3] = e1.cross(e2) / 6.0;
  g[0] = -(g[1] + g[2] + g[3]);
  return g;
}

}  // namespace

// E = k |V0| (J - 1)^2 / 2: dE/dx = k sign(V0) (J - 1) dV/dx.
void BulkEffect::add_forces(World& w, const StepContext& s) {
  if (alone_) {
    if (s.f_spring) std::fill(s.f_spring->begin(), s.f_spring->end(), Vec3::Zero());
    if (s.spring_energy) std::fill(s.spring_energy->begin(), s.spring_energy->end(), 0.0);
  }
  for (const BulkTet& t : tets_) {
    const Vec3 &a = w.x[t.node[0]], &b = w.x[t.node[1]], &c = w.x[t.node[2]], &d = w.x[t.node[3]];
    const double J = tet_volume(a, b, c, d) / t.v0;
    const double coef = -t.k * std::copysign(1.0, t.v0) * (J - 1.0);
    const std::array<Vec3, 4> g = volume_gradient(a, b, c, d);
    for (int q = 0; q < 4; ++q) {
      const Vec3 f = coef * g[q];
      w.f[t.node[q]] += f;
      if (s.f_spring) (*s.f_spring)[t.node[q]] += f;
    }
    if (s.spring_energy) {
      const double e = 0.125 * t.k * std::abs(t.v0) * (J - 1.0) * (J - 1.0);  // a quarter to each node
      for (int q = 0; q < 4; ++q) (*s.spring_energy)[t.node[q]] += e;
    }
  }
  if (s.guard_rows) add_stiffness_rows(w, *s.guard_rows);
}

double BulkEffect::energy(const World& w) const {
  double e = 0.0;
  for (const BulkTet& t : tets_) {
    const double J = tet_volume(w.x[t.node[0]], w.x[t.node[1]], w.x[t.node[2]], w.x[t.node[3]]) / t.v0;
    e += 0.5 * t.k * std::abs(t.v0) * (J - 1.0) * (J - 1.0);
  }
  return e;
}

// |d2E/dx dx| row sums: k / |V0| (dV/dx)(dV/dx)^T plus k |J - 1| d2V/dx dx, whose block coupling
// nodes p and q (p != q) is the cross-product matrix of the edge joining the other two, over 6
// (its rows' absolute sums: the other two components of that edge), and whose diagonal blocks
// are zero (V is linear in each node).
bool BulkEffect::add_stiffness_rows(const World& w, std::vector<Vec3>& rows) const {
  if (tets_.empty()) return false;
  for (const BulkTet& t : tets_) {
    const Vec3* x[4] = {&w.x[t.node[0]], &w.x[t.node[1]], &w.x[t.node[2]], &w.x[t.node[3]]};
    const double V = tet_volume(*x[0], *x[1], *x[2], *x[3]);
    const double J = V / t.v0;
    const std::array<Vec3, 4> g = volume_gradient(*x[0], *x[1], *x[2], *x[3]);
    double gsum = 0.0;
    for (const Vec3& gq : g) gsum += gq.cwiseAbs().sum();
    const double c1 = t.k / std::abs(t.v0), c2 = t.k * std::abs(J - 1.0) / 6.0;
    for (int p = 0; p < 4; ++p) {
      Vec3 row = c1 * gsum * g[p].cwiseAbs();
      for (int q = 0; q < 4; ++q) {
        if (q == p) continue;
        int o[2], n = 0;  // the other two nodes
        for (int r = 0; r < 4; ++r)
          if (r != p && r != q) o[n++] = r;
        const Vec3 e = (*x[o[1]] - *x[o[0]]).cwiseAbs();
        row += c2 * Vec3(e.y() + e.z(), e.x() + e.z(), e.x() + e.y());
      }
      rows[t.node[p]] += row;
    }
  }
  return true;
}

std::unique_ptr<Effect> make_bulk_effect(EffectBuild& b) {
  std::vector<BulkTet> tets = bulk_tets(b.world);
  if (tets.empty()) return nullptr;
  if (b.scene.integrator != Integrator::symplectic_euler)
    throw InputError(b.scene.file + ": time.integrator",
                     "the bulk effect runs with \"symplectic_euler\" only (its Jacobian is not assembled by the implicit integrator)");
  return std::make_unique<BulkEffect>(std::move(tets), !b.scene.has(kSprings));
}

}  // namespace harness
