#include "core/energy_audit.hpp"

#include "core/parallel.hpp"
#include "core/spring_forces.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <utility>

namespace harness {

namespace {

// The booking pass's partial sums, per chunk of kBookChunk nodes: the chunks, not the threads,
// fix the order of the sums, so the audit and the residual (and so the step at which a run
// settles) are the same for any thread count.
constexpr std::size_t kBookChunk = 4096;
enum BookSum {
  kKeStaggered, kKeNew, kCloseExt, kCloseDiss, kCloseDrv, kPendExt, kPendDiss, kPendDrv, kNet, kApplied, kSprings2,
  kGravityPotential, kKeBefore, kBookSums
};

// One node's share of the booking: f the total force of the substep at x_n, v_old = v_{n-1/2},
// v_new = v_{n+1/2}, dx_new its displacement x_{n+1} - x_n, dx_prev the one before. Each
// category's force at x_n closes the interval before (half of it dotted with dx_prev) and opens
// the one after (half dotted with dx_new).
struct BookInput {
  const World& w;
  const Points* f_ext;       // null without external effects
  const Points* f_dashpot;   // null without the damping effect
  const std::vector<double>* mass_damping;
  const Points* f_spring;    // null without springs
  Vec3 gravity;
  bool gravity_on;
  bool ke_before;            // the kinetic energy the step began with (its first substep, drivers)
};

inline void book_node(const BookInput& in, int i, const Vec3& f, const Vec3& v_old, const Vec3& v_new,
                      const Vec3& dx_new, const Vec3& dx_prev, double* acc) {
  const World& w = in.w;
  const double m = w.m[i];
  acc[kKeStaggered] += 0.5 * m * v_old.dot(v_new);
  acc[kKeNew] += 0.5 * m * v_new.squaredNorm();
  if (in.ke_before) acc[kKeBefore] += 0.5 * m * v_old.squaredNorm();
  if (in.f_ext) {
    const Vec3& fe = (*in.f_ext)[i];
    acc[kCloseExt] += 0.5 * fe.dot(dx_prev);
    acc[kPendExt] += 0.5 * fe.dot(dx_new);
  }
  if (in.f_dashpot) {
    const Vec3 fd = (*in.f_dashpot)[i] - ((*in.mass_damping)[i] * m) * v_old;
    acc[kCloseDiss] += 0.5 * fd.dot(dx_prev);
    acc[kPendDiss] += 0.5 * fd.dot(dx_new);
  }
  if (w.kinematic[i] == Kinematic::driven) {  // the driver holds its node against every force on it
    acc[kCloseDrv] -= 0.5 * f.dot(dx_prev);
    acc[kPendDrv] -= 0.5 * f.dot(dx_new);
  }
  if (w.is_free(i)) {
    acc[kNet] += f.squaredNorm();
    if (in.f_ext) acc[kApplied] += (*in.f_ext)[i].squaredNorm();
    if (in.f_spring) acc[kSprings2] += (*in.f_spring)[i].squaredNorm();
  }
}

// A chunk of free nodes on the fused path with the springs' energy left pending: the update and
// the booking over the nodes' coordinates as one flat array (m3, inv_m3: the node's mass and its
// inverse per coordinate; mdm3: its mass damping times its mass), vectorised. The update's
// operations are the integrator's, coordinate by coordinate (v += (h / m) f, x += h v: the same
// bits, floating-point contraction is off); the sums are those of book_node in another order.
struct FlatChunk {
  double* x;
  double* v;
  double* dp;  // the previous displacement, overwritten by this one
  const double* f;
  const double* m3;
  const double* inv_m3;
  const double* fs;    // springs' forces, or null
  const double* fe;    // external forces, or null
  const double* fd;    // dashpots' forces, or null
  const double* mdm3;  // with fd
};

template <bool SP, bool EX, bool DA, bool KB>
void flat_chunk(const FlatChunk& c, double h, std::size_t k0, std::size_t k1, double* acc) {
  double kb = 0.0, ks = 0.0, kn = 0.0, net = 0.0, sp = 0.0, app = 0.0, ce = 0.0, pe = 0.0, cd = 0.0, pd = 0.0;
  double* __restrict X = c.x;
  double* __restrict V = c.v;
  double* __restrict DP = c.dp;
  const double* __restrict F = c.f;
  const double* __restrict M = c.m3;
  const double* __restrict IM = c.inv_m3;
  const double* __restrict FS = c.fs;
  const double* __restrict FE = c.fe;
  const double* __restrict FD = c.fd;
  const double* __restrict MD = c.mdm3;
  const std::ptrdiff_t n0 = static_cast<std::ptrdiff_t>(k0), n1 = static_cast<std::ptrdiff_t>(k1);
#pragma omp simd reduction(+ : kb, ks, kn, net, sp, app, ce, pe, cd, pd)
  for (std::ptrdiff_t k = n0; k < n1; ++k) {
    const double f = F[k], vo = V[k];
    const double vn = vo + (h * IM[k]) * f;
    const double dx = h * vn;
    const double dprev = DP[k];
    V[k] = vn;
    X[k] = X[k] + dx;
    DP[k] = dx;
    if constexpr (KB) kb += M[k] * (vo * vo);
    ks += M[k] * (vo * vn);
    kn += M[k] * (vn * vn);
    net += f * f;
    if constexpr (SP) sp += FS[k] * FS[k];
    if constexpr (EX) {
      const double fe = FE[k];
      app += fe * fe;
      ce += fe * dprev;
      pe += fe * dx;
    }
    if constexpr (DA) {
      const double fd = FD[k] - MD[k] * vo;
      cd += fd * dprev;
      pd += fd * dx;
    }
  }
  acc[kKeBefore] += 0.5 * kb;
  acc[kKeStaggered] += 0.5 * ks;
  acc[kKeNew] += 0.5 * kn;
  acc[kNet] += net;
  acc[kSprings2] += sp;
  acc[kApplied] += app;
  acc[kCloseExt] += 0.5 * ce;
  acc[kPendExt] += 0.5 * pe;
  acc[kCloseDiss] += 0.5 * cd;
  acc[kPendDiss] += 0.5 * pd;
}

using FlatFn = void (*)(const FlatChunk&, double, std::size_t, std::size_t, double*);
template <int I>
constexpr FlatFn flat_entry() {
  return flat_chunk<(I & 8) != 0, (I & 4) != 0, (I & 2) != 0, (I & 1) != 0>;
}
template <int... I>
constexpr std::array<FlatFn, sizeof...(I)> flat_table(std::integer_sequence<int, I...>) {
  return {flat_entry<I>()...};
}
FlatFn flat_variant(bool sp, bool ex, bool da, bool kb) {
  static constexpr auto table = flat_table(std::make_integer_sequence<int, 16>{});
  return table[(sp ? 8 : 0) + (ex ? 4 : 0) + (da ? 2 : 0) + (kb ? 1 : 0)];
}

}  // namespace

EnergyAudit::EnergyAudit(const World& w, const AuditSetup& setup) : setup_(setup) {
  const std::size_t n = w.x.size();
  if (setup_.springs) f_spring_.assign(n, Vec3::Zero()), node_energy_.assign(n, 0.0);
  if (setup_.damping) {
    f_dashpot_.assign(n, Vec3::Zero());
    mass_damping_.assign(n, 0.0);
    for (const Body& b : w.bodies)
      for (int i = b.begin; i < b.end; ++i) mass_damping_[i] = b.material.mass_damping;
  }
  disp_prev_.assign(n, Vec3::Zero());
  v_before_.assign(n, Vec3::Zero());
  x_scratch_.assign(n, Vec3::Zero());
  m3_.resize(3 * n), inv_m3_.resize(3 * n);
  for (std::size_t i = 0; i < n; ++i)
    for (std::size_t a = 0; a < 3; ++a) m3_[3 * i + a] = w.m[i], inv_m3_[3 * i + a] = w.inv_m[i];
  if (setup_.damping) {
    mdm3_.resize(3 * n);
    for (std::size_t i = 0; i < n; ++i)
      for (std::size_t a = 0; a < 3; ++a) mdm3_[3 * i + a] = mass_damping_[i] * w.m[i];
  }
  chunk_sums_.assign(kBookSums * ((n + kBookChunk - 1) / kBookChunk + 1), 0.0);
}

void EnergyAudit::attach(StepContext& ctx, bool lazy_elastic) {
  ctx.f_spring = f_spring_.empty() ? nullptr : &f_spring_;
  ctx.f_dashpot = f_dashpot_.empty() ? nullptr : &f_dashpot_;
  // E*_0 is taken in the first step after a reset: its energy is evaluated in the pass.
  energy_in_pass_ = !lazy_elastic || !ledger_.started || (read_every_ > 0 && ctx.step % read_every_ == 0);
  ctx.spring_energy = node_energy_.empty() || !energy_in_pass_ ? nullptr : &node_energy_;
}

// In chunks whose partial sums are added in chunk order.
void EnergyAudit::integrate_and_book(World& w, const StepContext& s) {
  const double h = s.h;
  const double close_contact = setup_.contact ? 0.5 * setup_.contact->work(w, disp_prev_) : 0.0;
  const BookInput in{w,
                     setup_.f_ext,
                     f_dashpot_.empty() ? nullptr : &f_dashpot_,
                     &mass_damping_,
                     f_spring_.empty() ? nullptr : &f_spring_,
                     setup_.gravity_acceleration,
                     setup_.gravity && energy_in_pass_,  // else at the force point in complete()
                     first_substep_ && setup_.drivers && ledger_.started};
  const std::size_t n = w.x.size(), chunks = (n + kBookChunk - 1) / kBookChunk;
  // The flat path: the springs' energy pending (the gravity potential with it); per chunk when
  // all of its nodes are free.
  const bool flat = !energy_in_pass_;
  const FlatChunk fc{w.x[0].data(), w.v[0].data(), disp_prev_[0].data(), w.f[0].data(), m3_.data(), inv_m3_.data(),
                     in.f_spring ? (*in.f_spring)[0].data() : nullptr, in.f_ext ? (*in.f_ext)[0].data() : nullptr,
                     in.f_dashpot ? (*in.f_dashpot)[0].data() : nullptr, mdm3_.empty() ? nullptr : mdm3_.data()};
  const FlatFn flat_fn = flat_variant(fc.fs != nullptr, fc.fe != nullptr, fc.fd != nullptr, in.ke_before);
  const int T = threads_for(n);
#pragma omp parallel for num_threads(T) if(T > 1) schedule(dynamic, 1)
  for (std::size_t c = 0; c < chunks; ++c) {
    double acc[kBookSums] = {};
    const std::size_t i0 = c * kBookChunk, i1 = std::min(n, (c + 1) * kBookChunk);
    for (std::size_t k = i0; k < i1;) {
      if (flat && w.kinematic[k] == Kinematic::free) {  // a run of free nodes
        std::size_t e = k + 1;
        while (e < i1 && w.kinematic[e] == Kinematic::free) ++e;
        flat_fn(fc, h, 3 * k, 3 * e, acc);
        k = e;
        continue;
      }
      const int i = static_cast<int>(k++);
      const Vec3 f = w.f[i], v_old = w.v[i];
      if (in.gravity_on) acc[kGravityPotential] -= w.m[i] * in.gravity.dot(w.x[i]);
      Vec3 dx = Vec3::Zero();
      switch (w.kinematic[i]) {
        case Kinematic::free:
          w.v[i] += (h * w.inv_m[i]) * f;
          w.x[i] += h * w.v[i];
          dx = h * w.v[i];
          break;
        case Kinematic::pinned: break;
        case Kinematic::driven:
          w.x[i] += h * w.kin_v[i];
          dx = h * w.kin_v[i];
          break;
      }
      book_node(in, i, f, v_old, w.v[i], dx, disp_prev_[i], acc);
      disp_prev_[i] = dx;
    }
    std::copy(acc, acc + kBookSums, chunk_sums_.begin() + static_cast<std::ptrdiff_t>(c * kBookSums));
  }
  double sums[kBookSums] = {};
  for (std::size_t c = 0; c < chunks; ++c)
    for (int k = 0; k < kBookSums; ++k) sums[k] += chunk_sums_[c * kBookSums + k];
  const double open_contact = setup_.contact ? 0.5 * setup_.contact->work(w, disp_prev_) : 0.0;
  ledger_.work_contact += pending_[3] + close_contact;
  pending_[3] = open_contact;
  close_substep(sums);
}

void EnergyAudit::keep_velocities(const World& w) { std::copy(w.v.begin(), w.v.end(), v_before_.begin()); }

// The same sums from the velocities before the update (v_before_) and after it.
void EnergyAudit::book(const World& w, const StepContext& s) {
  const double h = s.h;
  const double close_contact = setup_.contact ? 0.5 * setup_.contact->work(w, disp_prev_) : 0.0;
  const BookInput in{w,
                     setup_.f_ext,
                     f_dashpot_.empty() ? nullptr : &f_dashpot_,
                     &mass_damping_,
                     f_spring_.empty() ? nullptr : &f_spring_,
                     setup_.gravity_acceleration,
                     setup_.gravity,
                     first_substep_ && setup_.drivers && ledger_.started};
  const std::size_t n = w.x.size(), chunks = (n + kBookChunk - 1) / kBookChunk;
  for (std::size_t c = 0; c < chunks; ++c) {
    double acc[kBookSums] = {};
    for (std::size_t k = c * kBookChunk; k < std::min(n, (c + 1) * kBookChunk); ++k) {
      const int i = static_cast<int>(k);
      const Vec3 dx = w.kinematic[i] == Kinematic::pinned  ? Vec3(Vec3::Zero())
                      : w.kinematic[i] == Kinematic::driven ? Vec3(h * w.kin_v[i])
                                                            : Vec3(h * w.v[i]);
      if (in.gravity_on) acc[kGravityPotential] -= w.m[i] * in.gravity.dot(w.x[i] - dx);
      book_node(in, i, w.f[i], v_before_[i], w.v[i], dx, disp_prev_[i], acc);
      disp_prev_[i] = dx;
    }
    std::copy(acc, acc + kBookSums, chunk_sums_.begin() + static_cast<std::ptrdiff_t>(c * kBookSums));
  }
  double sums[kBookSums] = {};
  for (std::size_t c = 0; c < chunks; ++c)
    for (int k = 0; k < kBookSums; ++k) sums[k] += chunk_sums_[c * kBookSums + k];
  const double open_contact = setup_.contact ? 0.5 * setup_.contact->work(w, disp_prev_) : 0.0;
  ledger_.work_contact += pending_[3] + close_contact;
  pending_[3] = open_contact;
  close_substep(sums);
}

// Closes the interval before this substep's force point in the ledger, opens the one after it,
// and takes the staggered energy E*_n, the energies and the force residual (energy.hpp). In a
// step's first substep, the drivers' work of starting or stopping their nodes first: the kinetic
// energy the step began with against the last step's (before the first step E*_0 holds it).
void EnergyAudit::close_substep(const double* sums) {
  if (first_substep_ && setup_.drivers && ledger_.started) ledger_.work_external += sums[kKeBefore] - ledger_.kinetic;
  first_substep_ = false;
  ledger_.work_external += (pending_[0] + sums[kCloseExt]) + (pending_[2] + sums[kCloseDrv]);
  ledger_.dissipated -= pending_[1] + sums[kCloseDiss];
  pending_[0] = sums[kPendExt], pending_[1] = sums[kPendDiss], pending_[2] = sums[kPendDrv];
  ke_staggered_ = sums[kKeStaggered];
  gravity_potential_ = sums[kGravityPotential];
  ledger_.kinetic = sums[kKeNew];
  elastic_pending_ = true;
  if (energy_in_pass_) book_elastic(node_energy_.empty() ? 0.0 : sum_node_energy(node_energy_));  // at x_n
  // Without applied forces, free bodies come to rest with their springs relaxed: the scale is
  // then the largest spring-force norm seen in the run.
  spring_force_peak_ = std::max(spring_force_peak_, sums[kSprings2]);
  const double scale = sums[kApplied] > 0.0 ? sums[kApplied] : spring_force_peak_;
  residual_ = scale > 0.0 ? std::sqrt(sums[kNet] / scale) : 0.0;
}

// -sum m g . x, in the booking pass's chunks.
double EnergyAudit::gravity_potential(const World& w, const Points& x) const {
  const std::size_t n = x.size();
  double total = 0.0;
  for (std::size_t c = 0; c * kBookChunk < n; ++c) {
    double part = 0.0;
    for (std::size_t i = c * kBookChunk; i < std::min(n, (c + 1) * kBookChunk); ++i)
      part -= w.m[i] * setup_.gravity_acceleration.dot(x[i]);
    total += part;
  }
  return total;
}

void EnergyAudit::book_elastic(double U) {
  ledger_.staggered = ke_staggered_ + U;
  if (!ledger_.started) ledger_.staggered0 = ledger_.staggered, ledger_.started = true;
  ledger_.elastic = U;
  ledger_.potential = U + gravity_potential_;
  elastic_pending_ = false;
}

void EnergyAudit::engine_step(const World& w, const Points& v_prev, double dt, double kinetic, double elastic,
                              double potential) {
  ledger_.kinetic = kinetic;
  ledger_.elastic = elastic;
  ledger_.potential = potential;
  double net = 0.0, applied = 0.0, springs = 0.0;
  for (int i = 0; i < w.num_nodes(); ++i) {
    if (!w.is_free(i)) continue;
    net += (w.m[i] * (w.v[i] - v_prev[i]) / dt).squaredNorm();
    if (setup_.f_ext) applied += (*setup_.f_ext)[i].squaredNorm();
    if (!f_spring_.empty()) springs += f_spring_[i].squaredNorm();
  }
  spring_force_peak_ = std::max(spring_force_peak_, springs);
  const double scale = applied > 0.0 ? applied : spring_force_peak_;
  residual_ = scale > 0.0 ? std::sqrt(net / scale) : 0.0;
}

void EnergyAudit::reset(double kinetic, double elastic, double potential) {
  ledger_ = EnergyLedger{};
  ledger_.kinetic = kinetic;
  ledger_.elastic = elastic;
  ledger_.potential = potential;
  ledger_.initial = ledger_.kinetic + ledger_.elastic;
  elastic_pending_ = false;
  std::fill(pending_, pending_ + 4, 0.0);
  std::fill(disp_prev_.begin(), disp_prev_.end(), Vec3::Zero());
}

}  // namespace harness
