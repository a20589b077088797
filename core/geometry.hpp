// Small geometric routines shared by shapes, exact detectors, measurements and tests.
#pragma once

#include "core/types.hpp"

#include <numeric>
#include <vector>

namespace harness {

// Closest point to p on triangle (a, b, c) (Ericson, Real-Time Collision Detection, 5.1.5).
// A collapsed triangle gives a point of it, not necessarily the closest: callers that meet
// degenerate triangles use closest_on_segment on its edges as well.
Vec3 closest_on_triangle(const Vec3& p, const Vec3& a, const Vec3& b, const Vec3& c);
// Barycentric coordinates (summing to one) of a point q of triangle (a, b, c); for a collapsed
// triangle, all weight on the vertex nearest to q.
void barycentric(const Vec3& q, const Vec3& a, const Vec3& b, const Vec3& c, double w[3]);
// Closest point to p on segment [a, b] (safe when a == b).
Vec3 closest_on_segment(const Vec3& p, const Vec3& a, const Vec3& b);

// Disjoint sets over 0..n-1 with path halving; unite(a, b) keeps a's root.
struct UnionFind {
  std::vector<int> parent;
  explicit UnionFind(std::size_t n) : parent(n) { std::iota(parent.begin(), parent.end(), 0); }
  int find(int x) {
    while (parent[x] != x) {
      parent[x] = parent[parent[x]];
      x = parent[x];
    }
    return x;
  }
  void unite(int a, int b) {
    a = find(a);
    b = find(b);
    if (a != b) parent[b] = a;
  }
};

}  // namespace harness
