// Small hand-built Worlds for the collision tests (independent of core/shapes.hpp): point
// clouds, a box lattice with an outward-oriented surface, an icosahedron.
#pragma once

#include "core/world.hpp"

#include <cmath>
#include <map>
#include <tuple>
#include <vector>

namespace harness::test {

struct NodeSet {
  Points nodes;          // surface vertices first
  int n_surface = 0;
  std::vector<Tri> faces;  // outward, over 0..n_surface-1
};

// Appends a body (unit masses, at rest) and returns its index.
inline int add_body(World& w, const std::string& name, const NodeSet& s) {
  Body b;
  b.name = name;
  b.begin = w.num_nodes();
  b.end = b.begin + static_cast<int>(s.nodes.size());
  b.n_surface = s.n_surface;
  b.faces = s.faces;
  b.vf_start.assign(static_cast<std::size_t>(s.n_surface) + 1, 0);
  for (const Tri& t : s.faces)
    for (int v : t) ++b.vf_start[v + 1];
  for (int i = 0; i < s.n_surface; ++i) b.vf_start[i + 1] += b.vf_start[i];
  b.vf_faces.assign(b.vf_start.back(), 0);
  std::vector<int> cursor(b.vf_start.begin(), b.vf_start.end() - 1);
  for (int f = 0; f < static_cast<int>(s.faces.size()); ++f)
    for (int v : s.faces[f]) b.vf_faces[cursor[v]++] = f;
  b.rest_min = Vec3::Constant(1e300);
  b.rest_max = Vec3::Constant(-1e300);
  for (const Vec3& p : s.nodes) {
    w.x.push_back(p);
    w.v.push_back(Vec3::Zero());
    w.f.push_back(Vec3::Zero());
    w.m.push_back(1.0);
    w.inv_m.push_back(1.0);
    w.kinematic.push_back(Kinematic::free);
    w.kin_v.push_back(Vec3::Zero());
    b.rest_min = b.rest_min.cwiseMin(p);
    b.rest_max = b.rest_max.cwiseMax(p);
  }
  b.spring_begin = b.spring_end = static_cast<int>(w.springs.size());
  w.bodies.push_back(b);
  w.body_law.push_back(BodyLaw{});
  return static_cast<int>(w.bodies.size()) - 1;
}

inline NodeSet cloud(const Points& p, int n_surface = 0) {
  NodeSet s;
  s.nodes = p;
  s.n_surface = n_surface;
  return s;
}

// Lattice of (c.x+1)(c.y+1)(c.z+1) nodes over [lo, hi]; boundary nodes first, the boundary
// quads split into outward triangles.
inline NodeSet box_lattice(const Vec3& lo, const Vec3& hi, const Vec3i& c) {
  auto boundary = [&](int i, int j, int k) {
    return i == 0 || j == 0 || k == 0 || i == c.x() || j == c.y() || k == c.z();
  };
  auto pos = [&](int i, int j, int k) {
    return Vec3(lo.x() + (hi.x() - lo.x()) * i / c.x(), lo.y() + (hi.y() - lo.y()) * j / c.y(),
                lo.z() + (hi.z() - lo.z()) * k / c.z());
  };
  std::map<std::tuple<int, int, int>, int> id;
  NodeSet s;
  for (int pass = 0; pass < 2; ++pass)
    for (int k = 0; k <= c.z(); ++k)
      for (int j = 0; j <= c.y(); ++j)
        for (int i = 0; i <= c.x(); ++i)
          if (boundary(i, j, k) == (pass == 0)) {
            id[{i, j, k}] = static_cast<int>(s.nodes.size());
            s.nodes.push_back(pos(i, j, k));
          }
  for (const auto& e : id)
    if (boundary(std::get<0>(e.first), std::get<1>(e.first), std::get<2>(e.first))) ++s.n_surface;
  // For each of the six sides, quads over the two in-plane axes, oriented by the outward axis.
  for (int a = 0; a < 3; ++a)
    for (int side = 0; side < 2; ++side) {
      const int b = (a + 1) % 3, d = (a + 2) % 3;
      Vec3 out = Vec3::Zero();
      out[a] = side ? 1.0 : -1.0;
      for (int u = 0; u < c[b]; ++u)
        for (int v = 0; v < c[d]; ++v) {
          int q[4];
          const int du[4] = {0, 1, 1, 0}, dv[4] = {0, 0, 1, 1};
          for (int r = 0; r < 4; ++r) {
            int ijk[3];
            ijk[a] = side ? c[a] : 0;
            ijk[b] = u + du[r];
            ijk[d] = v + dv[r];
            q[r] = id.at({ijk[0], ijk[1], ijk[2]});
          }
          for (Tri t : {Tri{q[0], q[1], q[2]}, Tri{q[0], q[2], q[3]}}) {
            const Vec3 n = (s.nodes[t[1]] - s.nodes[t[0]]).cross(s.nodes[t[2]] - s.nodes[t[0]]);
            if (n.dot(out) < 0) std::swap(t[1], t[2]);
            s.faces.push_back(t);
          }
        }
    }
  return s;
}

// Icosahedron inscribed in the sphere (center, radius), outward faces; optionally a centre node.
inline NodeSet icosahedron(const Vec3& center, double radius, bool centre_node) {
  const double phi = (1.0 + std::sqrt(5.0)) / 2.0;
  Points u;
  for (int s1 : {-1, 1})
    for (int s2 : {-1, 1}) {
      u.emplace_back(0, s1, s2 * phi);
      u.emplace_back(s1, s2 * phi, 0);
      u.emplace_back(s2 * phi, 0, s1);
    }
  NodeSet s;
  for (const Vec3& p : u) s.nodes.push_back(center + radius * p.normalized());
  s.n_surface = 12;
  // Faces: the triples of mutually adjacent vertices (edge length 2 before scaling).
  for (int i = 0; i < 12; ++i)
    for (int j = i + 1; j < 12; ++j)
      for (int k = j + 1; k < 12; ++k) {
        auto adj = [&](int a, int b) { return std::fabs((u[a] - u[b]).norm() - 2.0) < 1e-9; };
        if (!adj(i, j) || !adj(j, k) || !adj(i, k)) continue;
        Tri t{i, j, k};
        const Vec3 n = (u[j] - u[i]).cross(u[k] - u[i]);
        if (n.dot(u[i] + u[j] + u[k]) < 0) std::swap(t[1], t[2]);
        s.faces.push_back(t);
      }
  if (centre_node) s.nodes.push_back(center);
  return s;
}

}  // namespace harness::test
