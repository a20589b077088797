// Shape generators: every model is a closed, outward, 2-manifold surface over its first
// n_surface nodes, with clean springs and lumped volumes that add up.
#include "tests/core/surface_checks.hpp"

#include <catch2/catch.hpp>
#include <cmath>
#include <algorithm>
#include <array>
#include <set>
#include <stdexcept>

#include "core/shapes/shapes.hpp"

using namespace harness;

namespace {

const double kPi = std::acos(-1.0);

void check_model(const ShapeModel& m, bool expect_interior) {
  const int n = static_cast<int>(m.nodes.size());
  REQUIRE(m.n_surface > 0);
  REQUIRE(m.n_surface <= n);
  REQUIRE(m.node_volume.size() == m.nodes.size());

  // The surface: closed, every edge shared by two faces, sphere topology, outward.
  SurfaceMesh s;
  s.V.assign(m.nodes.begin(), m.nodes.begin() + m.n_surface);
  s.F = m.faces;
  const SurfaceReport r = harness::test::require_sphere_topology(s);
  CHECK(m.volume == Approx(r.signed_volume).epsilon(1e-12));

  // The first n_surface nodes are exactly the face vertices.
  std::set<int> used;
  for (const Tri& t : m.faces)
    for (int v : t) used.insert(v);
  CHECK(static_cast<int>(used.size()) == m.n_surface);
  CHECK(*used.begin() == 0);
  CHECK(*used.rbegin() == m.n_surface - 1);

  // Lumped volumes are positive and add up to the enclosed volume.
  double sum = 0.0;
  for (double v : m.node_volume) {
    CHECK(v > 0.0);
    sum += v;
  }
  CHECK(sum == Approx(m.volume).epsilon(1e-9));

  // Springs: in range, no self-loops, no duplicates, positive rest lengths.
  std::set<std::pair<int, int>> seen;
  std::vector<int> degree(m.nodes.size(), 0);
  bool ok = true;
  for (const Edge& e : m.springs) {
    ok = ok && e[0] >= 0 && e[1] >= 0 && e[0] < n && e[1] < n && e[0] != e[1];
    if (!ok) break;
    ok = ok && seen.insert({std::min(e[0], e[1]), std::max(e[0], e[1])}).second;
    ok = ok && (m.nodes[e[0]] - m.nodes[e[1]]).norm() > 0.0;
    ++degree[e[0]];
    ++degree[e[1]];
  }
  CHECK(ok);
  // Every surface edge is a spring.
  for (const Tri& t : m.faces)
    for (int k = 0; k < 3; ++k) {
      const int a = t[k], b = t[(k + 1) % 3];
      if (!seen.count({std::min(a, b), std::max(a, b)})) {
        FAIL_CHECK("surface edge without a spring");
        break;
      }
    }
  if (expect_interior) CHECK(n > m.n_surface);
  int min_degree = 1 << 30;
  for (int d : degree) min_degree = std::min(min_degree, d);
  CHECK(min_degree >= 3);
}

}  // namespace

TEST_CASE("make_box: lattice, surface first, exact volume", "[shapes]") {
  struct Case {
    Vec3 lo, hi;
    Vec3i cells;
  };
  const Case cases[] = {{Vec3(0, 0, 0), Vec3(1, 1, 1), Vec3i(1, 1, 1)},
                        {Vec3(-1, -2, -3), Vec3(1, 2, 3), Vec3i(2, 3, 4)},
                        {Vec3(0, 0, 0), Vec3(4, 3, 0.5), Vec3i(4, 3, 1)},  // one cell thick
                        {Vec3(0.1, 0.2, 0.3), Vec3(0.2, 0.25, 1.3), Vec3i(1, 1, 5)},
                        {Vec3(0, 0, 0), Vec3(1, 1, 1), Vec3i(5, 5, 5)}};
  for (const Case& c : cases) {
    const int nx = c.cells.x(), ny = c.cells.y(), nz = c.cells.z();
    INFO("cells " << nx << " " << ny << " " << nz);
    const ShapeModel m = make_box(c.lo, c.hi, c.cells);
    const int n = (nx + 1) * (ny + 1) * (nz + 1);
    const int interior = (nx - 1) * (ny - 1) * (nz - 1);
    CHECK(static_cast<int>(m.nodes.size()) == n);
    CHECK(m.n_surface == n - interior);
    CHECK(m.faces.size() == static_cast<std::size_t>(4 * (nx * ny + ny * nz + nz * nx)));
    const double vol = (c.hi - c.lo).prod();
    CHECK(m.volume == Approx(vol).epsilon(1e-14));
    check_model(m, interior > 0);
    // Structural + face diagonals + body diagonals.
    const int structural =
        nx * (ny + 1) * (nz + 1) + (nx + 1) * ny * (nz + 1) + (nx + 1) * (ny + 1) * nz;
    const int faces = 2 * (nx * ny * (nz + 1) + nx * (ny + 1) * nz + (nx + 1) * ny * nz);
    CHECK(static_cast<int>(m.springs.size()) == structural + faces + 4 * nx * ny * nz);
    // Boundary nodes first: every node past n_surface is strictly inside.
    for (int i = m.n_surface; i < n; ++i) {
      const Vec3& p = m.nodes[i];
      CHECK(((p - c.lo).minCoeff() > 0.0 && (c.hi - p).minCoeff() > 0.0));
    }
    // Nodes lie on the box, with the corners exact.
    Vec3 lo = m.nodes[0], hi = m.nodes[0];
    for (const Vec3& p : m.nodes) {
      lo = lo.cwiseMin(p);
      hi = hi.cwiseMax(p);
    }
    CHECK(lo == c.lo);
    CHECK(hi == c.hi);
    // A corner node gets 1/8 of a cell.
    const double cell = vol / (nx * ny * nz);
    double min_share = 1e300;
    for (double v : m.node_volume) min_share = std::min(min_share, v);
    CHECK(min_share == Approx(cell / 8.0));
  }
}

TEST_CASE("make_sphere: icosphere counts, both fills, volume converges", "[shapes]") {
  double previous_error = 1e300;
  for (int s = 0; s <= 3; ++s) {
    INFO("subdivisions " << s);
    const Vec3 c(0.5, -1.0, 2.0);
    const double r = 0.3;
    const ShapeModel shell = make_sphere(c, r, s, Fill::shell);
    const int nv = 10 * (1 << (2 * s)) + 2;
    CHECK(shell.n_surface == nv);
    CHECK(static_cast<int>(shell.nodes.size()) == nv);
    CHECK(static_cast<int>(shell.faces.size()) == 20 * (1 << (2 * s)));
    for (const Vec3& p : shell.nodes) CHECK((p - c).norm() == Approx(r).epsilon(1e-12));
    check_model(shell, false);
    // Shell springs: the edges plus one bending spring per edge (none coincide with an edge
    // beyond the icosahedron's level).
    const int edges = 3 * static_cast<int>(shell.faces.size()) / 2;
    CHECK(static_cast<int>(shell.springs.size()) <= 2 * edges);
    CHECK(static_cast<int>(shell.springs.size()) > edges);

    const double exact = 4.0 / 3.0 * kPi * r * r * r;
    const double error = exact - shell.volume;
    CHECK(error > 0.0);  // inscribed polyhedron
    CHECK(error < previous_error);
    previous_error = error;
    if (s == 3) CHECK(shell.volume == Approx(exact).epsilon(0.02));

    const ShapeModel vol = make_sphere(c, r, s, Fill::volume);
    CHECK(vol.n_surface == nv);
    check_model(vol, true);
    CHECK(vol.volume == Approx(shell.volume));
    // Interior nodes are inside the sphere, away from the surface.
    for (std::size_t i = static_cast<std::size_t>(vol.n_surface); i < vol.nodes.size(); ++i)
      CHECK((vol.nodes[i] - c).norm() < r);
  }
}

TEST_CASE("volume fill of a finer sphere uses a lattice", "[shapes]") {
  const ShapeModel m = make_sphere(Vec3::Zero(), 1.0, 4, Fill::volume);
  check_model(m, true);
  const int interior = static_cast<int>(m.nodes.size()) - m.n_surface;
  CHECK(interior > 100);
  // Interior volume is at most 80 % of the total.
  double in = 0.0;
  for (std::size_t i = static_cast<std::size_t>(m.n_surface); i < m.nodes.size(); ++i)
    in += m.node_volume[i];
  CHECK(in <= 0.8 * m.volume * (1 + 1e-12));
  CHECK(in > 0.0);
}

TEST_CASE("make_ellipsoid", "[shapes]") {
  for (Fill fill : {Fill::shell, Fill::volume}) {
    const Vec3 radii(1.0, 0.5, 0.25);
    const ShapeModel m = make_ellipsoid(Vec3(1, 2, 3), radii, 3, fill);
    check_model(m, fill == Fill::volume);
    for (int i = 0; i < m.n_surface; ++i) {
      const Vec3 q = (m.nodes[i] - Vec3(1, 2, 3)).cwiseQuotient(radii);
      CHECK(q.norm() == Approx(1.0).epsilon(1e-12));
    }
    CHECK(m.volume == Approx(4.0 / 3.0 * kPi * radii.prod()).epsilon(0.03));
  }
}

TEST_CASE("make_cylinder", "[shapes]") {
  for (int segments : {3, 8, 17})
    for (int rings : {1, 3})
      for (Fill fill : {Fill::shell, Fill::volume}) {
        INFO("segments " << segments << " rings " << rings);
        const Vec3 axis(1, 2, -0.5);
        const ShapeModel m =
            make_cylinder(Vec3(0.1, 0.2, 0.3), axis, 0.2, 1.5, segments, rings, fill);
        CHECK(m.n_surface == segments * (rings + 1) + 2);
        CHECK(static_cast<int>(m.faces.size()) == 2 * segments * rings + 2 * segments);
        check_model(m, fill == Fill::volume);
        // Prism volume: regular polygon area times length.
        const double area = 0.5 * segments * 0.2 * 0.2 * std::sin(2 * kPi / segments);
        CHECK(m.volume == Approx(area * 1.5).epsilon(1e-12));
      }
  // The nodes lie on the cylinder around the normalised axis.
  const Vec3 a = Vec3(0, 0, 3);
  const ShapeModel m = make_cylinder(Vec3::Zero(), a, 1.0, 2.0, 12, 2, Fill::shell);
  for (int i = 0; i < 36; ++i) {
    CHECK(std::hypot(m.nodes[i].x(), m.nodes[i].y()) == Approx(1.0));
    CHECK(std::fabs(m.nodes[i].z()) <= 1.0 + 1e-12);
  }
}

TEST_CASE("make_from_surface scales then translates", "[shapes]") {
  SurfaceMesh octa;
  octa.V = {Vec3(1, 0, 0),  Vec3(-1, 0, 0), Vec3(0, 1, 0),
            Vec3(0, -1, 0), Vec3(0, 0, 1),  Vec3(0, 0, -1)};
  octa.F = {{0, 2, 4}, {2, 1, 4}, {1, 3, 4}, {3, 0, 4}, {2, 0, 5}, {1, 2, 5}, {3, 1, 5}, {0, 3, 5}};
  for (Fill fill : {Fill::shell, Fill::volume}) {
    const ShapeModel m = make_from_surface(octa, 2.0, Vec3(10, 0, 0), fill);
    check_model(m, fill == Fill::volume);
    CHECK(m.volume == Approx(8.0 * 4.0 / 3.0));
    CHECK(m.nodes[0].isApprox(Vec3(12, 0, 0)));
    if (fill == Fill::volume) {
      // Too coarse for the lattice: one centre node tied to all six vertices.
      CHECK(m.nodes.size() == 7);
      CHECK(m.nodes[6].isApprox(Vec3(10, 0, 0)));
    }
  }
  // A finer mesh through the same path: a sphere's own surface.
  const ShapeModel s = make_sphere(Vec3::Zero(), 1.0, 3, Fill::shell);
  SurfaceMesh mesh{Points(s.nodes.begin(), s.nodes.begin() + s.n_surface), s.faces};
  const ShapeModel v = make_from_surface(mesh, 0.5, Vec3(1, 1, 1), Fill::volume);
  check_model(v, true);
  CHECK(v.volume == Approx(s.volume / 8.0));
}

TEST_CASE("finish_model bending springs and a box mesh read from a file", "[shapes]") {
  // The tetrahedron: each edge's opposite vertices are joined by an edge already.
  Points V = {Vec3(0, 0, 0), Vec3(1, 0, 0), Vec3(0, 1, 0), Vec3(0, 0, 1)};
  std::vector<Tri> F = {{0, 2, 1}, {0, 1, 3}, {0, 3, 2}, {1, 2, 3}};
  const ShapeModel t = finish_model(V, F, Fill::shell);
  CHECK(t.springs.size() == 6);
  check_model(t, false);
  // Octahedron: bending springs join the opposite vertices across each edge: the 3 axes.
  Points O = {Vec3(1, 0, 0),  Vec3(-1, 0, 0), Vec3(0, 1, 0),
              Vec3(0, -1, 0), Vec3(0, 0, 1),  Vec3(0, 0, -1)};
  std::vector<Tri> G = {{0, 2, 4}, {2, 1, 4}, {1, 3, 4}, {3, 0, 4},
                        {2, 0, 5}, {1, 2, 5}, {3, 1, 5}, {0, 3, 5}};
  const ShapeModel o = finish_model(O, G, Fill::shell);
  CHECK(o.springs.size() == 12 + 3);
  // The box's own surface through finish_model, volume fill: lattice nodes inside.
  const ShapeModel box = make_box(Vec3(0, 0, 0), Vec3(2, 1, 1), Vec3i(8, 4, 4));
  const ShapeModel fb = finish_model(Points(box.nodes.begin(), box.nodes.begin() + box.n_surface),
                                     box.faces, Fill::volume);
  check_model(fb, true);
  CHECK(fb.volume == Approx(2.0));
  for (std::size_t i = static_cast<std::size_t>(fb.n_surface); i < fb.nodes.size(); ++i) {
    const Vec3& p = fb.nodes[i];
    CHECK((p.minCoeff() > 0.0 && p.x() < 2.0 && p.y() < 1.0 && p.z() < 1.0));
  }
}

TEST_CASE("generators validate their arguments", "[shapes]") {
  const Vec3 o = Vec3::Zero();
  CHECK_THROWS_AS(make_box(o, o, Vec3i(1, 1, 1)), std::invalid_argument);
  CHECK_THROWS_AS(make_box(o, Vec3(1, 1, 1), Vec3i(0, 1, 1)), std::invalid_argument);
  CHECK_THROWS_AS(make_box(o, Vec3(1, 1, 1), Vec3i(100000, 100000, 100000)), std::invalid_argument);
  CHECK_THROWS_AS(make_box(Vec3(NAN, 0, 0), Vec3(1, 1, 1), Vec3i(1, 1, 1)), std::invalid_argument);
  CHECK_THROWS_AS(make_sphere(o, 0.0, 1, Fill::shell), std::invalid_argument);
  CHECK_THROWS_AS(make_sphere(o, 1.0, -1, Fill::shell), std::invalid_argument);
  CHECK_THROWS_AS(make_sphere(o, 1.0, 11, Fill::shell), std::invalid_argument);
  CHECK_THROWS_AS(make_ellipsoid(o, Vec3(1, -1, 1), 1, Fill::shell), std::invalid_argument);
  CHECK_THROWS_AS(make_cylinder(o, Vec3::Zero(), 1, 1, 8, 1, Fill::shell), std::invalid_argument);
  CHECK_THROWS_AS(make_cylinder(o, Vec3::UnitZ(), -1, 1, 8, 1, Fill::shell), std::invalid_argument);
  CHECK_THROWS_AS(make_cylinder(o, Vec3::UnitZ(), 1, 0, 8, 1, Fill::shell), std::invalid_argument);
  CHECK_THROWS_AS(make_cylinder(o, Vec3::UnitZ(), 1, 1, 2, 1, Fill::shell), std::invalid_argument);
  CHECK_THROWS_AS(make_cylinder(o, Vec3::UnitZ(), 1, 1, 8, 0, Fill::shell), std::invalid_argument);
  SurfaceMesh open;
  open.V = {Vec3(0, 0, 0), Vec3(1, 0, 0), Vec3(0, 1, 0)};
  open.F = {{0, 1, 2}};
  CHECK_THROWS_AS(make_from_surface(open, 1.0, o, Fill::shell), std::invalid_argument);
  SurfaceMesh octa;
  octa.V = {Vec3(1, 0, 0),  Vec3(-1, 0, 0), Vec3(0, 1, 0),
            Vec3(0, -1, 0), Vec3(0, 0, 1),  Vec3(0, 0, -1)};
  octa.F = {{0, 2, 4}, {2, 1, 4}, {1, 3, 4}, {3, 0, 4}, {2, 0, 5}, {1, 2, 5}, {3, 1, 5}, {0, 3, 5}};
  CHECK_THROWS_AS(make_from_surface(octa, 0.0, o, Fill::shell), std::invalid_argument);
  for (Tri& t : octa.F) std::swap(t[1], t[2]);  // inward: rejected, not silently flipped
  CHECK_THROWS_AS(finish_model(octa.V, octa.F, Fill::shell), std::invalid_argument);
}

namespace {
// Generalised winding number of a closed surface at p (solid angles, Van Oosterom-Strackee).
double winding_number(const Points& V, const std::vector<Tri>& F, const Vec3& p) {
  double sum = 0.0;
  for (const Tri& t : F) {
    const Vec3 a = V[t[0]] - p, b = V[t[1]] - p, c = V[t[2]] - p;
    const double la = a.norm(), lb = b.norm(), lc = c.norm();
    const double num = a.dot(b.cross(c));
    const double den = la * lb * lc + a.dot(b) * lc + b.dot(c) * la + c.dot(a) * lb;
    sum += 2.0 * std::atan2(num, den);
  }
  return sum / (4.0 * kPi);
}

double distance_to_vertices(const ShapeModel& m, const Vec3& p) {
  double d = 1e300;
  for (int i = 0; i < m.n_surface; ++i) d = std::min(d, (m.nodes[i] - p).norm());
  return d;
}
}  // namespace

TEST_CASE("volume fill keeps exactly the lattice points inside", "[shapes]") {
  // Rotated, off-centre shapes: interior nodes have winding number 1 and keep clear of the
  // surface vertices.
  const ShapeModel shapes[] = {
      make_cylinder(Vec3(0.3, -0.2, 0.1), Vec3(1, 1, 0.3), 0.4, 2.0, 16, 6, Fill::volume),
      make_ellipsoid(Vec3(-1, 2, 0.5), Vec3(1.0, 0.6, 0.3), 3, Fill::volume),
      make_sphere(Vec3(0.1, 0.2, 0.3), 1.0, 3, Fill::volume)};
  for (const ShapeModel& m : shapes) {
    check_model(m, true);
    const Points S(m.nodes.begin(), m.nodes.begin() + m.n_surface);
    const int interior = static_cast<int>(m.nodes.size()) - m.n_surface;
    CHECK(interior > 10);
    for (std::size_t i = static_cast<std::size_t>(m.n_surface); i < m.nodes.size(); ++i)
      CHECK(winding_number(S, m.faces, m.nodes[i]) == Approx(1.0).margin(1e-9));
  }
  // The sphere's lattice: its spacing is the mean edge length, and all lattice points deeper
  // than one spacing are kept, so the count matches the volume of the inner ball.
  const ShapeModel& s = shapes[2];
  double h = 0.0;
  for (const Tri& t : s.faces)
    for (int k = 0; k < 3; ++k) h += (s.nodes[t[k]] - s.nodes[t[(k + 1) % 3]]).norm();
  h /= 3.0 * static_cast<double>(s.faces.size());
  const int interior = static_cast<int>(s.nodes.size()) - s.n_surface;
  const double rin = 1.0 - 0.4 * h;
  CHECK(interior == Approx(4.0 / 3.0 * kPi * rin * rin * rin / (h * h * h)).epsilon(0.15));
  for (std::size_t i = static_cast<std::size_t>(s.n_surface); i < s.nodes.size(); ++i)
    CHECK(distance_to_vertices(s, s.nodes[i]) > 0.4 * h);
}

TEST_CASE("volume fill of a hollow sphere leaves the cavity empty", "[shapes]") {
  // Outer sphere outward, inner sphere inward: two components, Euler characteristic 4.
  const ShapeModel outer = make_sphere(Vec3::Zero(), 1.0, 3, Fill::shell);
  const ShapeModel inner = make_sphere(Vec3::Zero(), 0.5, 3, Fill::shell);
  Points V = outer.nodes;
  std::vector<Tri> F = outer.faces;
  const int base = static_cast<int>(V.size());
  V.insert(V.end(), inner.nodes.begin(), inner.nodes.end());
  for (const Tri& t : inner.faces) F.push_back({base + t[0], base + t[2], base + t[1]});
  const ShapeModel m = finish_model(V, F, Fill::volume);
  CHECK(m.volume == Approx(outer.volume - inner.volume));
  CHECK(m.nodes.size() > V.size() + 50);
  double sum = 0.0;
  for (double v : m.node_volume) sum += v;
  CHECK(sum == Approx(m.volume));
  for (std::size_t i = V.size(); i < m.nodes.size(); ++i) {
    const double r = m.nodes[i].norm();
    CHECK((r > 0.5 && r < 1.0));
  }
}

// The surface's triangles as sets of rest positions, mirrored x -> lo + hi - x along `axis`.
namespace {
std::set<std::array<std::array<long long, 3>, 3>> mirrored_faces(const ShapeModel& m, int axis, double mid2) {
  std::set<std::array<std::array<long long, 3>, 3>> out;
  for (const Tri& t : m.faces) {
    std::array<std::array<long long, 3>, 3> tri;
    for (int v = 0; v < 3; ++v) {
      Vec3 p = m.nodes[t[v]];
      if (axis >= 0) p[axis] = mid2 - p[axis];
      for (int a = 0; a < 3; ++a) tri[v][a] = std::llround(p[a] * 1e6);
    }
    std::sort(tri.begin(), tri.end());
    out.insert(tri);
  }
  return out;
}
}  // namespace

TEST_CASE("box: alternating diagonals make a closed surface that the mirrors keep", "[shapes]") {
  const Vec3 lo(-2, -2, 0), hi(2, 2, 1);
  const ShapeModel alt = make_box(lo, hi, Vec3i(4, 4, 2), true);
  const ShapeModel aligned = make_box(lo, hi, Vec3i(4, 4, 2), false);
  check_model(alt, true);
  CHECK(alt.faces.size() == aligned.faces.size());
  CHECK(alt.springs == aligned.springs);
  const auto a0 = mirrored_faces(alt, -1, 0.0), b0 = mirrored_faces(aligned, -1, 0.0);
  for (int axis = 0; axis < 3; ++axis) {
    INFO("mirror across the mid-plane of axis " << axis);
    CHECK(mirrored_faces(alt, axis, lo[axis] + hi[axis]) == a0);
    CHECK(mirrored_faces(aligned, axis, lo[axis] + hi[axis]) != b0);  // the aligned surface has a handedness
  }
}

TEST_CASE("box: alternating diagonals on a face of an odd cell count break that mirror", "[shapes]") {
  const ShapeModel alt = make_box(Vec3(-1.5, -2, 0), Vec3(1.5, 2, 1), Vec3i(3, 4, 2), true);
  const auto a0 = mirrored_faces(alt, -1, 0.0);
  CHECK(mirrored_faces(alt, 0, 0.0) != a0);  // 3 cells along x
  CHECK(mirrored_faces(alt, 1, 0.0) == a0);  // 4 along y
}
