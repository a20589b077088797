// Effect "bulk": a box lattice's resistance to a change of each cell's volume (material key
// "bulk_modulus", K in Pa). A mass-spring lattice has no force against a cell turned inside out: a
// spring's force depends on its length alone, so a node can pass through its neighbour and the
// lattice settles inverted (docs/findings.md: the cylinder's layer). This effect adds, per
// cell, the bulk energy of linear elasticity on each of the cell's 8 corner tetrahedra (a corner
// and its three neighbours along the cell's edges, rest volume V0 = cell volume / 6, signed):
//   E_t = (3 K / 4) |V0| (J - 1)^2 / 2,   J = V / V0,
// so that under a uniform change of volume the cell's 8 tetrahedra (together 4/3 of the cell)
// store K V_cell (J - 1)^2 / 2, the bulk energy of a material of bulk modulus K. The corner
// tetrahedra treat the cell's corners alike (no diagonal chosen: a symmetric scene stays
// symmetric), and an inverted corner (J <= 0) is pushed back with a force that grows with how far
// it went. Forces -dE/dx; its energy is elastic (the energy audit's stored energy, with the
// springs'); Gershgorin rows of its Hessian for the stability guard. The implicit integrator
// is refused (exit 2): its Jacobian has no place in LinearSystem (springs only), and forces taken
// explicitly inside it would run unguarded.
#pragma once

#include "core/effects/effects.hpp"

#include <array>
#include <vector>

namespace harness {

// One corner tetrahedron: global node indices (the corner first), its signed rest volume, and
// the modulus 3K/4 of its body.
struct BulkTet {
  std::array<int, 4> node;
  double v0 = 0.0;  // m^3, signed
  double k = 0.0;   // Pa, 3 K / 4
};

// The corner tetrahedra of every cell of the bodies whose bulk_modulus is positive.
std::vector<BulkTet> bulk_tets(const World& w);
// Signed volume of the tetrahedron (a, b, c, d): (b - a) . ((c - a) x (d - a)) / 6.
double tet_volume(const Vec3& a, const Vec3& b, const Vec3& c, const Vec3& d);

class BulkEffect final : public Effect {
 public:
  // alone: the springs effect is not built, so this pass is the first to write the audit's elastic
  // forces and node energies of the substep (it clears them).
  BulkEffect(std::vector<BulkTet> tets, bool alone) : tets_(std::move(tets)), alone_(alone) {}
  const char* name() const override { return "bulk"; }
  EffectCategory category() const override { return EffectCategory::elastic; }
  void add_forces(World& w, const StepContext& s) override;
  bool add_stiffness_rows(const World& w, std::vector<Vec3>& rows) const override;
  bool has_stiffness() const override { return !tets_.empty(); }
  double energy(const World& w) const override;
  const std::vector<BulkTet>& tets() const { return tets_; }

 private:
  std::vector<BulkTet> tets_;
  bool alone_ = false;
};

// Null when no body of the scene has a bulk modulus (listed, nothing to simulate).
std::unique_ptr<Effect> make_bulk_effect(EffectBuild& b);

}  // namespace harness
