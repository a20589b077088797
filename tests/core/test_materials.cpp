// Materials from Young's modulus (core/elastic_map.hpp): a bar pinned at one end and pulled at
// the other stretches by F L / (E A), and a block under uniaxial compression shortens by as much,
// at several resolutions that agree with each other; the lattice's Poisson ratio is 1/4.
#include "core/elastic_map.hpp"
#include "core/simulation.hpp"

#include <catch2/catch.hpp>

#include <cmath>
#include <sstream>

using namespace harness;

namespace {

struct Static {
  double axial = 0.0;    // mean displacement of the loaded face along the load, m
  double lateral = 0.0;  // mean change of the width at mid-length across the load, m
  double residual = 0.0;
  int steps = 0;
};

// A box of `size` with `cells`, youngs_modulus E, pinned on `pinned` and loaded on the opposite
// face with total force F along `axis` (sign of `dir`), linear law; implicit Euler with mass
// damping until the force residual is 1e-9.
Static solve(const Vec3& size, const Vec3i& cells, double E, int axis, double F) {
  const char* neg[] = {"-x", "-y", "-z"};
  const char* pos[] = {"+x", "+y", "+z"};
  Vec3 force = Vec3::Zero();
  force[axis] = F;
  std::ostringstream os;
  os.precision(17);
  os << R"({"name":"bar","time":{"dt":0.002,"steps":0,"integrator":"implicit_euler"},
    "effects":["springs","damping","pins","loads"],
    "bodies":[{"name":"b","shape":{"type":"box","min":[0,0,0],"max":[)" << size[0] << "," << size[1] << ","
     << size[2] << R"(],"cells":[)" << cells[0] << "," << cells[1] << "," << cells[2] << R"(]},
    "material":{"density":1000,"youngs_modulus":)" << E << R"(,"law":"linear","mass_damping":200},
    "pins":[{"side":")" << neg[axis] << R"("}],
    "loads":[{"select":{"side":")" << pos[axis] << R"("},"force":[)" << force[0] << "," << force[1] << ","
     << force[2] << R"(]}]}]})";
  Simulation sim(parse_scene(os.str(), "bar.json"));
  Static out;
  int below = 0;
  for (out.steps = 0; out.steps < 20000 && below < 20; ++out.steps) {
    sim.step();
    below = sim.residual() < 1e-9 ? below + 1 : 0;
  }
  out.residual = sim.residual();
  const World& w = sim.world();
  const Body& b = w.bodies[0];
  const int lat = (axis + 1) % 3;
  int n = 0;
  double lo = 0.0, hi = 0.0;
  int nlo = 0, nhi = 0;
  for (int i = b.begin; i < b.end; ++i) {
    const Vec3& p0 = w.x0[i];
    if (p0[axis] >= size[axis] - 1e-9) out.axial += w.x[i][axis] - p0[axis], ++n;
    if (std::fabs(p0[axis] - 0.5 * size[axis]) < 1e-9) {  // the mid-length section
      if (p0[lat] <= 1e-9) lo += w.x[i][lat] - p0[lat], ++nlo;
      if (p0[lat] >= size[lat] - 1e-9) hi += w.x[i][lat] - p0[lat], ++nhi;
    }
  }
  out.axial /= n;
  if (nlo && nhi) out.lateral = hi / nhi - lo / nlo;
  return out;
}

}  // namespace

TEST_CASE("a bar pinned at one end stretches by F L / (E A) at every resolution", "[materials]") {
  const double L = 0.1, a = 0.01, E = 1e4, F = 1e-3;  // strain 1e-3
  const double want = F * L / (E * a * a);
  double first = 0.0;
  for (int r : {1, 2, 4}) {
    const Static s = solve(Vec3(L, a, a), Vec3i(10 * r, r, r), E, 0, F);
    INFO("cells " << 10 * r << "x" << r << "x" << r << ": stretch " << s.axial << " m, F L / (E A) " << want
                  << " m, ratio " << s.axial / want << ", residual " << s.residual << " after " << s.steps
                  << " steps; Poisson ratio at mid-length " << -(s.lateral / a) / (s.axial / L));
    CHECK(s.residual < 1e-9);
    CHECK(s.axial == Approx(want).epsilon(0.05));
    if (r == 1) first = s.axial;
    else CHECK(s.axial == Approx(first).epsilon(0.03));
    if (r == 4) CHECK(-(s.lateral / a) / (s.axial / L) == Approx(kLatticePoisson).margin(0.03));
  }
}

TEST_CASE("a block under uniaxial compression shortens by F L / (E A) at every resolution", "[materials]") {
  const double a = 0.02, h = 0.04, E = 3e3, F = -3e-3 * E * a * a;  // strain -3e-3
  const double want = F * h / (E * a * a);
  double first = 0.0;
  for (int r : {2, 4}) {
    const Static s = solve(Vec3(a, a, h), Vec3i(r, r, 2 * r), E, 2, F);
    INFO("cells " << r << "x" << r << "x" << 2 * r << ": shortening " << s.axial << " m, F L / (E A) " << want
                  << " m, ratio " << s.axial / want);
    CHECK(s.residual < 1e-9);
    CHECK(s.axial == Approx(want).epsilon(0.05));
    if (r == 2) first = s.axial;
    else CHECK(s.axial == Approx(first).epsilon(0.03));
  }
}
