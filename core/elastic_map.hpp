// From Young's modulus to spring stiffness: each generator describes, per spring, a geometric
// factor kappa and a role, and a body with material.youngs_modulus E (and, for a shell,
// material.thickness t) gets
//   volume    k = E kappa       (kappa in m)
//   membrane  k = E t kappa     (kappa dimensionless)
//   bending   k = E t^3 kappa   (kappa in 1/m^2)
// so that the same material gives the same response at any mesh resolution. The mappings, with
// their sources (docs/scenes.md, "Materials", has the measured behaviour):
//
// Box lattice (structural, face-diagonal and body-diagonal springs). Linear springs under a
// homogeneous strain eps store W = 1/2 sum k l^2 (u.eps.u)^2, so a cell of volume V has the
// elastic constants C_ijkl = (1/V) sum k l^2 u_i u_j u_k u_l (the Cauchy-Born rule; Born and
// Huang 1954, Ostoja-Starzewski 2002). Central springs obey the Cauchy relation C12 = C44, so
// an isotropic lattice has lambda = mu, Poisson's ratio 1/4 and mu = E / 2.5: no other Poisson
// ratio can be represented. isotropic_cell() solves for the seven spring constants of an
// a x b x c cell (edges along x, y, z; the two diagonals of each face orientation; the four
// body diagonals) that give C11 = C22 = C33 = 3 mu, C12 = C13 = C23 = mu, with the body
// diagonals carrying half of the stiffest plane's C12 where possible (cells of aspect ratio up
// to about 1.2; longer cells get the nearest nonnegative constants and are anisotropic). Each spring then takes its share
// from every cell it borders (an edge 1/4 of the cell's edge constant, a face diagonal 1/2, a
// body diagonal all of it), so a homogeneous strain of the whole lattice, boundary cells
// included, has exactly the isotropic energy.
//
// Volume fill (an interior cubic lattice of spacing h tied to the surface). Lattice springs get
// their shares from the complete lattice cells (all eight corners interior) as above; every
// other spring (surface edges, bending and tie springs, lattice springs of no complete cell)
// belongs to the surface layer of volume V_layer = V - (complete cells) h^3, whose springs get
// one kappa = 6 V_layer / sum l^2: the isotropic average of the Cauchy-Born rule,
// mu = (1/15 V) sum k l^2 with mu = E / 2.5, for a layer of springs of no preferred direction.
//
// Shell (a membrane of thickness t; edge springs plus one bending spring across each edge).
// Edge springs: k = E t sum_T A_T / |e|^2 over the two triangles T of the edge (van Gelder,
// "Approximate simulation of elastic membranes by triangulated spring meshes", J. Graphics
// Tools 3(2), 1998), which on a regular triangulation is the triangular lattice's exact
// in-plane modulus (Seung and Nelson 1988: Y = 2 k / sqrt 3, Poisson's ratio 1/3). Bending
// springs: k = E t^3 / (4 l^2), a stabiliser against folding whose share of the in-plane
// stiffness is (t / edge)^2 / 7 or so; it is not a calibrated plate-bending model.
#pragma once

#include "core/types.hpp"

namespace harness {

enum class SpringRole : std::uint8_t { volume, membrane, bending };

// Poisson's ratio every isotropic central-spring lattice has (Cauchy relation).
constexpr double kLatticePoisson = 0.25;
// Shear modulus over Young's modulus at that ratio: mu = E / (2 (1 + nu)).
constexpr double kShearOverYoung = 1.0 / (2.0 * (1.0 + kLatticePoisson));

// Spring constants per unit Young's modulus (m) of one a x b x c lattice cell:
//   edge[a]  the cell's edge constant along axis a (each of its 4 edges takes a quarter),
//   face[n]  the constant of the diagonals of the faces normal to axis n (each of the 4 takes half),
//   body     each of the 4 body diagonals.
struct CellSprings {
  double edge[3];
  double face[3];
  double body;
};
// The constants are exact (the cell's C equals the isotropic one) when nonnegative constants can
// do it, which needs a cell aspect ratio up to about 1.2 (a long axis collects the diagonals'
// stiffness); else they are the nonnegative least-squares best. `anisotropy`, when given,
// receives the largest deviation of an elastic constant from the isotropic one, in units of mu
// (0 when exact).
CellSprings isotropic_cell(const Vec3& dims, double* anisotropy = nullptr);

}  // namespace harness
