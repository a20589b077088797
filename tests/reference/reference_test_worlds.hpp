// Hand-built closed surfaces and Worlds for the reference tests (independent of core/shapes):
// icospheres, subdivided box surfaces, random rigid motions.
#pragma once

#include "core/geometry.hpp"
#include "tests/core/collision/collision_test_worlds.hpp"
#include "core/world.hpp"

#include <Eigen/Geometry>

#include <cmath>
#include <map>
#include <random>
#include <string>
#include <tuple>
#include <utility>
#include <vector>

namespace harness::reftest {

struct Surface {
  Points V;              // surface vertices first; interior nodes may follow (n_surface marks the end)
  std::vector<Tri> F;    // outward triangles over 0..n_surface-1
  int n_surface = 0;
};

// Flips every triangle whose normal points towards `inside` (star-shaped surfaces only).
inline void orient_outward(Surface& s, const Vec3& inside) {
  for (Tri& t : s.F) {
    const Vec3 &a = s.V[t[0]], &b = s.V[t[1]], &c = s.V[t[2]];
    if ((b - a).cross(c - a).dot((a + b + c) / 3.0 - inside) < 0) std::swap(t[1], t[2]);
  }
}

// Icosahedron subdivided `sub` times (each triangle split in four), projected onto the sphere.
inline Surface icosphere(const Vec3& c, double r, int sub) {
  const double p = (1.0 + std::sqrt(5.0)) / 2.0;
  Points v = {{-1, p, 0}, {1, p, 0}, {-1, -p, 0}, {1, -p, 0}, {0, -1, p}, {0, 1, p},
              {0, -1, -p}, {0, 1, -p}, {p, 0, -1}, {p, 0, 1}, {-p, 0, -1}, {-p, 0, 1}};
  for (Vec3& q : v) q.normalize();
  std::vector<Tri> f = {{0, 11, 5}, {0, 5, 1},  {0, 1, 7},   {0, 7, 10}, {0, 10, 11},
                        {1, 5, 9},  {5, 11, 4}, {11, 10, 2}, {10, 7, 6}, {7, 1, 8},
                        {3, 9, 4},  {3, 4, 2},  {3, 2, 6},   {3, 6, 8},  {3, 8, 9},
                        {4, 9, 5},  {2, 4, 11}, {6, 2, 10},  {8, 6, 7},  {9, 8, 1}};
  for (int s = 0; s < sub; ++s) {
    std::map<std::pair<int, int>, int> mid;
    auto midpoint = [&](int a, int b) {
      const auto key = std::make_pair(std::min(a, b), std::max(a, b));
      auto it = mid.find(key);
      if (it != mid.end()) return it->second;
      v.push_back((v[a] + v[b]).normalized());
      mid[key] = static_cast<int>(v.size()) - 1;
      return static_cast<int>(v.size()) - 1;
    };
    std::vector<Tri> g;
    for (const Tri& t : f) {
      const int ab = midpoint(t[0], t[1]), bc = midpoint(t[1], t[2]), ca = midpoint(t[2], t[0]);
      g.push_back({t[0], ab, ca});
      g.push_back({t[1], bc, ab});
      g.push_back({t[2], ca, bc});
      g.push_back({ab, bc, ca});
    }
    f.swap(g);
  }
  Surface out;
  out.F = f;
  for (const Vec3& q : v) out.V.push_back(c + r * q);
  out.n_surface = static_cast<int>(out.V.size());
  orient_outward(out, c);
  return out;
}

// Surface of the box [lo, hi] with n[axis] cells along each axis, quads split in two.
inline Surface box_surface(const Vec3& lo, const Vec3& hi, const Vec3i& n) {
  Surface s;
  std::map<std::tuple<int, int, int>, int> id;
  auto vertex = [&](int i, int j, int k) {
    const auto key = std::make_tuple(i, j, k);
    auto it = id.find(key);
    if (it != id.end()) return it->second;
    s.V.push_back(Vec3(lo.x() + (hi.x() - lo.x()) * i / n.x(), lo.y() + (hi.y() - lo.y()) * j / n.y(),
                       lo.z() + (hi.z() - lo.z()) * k / n.z()));
    id[key] = static_cast<int>(s.V.size()) - 1;
    return id[key];
  };
  for (int axis = 0; axis < 3; ++axis) {
    const int u = (axis + 1) % 3, w = (axis + 2) % 3;
    for (int side = 0; side < 2; ++side)
      for (int a = 0; a < n[u]; ++a)
        for (int b = 0; b < n[w]; ++b) {
          auto at = [&](int da, int db) {
            int ijk[3];
            ijk[axis] = side * n[axis];
            ijk[u] = a + da;
            ijk[w] = b + db;
            return vertex(ijk[0], ijk[1], ijk[2]);
          };
          const int p00 = at(0, 0), p10 = at(1, 0), p11 = at(1, 1), p01 = at(0, 1);
          s.F.push_back({p00, p10, p11});
          s.F.push_back({p00, p11, p01});
        }
  }
  s.n_surface = static_cast<int>(s.V.size());
  orient_outward(s, (lo + hi) / 2.0);  // a box is convex: its centre sees every face outward
  return s;
}

// Appends a body (unit masses, at rest) holding s.V; returns its index.
inline int add_body(World& w, const std::string& name, const Surface& s) {
  return harness::test::add_body(w, name, harness::test::NodeSet{s.V, s.n_surface, s.F});
}

inline void translate_body(World& w, int body, const Vec3& d) {
  for (int i = w.bodies[body].begin; i < w.bodies[body].end; ++i) w.x[i] += d;
}

// Uniform random rotation (normalised Gaussian quaternion).
inline Eigen::Matrix3d random_rotation(std::mt19937& rng) {
  std::normal_distribution<double> g(0.0, 1.0);
  Eigen::Quaterniond q(g(rng), g(rng), g(rng), g(rng));
  q.normalize();
  return q.toRotationMatrix();
}

// Largest angle (rad) between the two ends of an edge, seen from c: the mesh's angular resolution.
inline double max_edge_angle(const Surface& s, const Vec3& c) {
  double a = 0.0;
  for (const Tri& t : s.F)
    for (int k = 0; k < 3; ++k) {
      const Vec3 p = (s.V[t[k]] - c).normalized(), q = (s.V[t[(k + 1) % 3]] - c).normalized();
      a = std::max(a, std::acos(std::min(1.0, p.dot(q))));
    }
  return a;
}

}  // namespace harness::reftest

namespace harness::reftest {

// A lower bound of the distance from c to the surface (the nearest face plane): for a surface
// star-shaped about c, every point nearer to c than this is strictly inside.
inline double min_plane_distance(const Surface& s, const Vec3& c) {
  double d = 1e300;
  for (const Tri& t : s.F) {
    const Vec3 n = (s.V[t[1]] - s.V[t[0]]).cross(s.V[t[2]] - s.V[t[0]]).normalized();
    d = std::min(d, std::fabs(n.dot(s.V[t[0]] - c)));
  }
  return d;
}

}  // namespace harness::reftest

namespace harness::reftest {

using harness::closest_on_segment;
using harness::closest_on_triangle;

}  // namespace harness::reftest
