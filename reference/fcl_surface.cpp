// The FCL translation unit: BVH models of deforming surfaces, triangle-pair collision, and
// GJK/EPA (libccd) signed distance of convex polytopes.
#include "reference/fcl_surface.hpp"

#include <fcl/config.h>
#include <fcl/geometry/bvh/BVH_model.h>
#include <fcl/geometry/shape/convex.h>
#include <fcl/math/bv/AABB.h>
#include <fcl/math/bv/OBBRSS.h>
#include <fcl/narrowphase/collision.h>
#include <fcl/narrowphase/detail/traversal/collision/intersect.h>
#include <fcl/narrowphase/detail/traversal/collision/mesh_collision_traversal_node.h>
#include <fcl/narrowphase/detail/traversal/collision_node.h>
#include <fcl/narrowphase/distance.h>

#include <algorithm>
#include <cmath>
#include <exception>
#include <limits>
#include <stdexcept>
#include <utility>

namespace harness {

using AabbModel = fcl::BVHModel<fcl::AABBd>;
using ObbrssModel = fcl::BVHModel<fcl::OBBRSSd>;

struct FclSurface::Impl {
  FclBv bv = FclBv::aabb;
  FclRefitPolicy policy;
  int n_vertices = 0;
  std::vector<Tri> faces;
  std::unique_ptr<AabbModel> aabb;      // exactly one of the two is set
  std::unique_ptr<ObbrssModel> obbrss;
  bool ready = false;
  int builds = 0, refits = 0, refits_since_build = 0;
  double cost = 0.0, cost_at_build = 0.0;
};

namespace {

double bv_area(const fcl::AABBd& b) {
  const double w = b.width(), h = b.height(), d = b.depth();
  return 2.0 * (w * h + h * d + d * w);
}
double bv_area(const fcl::OBBRSSd& b) {
  const fcl::Vector3d& e = b.obb.extent;  // half extents
  return 8.0 * (e[0] * e[1] + e[1] * e[2] + e[2] * e[0]);
}

// Summed surface area of all node volumes over that of the vertices' bounding box (not the
// root's volume: a refitted OBBRSS root is itself loose).
template <class BV>
double tree_cost_of(const fcl::BVHModel<BV>& m) {
  const int n = m.getNumBVs();
  if (n == 0 || m.num_vertices == 0) return 0.0;
  fcl::AABBd box(m.vertices[0]);
  for (int i = 1; i < m.num_vertices; ++i) box += m.vertices[i];
  double sum = 0.0;
  for (int i = 0; i < n; ++i) sum += bv_area(m.getBV(i).bv);
  const double ref = bv_area(box);
  return ref > 0.0 ? sum / ref : 0.0;
}

template <class BV>
void update_model(std::unique_ptr<fcl::BVHModel<BV>>& m, FclSurface::Impl& s, const Vec3* p) {
  if (!s.ready) {
    m = std::make_unique<fcl::BVHModel<BV>>();
    std::vector<fcl::Vector3d> pts(p, p + s.n_vertices);
    std::vector<fcl::Triangle> tris;
    tris.reserve(s.faces.size());
    for (const Tri& t : s.faces) tris.emplace_back(t[0], t[1], t[2]);
    m->beginModel(static_cast<int>(tris.size()), s.n_vertices);
    m->addSubModel(pts, tris);
    m->endModel();
    ++s.builds;
    s.refits_since_build = 0;
    s.cost = s.cost_at_build = tree_cost_of(*m);
    s.ready = true;
    return;
  }
  // Decided on the state left by the previous update: a tree found degraded is rebuilt on the
  // next step (a degraded tree is still correct, bounding volumes stay conservative; only slower).
  const bool rebuild = s.refits_since_build >= s.policy.rebuild_every ||
                       s.cost > s.policy.cost_growth * s.cost_at_build;
  m->beginReplaceModel();
  for (int i = 0; i < s.n_vertices; ++i) m->replaceVertex(p[i]);
  m->endReplaceModel(/*refit=*/!rebuild, /*bottomup=*/true);
  if (rebuild) {
    ++s.builds;
    s.refits_since_build = 0;
    s.cost = s.cost_at_build = tree_cost_of(*m);
  } else {
    ++s.refits;
    ++s.refits_since_build;
    s.cost = tree_cost_of(*m);
  }
}

const fcl::Transform3d& identity() {
  static const fcl::Transform3d I = fcl::Transform3d::Identity();
  return I;
}

fcl::CollisionRequestd all_pairs_request(bool enable_contact) {
  // One contact per intersecting pair without contact data; the traversal stops once
  // num_max_contacts are found, so it is unbounded here.
  return fcl::CollisionRequestd(std::numeric_limits<std::size_t>::max(), enable_contact);
}

void traverse(AabbModel& a, AabbModel& b, fcl::CollisionResultd& res) {
  fcl::detail::MeshCollisionTraversalNode<fcl::AABBd> node;
  fcl::Transform3d ta = identity(), tb = identity();  // identity: initialize() copies nothing
  fcl::detail::initialize(node, a, ta, b, tb, all_pairs_request(false), res);
  fcl::detail::collide<double>(&node);
}

void traverse(ObbrssModel& a, ObbrssModel& b, fcl::CollisionResultd& res) {
  fcl::detail::MeshCollisionTraversalNodeOBBRSS<double> node;
  fcl::detail::initialize(node, a, identity(), b, identity(), all_pairs_request(false), res);
  fcl::detail::collide<double>(&node);
}

}  // namespace

FclSurface::FclSurface(FclBv bv, FclRefitPolicy policy) : impl_(std::make_unique<Impl>()) {
  impl_->bv = bv;
  impl_->policy = policy;
}
FclSurface::~FclSurface() = default;
FclSurface::FclSurface(FclSurface&&) noexcept = default;
FclSurface& FclSurface::operator=(FclSurface&&) noexcept = default;

void FclSurface::set_topology(int n_vertices, const std::vector<Tri>& F) {
  if (n_vertices < 3 || F.empty())
    throw std::invalid_argument("FclSurface: a surface needs vertices and triangles");
  Impl& s = *impl_;
  for (const Tri& t : F)
    for (int v : t)
      if (v < 0 || v >= n_vertices)
        throw std::invalid_argument("FclSurface: vertex index out of range");
  s.n_vertices = n_vertices;
  s.faces = F;
  s.aabb.reset();
  s.obbrss.reset();
  s.ready = false;
  s.builds = s.refits = s.refits_since_build = 0;
  s.cost = s.cost_at_build = 0.0;
}

void FclSurface::update(const Vec3* points) {
  Impl& s = *impl_;
  if (s.bv == FclBv::aabb)
    update_model(s.aabb, s, points);
  else
    update_model(s.obbrss, s, points);
}

FclBv FclSurface::bv() const { return impl_->bv; }
int FclSurface::num_vertices() const { return impl_->n_vertices; }
const std::vector<Tri>& FclSurface::faces() const { return impl_->faces; }
const Vec3& FclSurface::vertex(int i) const {
  return impl_->bv == FclBv::aabb ? impl_->aabb->vertices[i] : impl_->obbrss->vertices[i];
}
bool FclSurface::ready() const { return impl_->ready; }
int FclSurface::builds() const { return impl_->builds; }
int FclSurface::refits() const { return impl_->refits; }
double FclSurface::tree_cost() const { return impl_->cost; }

void intersecting_pairs(FclSurface& a, FclSurface& b, std::vector<TrianglePair>& out,
                        bool with_depth) {
  out.clear();
  if (a.bv() != b.bv()) throw std::invalid_argument("intersecting_pairs: bounding volumes differ");
  if (!a.ready() || !b.ready()) throw std::logic_error("intersecting_pairs: surface not updated");
  fcl::CollisionResultd res;
  if (a.bv() == FclBv::aabb)
    traverse(*a.impl().aabb, *b.impl().aabb, res);
  else
    traverse(*a.impl().obbrss, *b.impl().obbrss, res);
  const std::size_t n = res.numContacts();
  out.resize(n);
  for (std::size_t i = 0; i < n; ++i) {
    const fcl::Contactd& c = res.getContact(i);
    out[i].a = c.b1;
    out[i].b = c.b2;
  }
  if (!with_depth) return;
  const auto& fa = a.faces();
  const auto& fb = b.faces();
  for (TrianglePair& p : out) {
    // The very computation of MeshCollisionTraversalNode::leafTesting with enable_contact.
    fcl::Vector3d contacts[2];
    unsigned int n_contacts = 0;
    double depth = 0.0;
    fcl::Vector3d normal;
    const Tri& ta = fa[p.a];
    const Tri& tb = fb[p.b];
    if (fcl::detail::Intersect<double>::intersect_Triangle(
            a.vertex(ta[0]), a.vertex(ta[1]), a.vertex(ta[2]), b.vertex(tb[0]), b.vertex(tb[1]),
            b.vertex(tb[2]), contacts, &n_contacts, &depth, &normal) &&
        n_contacts > 0) {
      p.depth = depth;
      p.has_depth = true;
    }
  }
}

void intersecting_pairs_brute_force(const FclSurface& a, const FclSurface& b,
                                    std::vector<TrianglePair>& out) {
  out.clear();
  const auto& fa = a.faces();
  const auto& fb = b.faces();
  for (int i = 0; i < static_cast<int>(fa.size()); ++i)
    for (int j = 0; j < static_cast<int>(fb.size()); ++j) {
      const Tri& ta = fa[i];
      const Tri& tb = fb[j];
      if (fcl::detail::Intersect<double>::intersect_Triangle(
              a.vertex(ta[0]), a.vertex(ta[1]), a.vertex(ta[2]), b.vertex(tb[0]), b.vertex(tb[1]),
              b.vertex(tb[2])))
        out.push_back(TrianglePair{i, j, 0.0, false});
    }
}

FclCollideResult fcl_collide(const FclSurface& a, const FclSurface& b, bool enable_contact) {
  if (a.bv() != FclBv::obbrss || b.bv() != FclBv::obbrss)
    throw std::invalid_argument("fcl_collide: OBBRSS models only (FCL 0.7 copies AABB models unsafely)");
  const fcl::CollisionGeometryd* ga = a.impl().obbrss.get();
  const fcl::CollisionGeometryd* gb = b.impl().obbrss.get();
  fcl::CollisionResultd res;
  fcl::collide(ga, identity(), gb, identity(), all_pairs_request(enable_contact), res);
  FclCollideResult r;
  r.contacts = static_cast<int>(res.numContacts());
  std::vector<std::pair<int, int>> pairs;
  pairs.reserve(res.numContacts());
  for (std::size_t i = 0; i < res.numContacts(); ++i) {
    const fcl::Contactd& c = res.getContact(i);
    pairs.emplace_back(c.b1, c.b2);
    if (enable_contact) r.max_depth = std::max(r.max_depth, c.penetration_depth);
  }
  std::sort(pairs.begin(), pairs.end());
  r.pairs = static_cast<int>(std::unique(pairs.begin(), pairs.end()) - pairs.begin());
  return r;
}

namespace {
std::shared_ptr<const fcl::Convexd> make_convex(const Points& V, const std::vector<Tri>& F) {
  auto verts = std::make_shared<std::vector<fcl::Vector3d>>(V.begin(), V.end());
  auto faces = std::make_shared<std::vector<int>>();
  faces->reserve(4 * F.size());
  for (const Tri& t : F) faces->insert(faces->end(), {3, t[0], t[1], t[2]});
  return std::make_shared<const fcl::Convexd>(verts, static_cast<int>(F.size()), faces);
}
}  // namespace

bool convex_signed_distance(const Points& Va, const std::vector<Tri>& Fa, const Points& Vb,
                            const std::vector<Tri>& Fb, double& distance) {
  distance = 0.0;
  if (Va.empty() || Vb.empty() || Fa.empty() || Fb.empty()) return false;
  const auto ca = make_convex(Va, Fa);
  const auto cb = make_convex(Vb, Fb);
  fcl::DistanceRequestd req(/*enable_nearest_points=*/false, /*enable_signed_distance=*/true,
                            /*rel_err=*/0.0, /*abs_err=*/0.0, /*distance_tolerance=*/1e-9,
                            fcl::GST_LIBCCD);
  fcl::DistanceResultd res;
  try {
    fcl::distance(ca.get(), identity(), cb.get(), identity(), req, res);
  } catch (const std::exception&) {
    return false;
  }
  distance = res.min_distance;
  return std::isfinite(distance);
}

std::string fcl_version() { return FCL_VERSION; }

}  // namespace harness
