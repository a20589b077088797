// The surface checks (check_surface, mesh.hpp): closed, 2-manifold, consistently oriented, outward;
// messages rank problems so that the most basic one is reported.
#include "core/mesh_internal.hpp"

#include "core/edge_key.hpp"
#include "core/geometry.hpp"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <numeric>

namespace harness {

namespace {
template <class C>
int isize(const C& c) {
  return static_cast<int>(c.size());
}
}  // namespace

namespace mesh_detail {
namespace {

std::string vname(const Labels& l, int v) {
  return "vertex " + std::to_string(l.vertex ? (*l.vertex)[v] : static_cast<long long>(v));
}
std::string fname(const Labels& l, int f) {
  if (l.face_line) return "the face on line " + std::to_string((*l.face_line)[f]);
  return "face " + std::to_string(f);
}

// All checks of check_surface; messages are ranked so the most basic problem is reported.
class SurfaceAnalysis {
 public:
  SurfaceAnalysis(const Points& V, const std::vector<Tri>& F, const Labels& lab)
      : V_(V), F_(F), lab_(lab), nv_(isize(V)), nf_(isize(F)), corners_(3 * F.size()),
        verts_(static_cast<std::size_t>(nv_)) {}

  SurfaceReport run() {
    if (F_.empty()) {
      r_.problem = "the surface has no faces";
      return r_;
    }
    if (!check_faces()) return finish();
    check_edges();
    check_fans();
    for (int v = 0; v < nv_; ++v)
      if (verts_.find(v) == v) ++r_.components;
    r_.euler = nv_ - n_edges_ + nf_;
    r_.signed_volume = signed_volume(V_, F_);
    if (!(r_.signed_volume > 0.0))
      note(kVolume, "signed volume " + std::to_string(r_.signed_volume) +
                        " is not positive (inward orientation or empty)");
    return finish();
  }

 private:
  enum { kRange, kDegenerate, kEdgeMany, kOpen, kPinched, kUnused, kOrient, kVolume, kCount };
  // Every directed half-edge, grouped by its undirected edge.
  struct Half {
    std::uint64_t key;
    int face;
    int corner;  // the half-edge runs from corner to corner+1 of the face
  };

  void note(int kind, const std::string& msg) {
    if (problem_[kind].empty()) problem_[kind] = msg;
  }
  SurfaceReport finish() {
    for (const auto& p : problem_)
      if (!p.empty()) {
        r_.problem = p;
        break;
      }
    return r_;
  }

  // Indices in range, no repeated vertex in a face; false when either fails.
  bool check_faces() {
    for (int f = 0; f < nf_; ++f) {
      for (int k = 0; k < 3; ++k)
        if (F_[f][k] < 0 || F_[f][k] >= nv_)
          note(kRange, fname(lab_, f) + " has vertex index " + std::to_string(F_[f][k]) + " out of range [0, " +
                           std::to_string(nv_) + ")");
      if (F_[f][0] == F_[f][1] || F_[f][1] == F_[f][2] || F_[f][2] == F_[f][0])
        note(kDegenerate, fname(lab_, f) + " repeats a vertex (degenerate)");
    }
    return problem_[kRange].empty() && problem_[kDegenerate].empty();
  }

  // Closed (two faces per edge), edge-manifold, consistently oriented; joins the corners of the
  // two faces of every edge into fans around its end vertices, and the vertices into components.
  void check_edges() {
    std::vector<Half> half(3 * F_.size());
    for (int f = 0; f < nf_; ++f)
      for (int k = 0; k < 3; ++k) half[3 * f + k] = {edge_key(F_[f][k], F_[f][(k + 1) % 3]), f, k};
    std::sort(half.begin(), half.end(),
              [](const Half& a, const Half& b) { return a.key != b.key ? a.key < b.key : a.face < b.face; });
    r_.closed = true;
    r_.oriented = true;
    for (std::size_t i = 0; i < half.size();) {
      std::size_t j = i;
      while (j < half.size() && half[j].key == half[i].key) ++j;
      edge(half[i], j - i, j - i == 2 ? &half[i + 1] : nullptr);
      i = j;
    }
  }

  void edge(const Half& h0, std::size_t count, const Half* h1) {
    ++n_edges_;
    const int u = F_[h0.face][h0.corner], w = F_[h0.face][(h0.corner + 1) % 3];
    verts_.unite(u, w);
    const std::string name = "edge (" + vname(lab_, u) + ", " + vname(lab_, w) + ")";
    if (count == 1) {
      r_.closed = false;
      note(kOpen, name + " belongs only to " + fname(lab_, h0.face) + ": the surface is not closed");
      return;
    }
    if (count > 2) {
      r_.closed = false;
      edges_manifold_ = false;
      note(kEdgeMany, name + " is shared by " + std::to_string(count) + " faces (" + fname(lab_, h0.face) +
                          " and others): not 2-manifold");
      return;
    }
    if (F_[h1->face][h1->corner] == u) {
      r_.oriented = false;
      note(kOrient, fname(lab_, h0.face) + " and " + fname(lab_, h1->face) + " traverse " + name +
                        " in the same direction: inconsistent orientation");
    }
    // The two faces are neighbours in the fans around both end vertices.
    corners_.unite(corner_of(h0.face, u), corner_of(h1->face, u));
    corners_.unite(corner_of(h0.face, w), corner_of(h1->face, w));
  }

  int corner_of(int f, int v) const {  // corner 3f+k = vertex F[f][k] inside face f
    for (int k = 0; k < 3; ++k)
      if (F_[f][k] == v) return 3 * f + k;
    return 3 * f;  // unreachable: v is a vertex of f
  }

  // Fans per vertex: the corner sets left after joining neighbours across shared edges.
  void check_fans() {
    std::vector<int> fans(static_cast<std::size_t>(nv_), 0);
    for (int c = 0; c < 3 * nf_; ++c)
      if (corners_.find(c) == c) ++fans[F_[c / 3][c % 3]];
    bool fans_ok = true;
    for (int v = 0; v < nv_; ++v) {
      if (fans[v] == 0) {
        fans_ok = false;
        note(kUnused, vname(lab_, v) + " is referenced by no face");
      } else if (fans[v] > 1 && edges_manifold_) {
        fans_ok = false;
        note(kPinched, "the faces around " + vname(lab_, v) + " form " + std::to_string(fans[v]) +
                           " separate fans: not 2-manifold");
      }
    }
    r_.manifold = r_.closed && edges_manifold_ && fans_ok;
  }

  const Points& V_;
  const std::vector<Tri>& F_;
  const Labels& lab_;
  int nv_, nf_;
  SurfaceReport r_;
  std::string problem_[kCount];
  UnionFind corners_, verts_;
  int n_edges_ = 0;
  bool edges_manifold_ = true;
};

}  // namespace

SurfaceReport analyze(const Points& V, const std::vector<Tri>& F, const Labels& lab) {
  return SurfaceAnalysis(V, F, lab).run();
}

}  // namespace mesh_detail

double signed_volume(const Points& V, const std::vector<Tri>& F) {
  // Divergence theorem over tetrahedra (origin, a, b, c); origin at the first vertex keeps the
  // sum well conditioned for meshes far from the origin.
  if (V.empty()) return 0.0;
  const Vec3 o = V[0];
  double six_v = 0.0;
  for (const Tri& t : F) {
    if (t[0] < 0 || t[1] < 0 || t[2] < 0 || t[0] >= isize(V) || t[1] >= isize(V) ||
        t[2] >= isize(V))
      continue;
    six_v += (V[t[0]] - o).dot((V[t[1]] - o).cross(V[t[2]] - o));
  }
  return six_v / 6.0;
}

SurfaceReport check_surface(const SurfaceMesh& mesh) { return mesh_detail::analyze(mesh.V, mesh.F, mesh_detail::Labels{}); }

}  // namespace harness
