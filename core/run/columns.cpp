#include "core/run/columns.hpp"

#include <cmath>
#include <stdexcept>

namespace harness {

namespace {

bool contact(const StepRow& r) { return r.pair && r.pair->collision; }
// Contact handled by the harness or by a peer engine (engine.hpp: counts and detection time only).
bool any_contact(const StepRow& r) { return r.pair && (r.pair->collision || r.pair->engine_contact); }
bool cgal(const StepRow& r) { return r.m && r.m->has_cgal; }
bool fcl(const StepRow& r) { return r.m && r.m->has_fcl; }
bool ccd(const StepRow& r) { return r.m && r.m->has_ccd; }

// One corner of the pair's voxel region (k: 0..2 lower x, y, z, 3..5 upper), empty without a grid.
template <int k>
void region(const CsvField& o, const StepRow& r) {
  Vec3 lo, hi;
  if (contact(r) && r.pair->collision->detector().region(lo, hi)) o.g9(k < 3 ? lo[k] : hi[k - 3]);
}

}  // namespace

const std::vector<Column>& steps_columns() {
  using O = const CsvField&;
  using R = const StepRow&;
  static const std::vector<Column> columns = {
      {"step", "step index (from 1); the row describes the state after this step", [](O o, R r) { o.integer(r.sim.step_index()); }},
      {"time", "simulated time after the step, s", [](O o, R r) { o.g9(r.sim.time()); }},
      {"pair", "the contact pair's label (host/guest); empty in a scene without pairs", [](O o, R r) { if (r.pair) o.text(r.pair->label); }},
      {"detector", "the detector that drove elimination (`none` without contact handling)", [](O o, R r) { if (r.pair) o.text(r.pair->collision ? r.pair->spec.detector.c_str() : r.pair->engine_contact ? r.pair->engine_contact : "none"); }},
      {"contacts", "contacts the detector reported this step", [](O o, R r) { if (any_contact(r)) o.integer(r.pair->last.contacts); }},
      {"t_step_us", "wall time of the whole step, us", [](O o, R r) { o.us(r.sim.last().step_us); }, true},
      {"t_physics_us", "wall time of the step less detection and elimination, us", [](O o, R r) { o.us(r.sim.last().physics_us); }, true},
      {"t_detect_us", "wall time of detection, us", [](O o, R r) { if (any_contact(r)) o.us(r.pair->last.detect_us); }, true},
      {"t_eliminate_us", "wall time of elimination (the response's forces), us", [](O o, R r) { if (contact(r)) o.us(r.pair->last.eliminate_us); }, true},
      {"kinetic_energy", "kinetic energy of all bodies, J", [](O o, R r) { o.g9(r.kinetic_energy); }},
      {"true_pen_guest", "guest nodes strictly inside the host's closed surface (CGAL, exact predicates)", [](O o, R r) { if (cgal(r)) o.integer(r.m->true_pen_guest); }},
      {"true_pen_host", "host nodes strictly inside the guest's closed surface", [](O o, R r) { if (cgal(r)) o.integer(r.m->true_pen_host); }},
      {"tp", "guest nodes detected and truly penetrating", [](O o, R r) { if (cgal(r)) o.integer(r.m->tp); }},
      {"fp", "guest nodes detected, not penetrating", [](O o, R r) { if (cgal(r)) o.integer(r.m->fp); }},
      {"fn", "guest nodes penetrating, not detected", [](O o, R r) { if (cgal(r)) o.integer(r.m->fn); }},
      {"max_depth", "largest residual depth of a truly penetrating node (both bodies), m", [](O o, R r) { if (cgal(r)) o.g9(r.m->max_depth); }},
      {"mean_depth", "mean residual depth over the truly penetrating nodes, m", [](O o, R r) { if (cgal(r)) o.g9(r.m->mean_depth); }},
      {"surfaces_intersect", "1 when the two closed surfaces intersect (CGAL), else 0", [](O o, R r) { if (cgal(r)) o.integer(r.m->surfaces_intersect ? 1 : 0); }},
      {"fcl_pairs", "intersecting triangle pairs reported by FCL", [](O o, R r) { if (fcl(r)) o.integer(r.m->fcl_pairs); }},
      {"t_cgal_us", "wall time of the CGAL measurement, us", [](O o, R r) { if (cgal(r)) o.us(r.m->t_cgal_us); }, true},
      {"t_fcl_us", "wall time of the FCL measurement, us", [](O o, R r) { if (fcl(r)) o.us(r.m->t_fcl_us); }, true},
      // Past the contract's columns:
      {"force", "force per contact used this step, N", [](O o, R r) { if (contact(r)) o.g9(r.pair->last.force); }},
      {"fcl_max_depth", "FCL's largest penetration depth, m", [](O o, R r) { if (fcl(r)) o.g9(r.m->fcl_max_depth); }},
      {"ccd_distance", "libccd's distance (negative: penetration) between the hulls, m", [](O o, R r) { if (ccd(r)) o.g9(r.m->ccd_distance); }},
      {"t_ccd_us", "wall time of the libccd measurement, us", [](O o, R r) { if (ccd(r)) o.us(r.m->t_ccd_us); }, true},
      {"penetration_volume", "volume of the bodies' intersection (CGAL corefinement), m^3", [](O o, R r) { if (r.m && r.m->has_volume) o.g9(r.m->penetration_volume); }},
      {"potential_energy", "gravitational potential energy, J", [](O o, R r) { if (!std::isnan(r.potential_energy)) o.g9(r.potential_energy); }},
      {"region_lo_x", "lower x corner of the pair's voxel region, m", region<0>},
      {"region_lo_y", "lower y corner of the voxel region, m", region<1>},
      {"region_lo_z", "lower z corner of the voxel region, m", region<2>},
      {"region_hi_x", "upper x corner of the voxel region, m", region<3>},
      {"region_hi_y", "upper y corner of the voxel region, m", region<4>},
      {"region_hi_z", "upper z corner of the voxel region, m", region<5>},
      {"t_volume_us", "wall time of the intersection volume, us", [](O o, R r) { if (r.m && r.m->has_volume) o.us(r.m->t_volume_us); }, true},
      // The energy audit (energy.hpp), J, cumulative where it is work; the force residual.
      // The works, the kinetic energy: every step; the elastic energy and the balance (which
      // needs it): on the steps the recorder evaluated it (recorder.hpp), empty on the others.
      {"energy_kinetic", "energy audit: kinetic energy, J", [](O o, R r) { o.g9(r.sim.energy_booked().kinetic); }},
      {"energy_elastic", "energy audit: elastic energy (on evaluated steps), J", [](O o, R r) { if (r.sim.energy_current()) o.g9(r.sim.energy_booked().elastic); }},
      {"work_external", "energy audit: cumulative work of external effects, J", [](O o, R r) { o.g9(r.sim.energy_booked().work_external); }},
      {"energy_dissipated", "energy audit: cumulative dissipated energy, J", [](O o, R r) { o.g9(r.sim.energy_booked().dissipated); }},
      {"work_contact", "energy audit: cumulative work of contact forces, J", [](O o, R r) { o.g9(r.sim.energy_booked().work_contact); }},
      {"energy_balance_error", "energy audit: relative balance error (on evaluated steps)", [](O o, R r) { if (r.sim.energy_current()) o.g9(r.sim.energy_booked().balance_error()); }},
      {"residual", "force residual (settling measure)", [](O o, R r) { o.g9(r.sim.residual()); }},
      // Accuracy both ways (run/compare.hpp), m: the signed distance of the nodes contact pushed
      // (positive: across a gap), and the error against the reference at this step.
      {"force_dist_max", "largest signed distance of a node contact pushed (positive: across a gap), m", [](O o, R r) { if (r.fig && r.fig->force_dist) o.g9(r.fig->force_dist_max); }},
      {"force_dist_mean", "mean signed distance of the nodes contact pushed, m", [](O o, R r) { if (r.fig && r.fig->force_dist) o.g9(r.fig->force_dist_mean); }},
      {"gap_max", "largest gap between bodies where the reference has contact, m", [](O o, R r) { if (r.fig && r.fig->vs_reference) o.g9(r.fig->errors.gap_max); }},
      {"gap_mean", "mean gap where the reference has contact, m", [](O o, R r) { if (r.fig && r.fig->vs_reference) o.g9(r.fig->errors.gap_mean); }},
      {"pos_err_max", "largest node position error against the reference, m", [](O o, R r) { if (r.fig && r.fig->vs_reference) o.g9(r.fig->errors.pos_err_max); }},
      {"pos_err_rms", "RMS node position error against the reference, m", [](O o, R r) { if (r.fig && r.fig->vs_reference) o.g9(r.fig->errors.pos_err_rms); }},
      // Host nodes detected the other way round (two-sided contact) against those truly inside the
      // guest; nodes that have passed through the other body (core/measure.hpp tunnelled_guest).
      {"tp_host", "host nodes detected (two-sided contact) and truly inside the guest", [](O o, R r) { if (cgal(r)) o.integer(r.m->tp_host); }},
      {"fp_host", "host nodes detected, not inside the guest", [](O o, R r) { if (cgal(r)) o.integer(r.m->fp_host); }},
      {"fn_host", "host nodes inside the guest, not detected", [](O o, R r) { if (cgal(r)) o.integer(r.m->fn_host); }},
      {"tunnelled_guest", "guest nodes that have passed through the host", [](O o, R r) { if (r.fig && r.fig->tunnelled.measured) o.integer(r.fig->tunnelled.guest); }},
      {"tunnelled_host", "host nodes that have passed through the guest", [](O o, R r) { if (r.fig && r.fig->tunnelled.measured) o.integer(r.fig->tunnelled.host); }},
      // Guest nodes found inside beyond the detector's guaranteed band (voxel_exact), both ways;
      // empty for detectors without a band.
      {"beyond_band", "guest nodes found inside beyond the detector's guaranteed band (voxel_exact)", [](O o, R r) { if (contact(r) && r.pair->last.beyond_band >= 0) o.integer(r.pair->last.beyond_band); }},
      // The error against the second reference (--compare-also), m; empty without one.
      {"also_gap_max", "gap_max against the second reference (--compare-also), m", [](O o, R r) { if (r.fig && r.fig->vs_also && r.fig->also_errors.distances) o.g9(r.fig->also_errors.gap_max); }},
      {"also_gap_mean", "gap_mean against the second reference, m", [](O o, R r) { if (r.fig && r.fig->vs_also && r.fig->also_errors.distances) o.g9(r.fig->also_errors.gap_mean); }},
      {"also_pos_err_max", "pos_err_max against the second reference, m", [](O o, R r) { if (r.fig && r.fig->vs_also) o.g9(r.fig->also_errors.pos_err_max); }},
      {"also_pos_err_rms", "pos_err_rms against the second reference, m", [](O o, R r) { if (r.fig && r.fig->vs_also) o.g9(r.fig->also_errors.pos_err_rms); }},
  };
  return columns;
}

namespace {

std::FILE* open_csv(const std::string& path) {
  std::FILE* f = std::fopen(path.c_str(), "w");
  if (!f) throw std::runtime_error("cannot write " + path);
  std::setvbuf(f, nullptr, _IOFBF, 1 << 20);
  return f;
}

bool is_key(const Column& c) {
  for (const char* k : kTimingKeys)
    if (std::string(k) == c.name) return true;
  return false;
}

// Column c in timing.csv: the keys, then the wall times.
bool in_timing(const Column& c) { return c.timing || is_key(c); }

void header(std::FILE* f, bool timing) {
  bool first = true;
  for (const Column& c : steps_columns()) {
    if (timing ? !in_timing(c) : c.timing) continue;
    std::fprintf(f, first ? "%s" : ",%s", c.name);
    first = false;
  }
  std::fputc('\n', f);
}

void close_csv(std::FILE*& f, const std::string& path) {
  if (!f) return;
  const bool ok = std::ferror(f) == 0;
  const int rc = std::fclose(f);
  f = nullptr;
  if (rc != 0 || !ok) throw std::runtime_error("cannot write " + path);
}

}  // namespace

StepsWriter::StepsWriter(const std::string& steps_path, const std::string& timing_path) {
  steps_ = {steps_path, open_csv(steps_path)};
  try {
    timing_ = {timing_path, open_csv(timing_path)};
  } catch (...) {
    std::fclose(steps_.f);
    throw;
  }
  header(steps_.f, false);
  header(timing_.f, true);
}

StepsWriter::~StepsWriter() {
  if (steps_.f) std::fclose(steps_.f);
  if (timing_.f) std::fclose(timing_.f);
}

void StepsWriter::row(const StepRow& r) {
  const CsvField out_s(steps_.f), out_t(timing_.f);
  bool first_s = true, first_t = true;
  for (const Column& c : steps_columns()) {
    if (!c.timing) {
      if (!first_s) std::fputc(',', steps_.f);
      c.write(out_s, r);
      first_s = false;
    }
    if (in_timing(c)) {
      if (!first_t) std::fputc(',', timing_.f);
      c.write(out_t, r);
      first_t = false;
    }
  }
  std::fputc('\n', steps_.f);
  std::fputc('\n', timing_.f);
}

void StepsWriter::close() {
  close_csv(steps_.f, steps_.path);
  close_csv(timing_.f, timing_.path);
}

}  // namespace harness
