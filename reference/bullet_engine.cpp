#include "reference/bullet_engine.hpp"

#include "core/clock.hpp"
#include "core/scene/scene.hpp"
#include "core/world.hpp"

#include <BulletSoftBody/btSoftBody.h>
#include <BulletSoftBody/btSoftBodyRigidBodyCollisionConfiguration.h>
#include <BulletSoftBody/btSoftRigidDynamicsWorld.h>
#include <BulletCollision/BroadphaseCollision/btDbvtBroadphase.h>
#include <BulletDynamics/ConstraintSolver/btSequentialImpulseConstraintSolver.h>
#include <btBulletDynamicsCommon.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>
#include <memory>
#include <numeric>
#include <random>

#ifndef BT_USE_DOUBLE_PRECISION
#error "the Bullet engine needs Bullet's double-precision build (pkg-config bullet-float64)"
#endif
static_assert(sizeof(btScalar) == sizeof(double), "Bullet's double-precision build expected");

namespace harness {

namespace {

btVector3 bt(const Vec3& v) { return btVector3(v.x(), v.y(), v.z()); }
Vec3 ev(const btVector3& v) { return Vec3(v.x(), v.y(), v.z()); }

// The world with its collision pass timed (Bullet runs VF_SS inside it).
class TimedWorld final : public btSoftRigidDynamicsWorld {
 public:
  using btSoftRigidDynamicsWorld::btSoftRigidDynamicsWorld;
  void performDiscreteCollisionDetection() override {
    const auto t0 = Clock::now();
    btSoftRigidDynamicsWorld::performDiscreteCollisionDetection();
    collide_us += us_since(t0);
  }
  double collide_us = 0.0;
};

// A soft-body world with its collision configuration, dispatcher, broadphase and solver, and the
// soft bodies it owns (removed and deleted with it). No air (no aerodynamic forces).
struct SoftWorld {
  explicit SoftWorld(const btVector3& gravity) {
    btSoftBodyWorldInfo& info = world.getWorldInfo();
    info.m_gravity = gravity;
    info.air_density = 0;
    info.m_sparsesdf.Initialize();
    world.setGravity(gravity);
  }
  ~SoftWorld() {
    for (btSoftBody* b : bodies) {
      world.removeSoftBody(b);
      delete b;
    }
  }
  SoftWorld(const SoftWorld&) = delete;
  SoftWorld& operator=(const SoftWorld&) = delete;

  btSoftBodyRigidBodyCollisionConfiguration config;
  btCollisionDispatcher dispatcher{&config};
  btDbvtBroadphase broadphase;
  btSequentialImpulseConstraintSolver solver;
  TimedWorld world{&dispatcher, &broadphase, &solver, &config};
  std::vector<btSoftBody*> bodies;
};

class BulletEngine final : public StepEngine {
 public:
  BulletEngine(const Scene& sc, const World& w, const BulletOptions& opt);
  const char* name() const override { return "bullet"; }
  const char* contact_model() const override { return "bullet_vf_ss"; }
  EngineStep step(World& w, int step, double dt) override;
  nlohmann::json describe() const override { return describe_; }

 private:
  std::unique_ptr<SoftWorld> soft_;  // made once the scene is known to be representable
  std::vector<std::vector<int>> pair_of_;  // [body][other body] -> contact pair index, -1 none
  std::size_t n_pairs_ = 0;
  nlohmann::json describe_;
};

// The body's mean surface edge at its current positions (world.hpp, the one definition).
double mean_surface_edge_of(const World& w, const Body& b) {
  return current_surface_edge(w, static_cast<int>(&b - w.bodies.data()));
}

// A soft body of a world's body: its nodes at their positions with their lumped masses.
btSoftBody* soft_body_of(btSoftBodyWorldInfo& info, const World& w, const Body& b) {
  std::vector<btVector3> x(b.size());
  std::vector<btScalar> m(b.size());
  for (int i = 0; i < b.size(); ++i) x[i] = bt(w.x[b.begin + i]), m[i] = w.m[b.begin + i];
  return new btSoftBody(&info, b.size(), x.data(), m.data());
}

// What Bullet cannot represent, refused before anything is built.
void check_representable(const Scene& sc) {
  const auto refuse = [&](const std::string& key, const std::string& why) {
    throw InputError(sc.file + ": " + key, why + " (--engine bullet)");
  };
  if (sc.bodies.size() > 30) refuse("bodies", "Bullet's collision filter masks hold at most 30 bodies");
  for (const BodySpec& b : sc.bodies) {
    if (sc.has(kSprings) && b.material.law != SpringLawKind::linear)
      refuse(b.path + ".material.law", std::string("Bullet's links are linear position constraints; the ") +
                                           to_string(b.material.law) + " law cannot be represented");
    if (sc.has(kDamping) && b.material.damping > 0.0)
      refuse(b.path + ".material.damping",
             "Bullet has no dashpot along its links (only velocity damping kDP, from mass_damping); set it to 0");
    if (sc.has(kDamping) && b.material.mass_damping * sc.dt >= 1.0)
      refuse(b.path + ".material.mass_damping", "Bullet's velocity damping kDP = mass_damping x dt must be below 1");
    if (sc.has(kPressure) && b.pressure.present)
      refuse(b.path + ".pressure", "the harness's pressure ramp on a closed surface is not mapped to Bullet");
    if (sc.has(kBulk) && b.material.bulk_modulus > 0.0)
      refuse(b.path + ".material.bulk_modulus", "the cells' bulk term is not mapped to Bullet");
    if (sc.has(kLoads) && !b.loads.empty())
      refuse(b.path + ".loads", "nodal loads are not mapped to Bullet");
  }
}

BulletEngine::BulletEngine(const Scene& sc, const World& w, const BulletOptions& opt) {
  check_representable(sc);
  if (opt.iterations < 1) throw InputError("--bullet-iterations", "must be at least 1");
  if (!(opt.margin >= 0.0) || !std::isfinite(opt.margin)) throw InputError("--bullet-margin", "must be a length >= 0, m");
  soft_ = std::make_unique<SoftWorld>(sc.has(kGravity) ? bt(sc.gravity) : btVector3(0, 0, 0));
  btSoftBodyWorldInfo& info = soft_->world.getWorldInfo();

  const std::size_t nb = w.bodies.size();
  pair_of_.assign(nb, std::vector<int>(nb, -1));
  std::vector<int> mask(nb, 0);
  if (sc.has(kContact))
    for (std::size_t p = 0; p < sc.contacts.size(); ++p) {
      const int h = sc.contacts[p].spec.host, g = sc.contacts[p].spec.guest;
      pair_of_[h][g] = pair_of_[g][h] = static_cast<int>(p);
      mask[h] |= 1 << g;
      mask[g] |= 1 << h;
    }
  n_pairs_ = sc.contacts.size();

  double klst_min = std::numeric_limits<double>::infinity(), klst_max = 0.0;
  nlohmann::json margins = nlohmann::json::array(), kdp = nlohmann::json::array();
  for (std::size_t bi = 0; bi < nb; ++bi) {
    const Body& b = w.bodies[bi];
    btSoftBody* psb = soft_body_of(info, w, b);
    soft_->bodies.push_back(psb);
    for (int i = 0; i < b.size(); ++i) psb->m_nodes[i].m_v = bt(w.v[b.begin + i]);
    if (sc.has(kSprings))
      for (int s = b.spring_begin; s < b.spring_end; ++s) {
        const Edge& e = w.springs.ends[s];
        const int a = e[0] - b.begin, c = e[1] - b.begin;
        const double klst = w.springs.k[s] * sc.dt * sc.dt * (w.inv_m[e[0]] + w.inv_m[e[1]]) / opt.iterations;
        if (!(klst < 1.0))
          throw InputError(sc.file + ": time.dt",
                           "too large for Bullet's position solver: a link of " + b.name + " needs stiffness kLST = k dt^2 "
                           "(1/m_a + 1/m_b) / iterations = " + std::to_string(klst) + " >= 1 (--engine bullet)");
        klst_min = std::min(klst_min, klst), klst_max = std::max(klst_max, klst);
        btSoftBody::Material* mat = psb->appendMaterial();
        mat->m_kLST = klst;
        mat->m_kAST = mat->m_kVST = 0;
        psb->appendLink(a, c, mat, false);
      }
    for (const Tri& t : b.faces) psb->appendFace(t[0], t[1], t[2]);
    const double margin = opt.margin > 0.0 ? opt.margin : BulletOptions::kMarginFraction * mean_surface_edge_of(w, b);
    psb->getCollisionShape()->setMargin(margin);
    margins.push_back(margin);
    btSoftBody::Config& cfg = psb->m_cfg;
    cfg.collisions = btSoftBody::fCollision::VF_SS;
    cfg.kDF = 0;   // frictionless, as the harness's contact
    cfg.kSHR = 1;  // soft-soft contact hardness: full correction
    cfg.kDP = sc.has(kDamping) ? b.material.mass_damping * sc.dt : 0.0;
    cfg.piterations = opt.iterations;
    cfg.viterations = cfg.diterations = 0;
    cfg.kMT = 0;
    kdp.push_back(cfg.kDP);
    // Bullet's constants, then the rest lengths it would otherwise take from the current state.
    psb->updateConstants();
    for (int s = b.spring_begin, l = 0; sc.has(kSprings) && s < b.spring_end; ++s, ++l) {
      psb->m_links[l].m_rl = w.springs.rest[s];
      psb->m_links[l].m_c1 = w.springs.rest[s] * w.springs.rest[s];
    }
    psb->m_bUpdateRtCst = false;
    psb->m_fdbvt.clear();
    psb->initializeFaceTree();
    psb->setActivationState(DISABLE_DEACTIVATION);
    soft_->world.addSoftBody(psb, 1 << bi, mask[bi]);
  }
  describe_ = {{"name", "bullet"},
               {"version", bullet_version()},
               {"solver", "btSoftRigidDynamicsWorld::stepSimulation(dt, 0), position solver"},
               {"contact", "VF_SS (vertex-face soft-soft), frictionless, kSHR 1"},
               {"margin_m", margins},
               {"margin_rule", opt.margin > 0.0 ? "--bullet-margin" : "0.05 x the body's mean surface edge"},
               {"position_iterations", opt.iterations},
               {"link_stiffness", "kLST = k dt^2 (1/m_a + 1/m_b) / iterations, per link"},
               {"kLST_min", nb && std::isfinite(klst_min) ? nlohmann::json(klst_min) : nlohmann::json(nullptr)},
               {"kLST_max", klst_max},
               {"kDP", kdp}};
}

EngineStep BulletEngine::step(World& w, int /*step*/, double dt) {
  for (std::size_t bi = 0; bi < soft_->bodies.size(); ++bi) {
    const Body& b = w.bodies[bi];
    btSoftBody* psb = soft_->bodies[bi];
    for (int i = 0; i < b.size(); ++i) {
      const int g = b.begin + i;
      btSoftBody::Node& n = psb->m_nodes[i];
      n.m_x = bt(w.x[g]);
      switch (w.kinematic[g]) {
        case Kinematic::free: n.m_im = w.inv_m[g], n.m_v = bt(w.v[g]); break;
        case Kinematic::pinned: n.m_im = 0, n.m_v = btVector3(0, 0, 0); break;
        case Kinematic::driven: n.m_im = 0, n.m_v = bt(w.kin_v[g]); break;
      }
    }
  }
  soft_->world.collide_us = 0.0;
  soft_->world.stepSimulation(dt, 0, dt);
  EngineStep out;
  out.detect_us = soft_->world.collide_us;
  out.contacts.assign(n_pairs_, 0);
  for (std::size_t bi = 0; bi < soft_->bodies.size(); ++bi) {
    const Body& b = w.bodies[bi];
    btSoftBody* psb = soft_->bodies[bi];
    for (int i = 0; i < b.size(); ++i) {
      const int g = b.begin + i;
      const btSoftBody::Node& n = psb->m_nodes[i];
      w.x[g] = ev(n.m_x);
      w.v[g] = w.kinematic[g] == Kinematic::free ? ev(n.m_v) : w.kinematic[g] == Kinematic::driven ? w.kin_v[g] : Vec3::Zero();
    }
    // Contacts of this body's nodes against the faces of the others.
    for (int c = 0; c < psb->m_scontacts.size(); ++c) {
      const btSoftBody::Face* f = psb->m_scontacts[c].m_face;
      for (std::size_t o = 0; o < soft_->bodies.size(); ++o) {
        const auto& faces = soft_->bodies[o]->m_faces;
        if (o == bi || faces.size() == 0 || f < &faces[0] || f > &faces[faces.size() - 1]) continue;
        if (pair_of_[bi][o] >= 0) ++out.contacts[pair_of_[bi][o]];
        break;
      }
    }
  }
  return out;
}

}  // namespace

struct BulletCollisionBench::Impl {
  SoftWorld soft{btVector3(0, 0, 0)};
};

BulletCollisionBench::BulletCollisionBench(const World& w, int host, int guest) : impl_(std::make_unique<Impl>()) {
  SoftWorld& m = impl_->soft;
  btSoftBodyWorldInfo& info = m.world.getWorldInfo();
  int bit = 0;
  for (int bi : {host, guest}) {
    const Body& b = w.bodies[bi];
    btSoftBody* psb = soft_body_of(info, w, b);
    m.bodies.push_back(psb);
    for (const Tri& t : b.faces) psb->appendFace(t[0], t[1], t[2]);
    // The face tree by incremental insertion: Bullet's own initializeFaceTree (what predictMotion
    // calls after faces were appended) pairs faces by an adjacency search quadratic in their count,
    // hours at 10^6 faces, and its node tree needs links to terminate. Leaves go in in a shuffled
    // (seeded) order, then the tree is rebuilt top-down: inserted in mesh order, Bullet's
    // incremental tree degenerates (minutes at 10^6 nodes).
    const double margin = BulletOptions::kMarginFraction * mean_surface_edge_of(w, b);
    psb->getCollisionShape()->setMargin(margin);
    std::mt19937 rng(12345);
    std::vector<int> order(psb->m_faces.size());
    std::iota(order.begin(), order.end(), 0);
    std::shuffle(order.begin(), order.end(), rng);
    for (int f : order) {
      btSoftBody::Face& face = psb->m_faces[f];
      const btVector3 pts[3] = {face.m_n[0]->m_x, face.m_n[1]->m_x, face.m_n[2]->m_x};
      face.m_leaf = psb->m_fdbvt.insert(btDbvtVolume::FromPoints(pts, 3), &face);
    }
    psb->m_fdbvt.optimizeTopDown();
    psb->m_bUpdateRtCst = false;
    // The node tree again with this margin: the constructor inserted the nodes with the default
    // margin (0.25 m), which a refit never shrinks.
    psb->m_ndbvt.clear();
    order.resize(psb->m_nodes.size());
    std::iota(order.begin(), order.end(), 0);
    std::shuffle(order.begin(), order.end(), rng);
    for (int i : order)
      psb->m_nodes[i].m_leaf = psb->m_ndbvt.insert(btDbvtVolume::FromCR(psb->m_nodes[i].m_x, margin), &psb->m_nodes[i]);
    psb->m_ndbvt.optimizeTopDown();
    psb->m_cfg.collisions = btSoftBody::fCollision::VF_SS;
    psb->m_cfg.kDF = 0;
    psb->setActivationState(DISABLE_DEACTIVATION);
    m.world.addSoftBody(psb, 1 << bit, 1 << (1 - bit));
    ++bit;
  }
}

BulletCollisionBench::~BulletCollisionBench() = default;

int BulletCollisionBench::collide() {
  SoftWorld& m = impl_->soft;
  for (btSoftBody* psb : m.bodies) psb->predictMotion(1e-6);  // at rest: refits the trees, clears contacts
  m.world.performDiscreteCollisionDetection();
  int n = 0;
  for (btSoftBody* psb : m.bodies) n += psb->m_scontacts.size();
  return n;
}

std::string bullet_version() {
  const int v = btGetVersion();
  char buf[32];
  std::snprintf(buf, sizeof buf, "%d.%02d (double)", v / 100, v % 100);
  return buf;
}

EngineMaker make_bullet_engine(const BulletOptions& options) {
  return [options](const Scene& sc, const World& w) -> std::unique_ptr<StepEngine> {
    return std::make_unique<BulletEngine>(sc, w, options);
  };
}

}  // namespace harness
