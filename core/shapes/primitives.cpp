// The primitive shapes: icosphere (sphere, ellipsoid), cylinder, and a surface read from a
// mesh file; each a closed outward surface handed to finish_model (model.cpp).
#include "core/edge_key.hpp"
#include "core/shapes/internal.hpp"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <utility>

namespace harness {

using shapes::isize;
using shapes::require;
using shapes::require_finite;

namespace {

void icosphere(int subdivisions, Points& V, std::vector<Tri>& F) {
  const double t = (1.0 + std::sqrt(5.0)) / 2.0;
  V = {Vec3(-1, t, 0), Vec3(1, t, 0), Vec3(-1, -t, 0), Vec3(1, -t, 0),
       Vec3(0, -1, t), Vec3(0, 1, t), Vec3(0, -1, -t), Vec3(0, 1, -t),
       Vec3(t, 0, -1), Vec3(t, 0, 1), Vec3(-t, 0, -1), Vec3(-t, 0, 1)};
  for (Vec3& v : V) v.normalize();
  F = {{0, 11, 5},  {0, 5, 1},  {0, 1, 7},  {0, 7, 10}, {0, 10, 11}, {1, 5, 9}, {5, 11, 4},
       {11, 10, 2}, {10, 7, 6}, {7, 1, 8},  {3, 9, 4},  {3, 4, 2},   {3, 2, 6}, {3, 6, 8},
       {3, 8, 9},   {4, 9, 5},  {2, 4, 11}, {6, 2, 10}, {8, 6, 7},   {9, 8, 1}};
  for (int s = 0; s < subdivisions; ++s) {
    // Shared midpoints found by sorting the half-edges by edge (no hash map of 30M entries).
    const std::size_t nf = F.size();
    std::vector<std::pair<std::uint64_t, std::uint32_t>> half(3 * nf);
    for (std::size_t f = 0; f < nf; ++f)
      for (int k = 0; k < 3; ++k)
        half[3 * f + k] = {edge_key(F[f][k], F[f][(k + 1) % 3]),
                           static_cast<std::uint32_t>(3 * f + k)};
    std::sort(half.begin(), half.end());
    std::vector<int> mid(3 * nf);
    for (std::size_t i = 0; i < half.size(); ++i) {
      if (i == 0 || half[i].first != half[i - 1].first) {
        const Edge e = key_edge(half[i].first);
        V.push_back((V[e[0]] + V[e[1]]).normalized());
      }
      mid[half[i].second] = isize(V) - 1;
    }
    std::vector<Tri> G(4 * nf);
    for (std::size_t f = 0; f < nf; ++f) {
      const int a = F[f][0], b = F[f][1], c = F[f][2];
      const int ab = mid[3 * f], bc = mid[3 * f + 1], ca = mid[3 * f + 2];
      G[4 * f] = {a, ab, ca};
      G[4 * f + 1] = {ab, b, bc};
      G[4 * f + 2] = {ca, bc, c};
      G[4 * f + 3] = {ab, bc, ca};
    }
    F.swap(G);
  }
}

Vec3 frame_normal(const Vec3& axis) {
  // Any unit vector perpendicular to axis: cross with the least aligned coordinate axis.
  Eigen::Index i = 0;
  axis.cwiseAbs().minCoeff(&i);
  return axis.cross(Vec3::Unit(i)).normalized();
}

ShapeModel icosahedral(const Vec3& center, const Vec3& radii, int subdivisions, Fill fill,
                       const char* who) {
  const std::string w(who);
  require_finite(center, (w + ": center").c_str());
  require(radii.allFinite() && (radii.array() > 0.0).all(), w + ": radius must be positive");
  require(subdivisions >= 0 && subdivisions <= kMaxSubdivisions,
          w + ": subdivisions must be in [0, " + std::to_string(kMaxSubdivisions) + "], got " +
              std::to_string(subdivisions));
  Points V;
  std::vector<Tri> F;
  icosphere(subdivisions, V, F);
  for (Vec3& v : V) v = center + radii.cwiseProduct(v);
  return finish_model(std::move(V), std::move(F), fill);
}

}  // namespace

ShapeModel make_sphere(const Vec3& center, double radius, int subdivisions, Fill fill) {
  return icosahedral(center, Vec3::Constant(radius), subdivisions, fill, "sphere");
}

ShapeModel make_ellipsoid(const Vec3& center, const Vec3& radii, int subdivisions, Fill fill) {
  return icosahedral(center, radii, subdivisions, fill, "ellipsoid");
}

ShapeModel make_cylinder(const Vec3& center, const Vec3& axis, double radius, double length,
                         int segments, int rings, Fill fill) {
  require_finite(center, "cylinder: center");
  require(axis.allFinite() && axis.norm() > 0.0, "cylinder: axis must be a non-zero vector");
  require(std::isfinite(radius) && radius > 0.0, "cylinder: radius must be positive");
  require(std::isfinite(length) && length > 0.0, "cylinder: length must be positive");
  require(segments >= 3, "cylinder: segments must be >= 3");
  require(rings >= 1, "cylinder: rings must be >= 1");
  require(static_cast<long long>(segments) * (static_cast<long long>(rings) + 1) + 2 <=
              kMaxCylinderNodes,
          "cylinder: too many nodes (limit " + std::to_string(kMaxCylinderNodes) + ")");
  // Right-handed frame (u, w, a): u x w = a, so increasing angle turns counter-clockwise
  // about the axis.
  const Vec3 a = axis.normalized();
  const Vec3 u = frame_normal(a);
  const Vec3 w = a.cross(u);
  const double pi = std::acos(-1.0);
  Points V;
  for (int r = 0; r <= rings; ++r) {
    const Vec3 c = center + a * (length * (static_cast<double>(r) / rings - 0.5));
    for (int s = 0; s < segments; ++s) {
      const double th = 2.0 * pi * s / segments;
      V.push_back(c + radius * (std::cos(th) * u + std::sin(th) * w));
    }
  }
  const int bottom = isize(V), top = bottom + 1;
  V.push_back(center - 0.5 * length * a);
  V.push_back(center + 0.5 * length * a);
  std::vector<Tri> F;
  auto ring = [&](int r, int s) { return r * segments + s % segments; };
  for (int r = 0; r < rings; ++r)
    for (int s = 0; s < segments; ++s) {
      // Tangent (A->B) x axial (B->C) points outward.
      const int A = ring(r, s), B = ring(r, s + 1), C = ring(r + 1, s + 1), D = ring(r + 1, s);
      F.push_back({A, B, C});
      F.push_back({A, C, D});
    }
  for (int s = 0; s < segments; ++s) {
    F.push_back({bottom, ring(0, s + 1), ring(0, s)});
    F.push_back({top, ring(rings, s), ring(rings, s + 1)});
  }
  return finish_model(std::move(V), std::move(F), fill);
}

ShapeModel make_from_surface(const SurfaceMesh& mesh, double scale, const Vec3& translate,
                             Fill fill) {
  require(std::isfinite(scale) && scale > 0.0, "mesh: scale must be positive");
  require_finite(translate, "mesh: translate");
  Points V = mesh.V;
  for (Vec3& v : V) v = v * scale + translate;
  return finish_model(std::move(V), mesh.F, fill);
}

}  // namespace harness
