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
      {"step", [](O o, R r) { o.integer(r.sim.step_index()); }},
      {"time", [](O o, R r) { o.g9(r.sim.time()); }},
      {"pair", [](O o, R r) { if (r.pair) o.text(r.pair->label); }},
      {"detector", [](O o, R r) { if (r.pair) o.text(r.pair->collision ? to_string(r.pair->spec.detector) : r.pair->engine_contact ? r.pair->engine_contact : "none"); }},
      {"contacts", [](O o, R r) { if (any_contact(r)) o.integer(r.pair->last.contacts); }},
      {"t_step_us", [](O o, R r) { o.us(r.sim.last().step_us); }},
      {"t_physics_us", [](O o, R r) { o.us(r.sim.last().physics_us); }},
      {"t_detect_us", [](O o, R r) { if (any_contact(r)) o.us(r.pair->last.detect_us); }},
      {"t_eliminate_us", [](O o, R r) { if (contact(r)) o.us(r.pair->last.eliminate_us); }},
      {"kinetic_energy", [](O o, R r) { o.g9(r.kinetic_energy); }},
      {"true_pen_guest", [](O o, R r) { if (cgal(r)) o.integer(r.m->true_pen_guest); }},
      {"true_pen_host", [](O o, R r) { if (cgal(r)) o.integer(r.m->true_pen_host); }},
      {"tp", [](O o, R r) { if (cgal(r)) o.integer(r.m->tp); }},
      {"fp", [](O o, R r) { if (cgal(r)) o.integer(r.m->fp); }},
      {"fn", [](O o, R r) { if (cgal(r)) o.integer(r.m->fn); }},
      {"max_depth", [](O o, R r) { if (cgal(r)) o.g9(r.m->max_depth); }},
      {"mean_depth", [](O o, R r) { if (cgal(r)) o.g9(r.m->mean_depth); }},
      {"surfaces_intersect", [](O o, R r) { if (cgal(r)) o.integer(r.m->surfaces_intersect ? 1 : 0); }},
      {"fcl_pairs", [](O o, R r) { if (fcl(r)) o.integer(r.m->fcl_pairs); }},
      {"t_cgal_us", [](O o, R r) { if (cgal(r)) o.us(r.m->t_cgal_us); }},
      {"t_fcl_us", [](O o, R r) { if (fcl(r)) o.us(r.m->t_fcl_us); }},
      // Past the contract's columns:
      {"force", [](O o, R r) { if (contact(r)) o.g9(r.pair->last.force); }},
      {"fcl_max_depth", [](O o, R r) { if (fcl(r)) o.g9(r.m->fcl_max_depth); }},
      {"ccd_distance", [](O o, R r) { if (ccd(r)) o.g9(r.m->ccd_distance); }},
      {"t_ccd_us", [](O o, R r) { if (ccd(r)) o.us(r.m->t_ccd_us); }},
      {"penetration_volume", [](O o, R r) { if (r.m && r.m->has_volume) o.g9(r.m->penetration_volume); }},
      {"potential_energy", [](O o, R r) { if (!std::isnan(r.potential_energy)) o.g9(r.potential_energy); }},
      {"region_lo_x", region<0>},
      {"region_lo_y", region<1>},
      {"region_lo_z", region<2>},
      {"region_hi_x", region<3>},
      {"region_hi_y", region<4>},
      {"region_hi_z", region<5>},
      {"t_volume_us", [](O o, R r) { if (r.m && r.m->has_volume) o.us(r.m->t_volume_us); }},
      // The energy audit (energy.hpp), J, cumulative where it is work; the force residual.
      // The works, the kinetic energy: every step; the elastic energy and the balance (which
      // needs it): on the steps the recorder evaluated it (recorder.hpp), empty on the others.
      {"energy_kinetic", [](O o, R r) { o.g9(r.sim.energy_booked().kinetic); }},
      {"energy_elastic", [](O o, R r) { if (r.sim.energy_current()) o.g9(r.sim.energy_booked().elastic); }},
      {"work_external", [](O o, R r) { o.g9(r.sim.energy_booked().work_external); }},
      {"energy_dissipated", [](O o, R r) { o.g9(r.sim.energy_booked().dissipated); }},
      {"work_contact", [](O o, R r) { o.g9(r.sim.energy_booked().work_contact); }},
      {"energy_balance_error", [](O o, R r) { if (r.sim.energy_current()) o.g9(r.sim.energy_booked().balance_error()); }},
      {"residual", [](O o, R r) { o.g9(r.sim.residual()); }},
      // Accuracy both ways (run/compare.hpp), m: the signed distance of the nodes contact pushed
      // (positive: across a gap), and the error against the reference at this step.
      {"force_dist_max", [](O o, R r) { if (r.fig && r.fig->force_dist) o.g9(r.fig->force_dist_max); }},
      {"force_dist_mean", [](O o, R r) { if (r.fig && r.fig->force_dist) o.g9(r.fig->force_dist_mean); }},
      {"gap_max", [](O o, R r) { if (r.fig && r.fig->vs_reference) o.g9(r.fig->errors.gap_max); }},
      {"gap_mean", [](O o, R r) { if (r.fig && r.fig->vs_reference) o.g9(r.fig->errors.gap_mean); }},
      {"pos_err_max", [](O o, R r) { if (r.fig && r.fig->vs_reference) o.g9(r.fig->errors.pos_err_max); }},
      {"pos_err_rms", [](O o, R r) { if (r.fig && r.fig->vs_reference) o.g9(r.fig->errors.pos_err_rms); }},
      // Host nodes detected the other way round (two-sided contact) against those truly inside the
      // guest; nodes that have passed through the other body (core/measure.hpp tunnelled_guest).
      {"tp_host", [](O o, R r) { if (cgal(r)) o.integer(r.m->tp_host); }},
      {"fp_host", [](O o, R r) { if (cgal(r)) o.integer(r.m->fp_host); }},
      {"fn_host", [](O o, R r) { if (cgal(r)) o.integer(r.m->fn_host); }},
      {"tunnelled_guest", [](O o, R r) { if (r.fig && r.fig->tunnelled.measured) o.integer(r.fig->tunnelled.guest); }},
      {"tunnelled_host", [](O o, R r) { if (r.fig && r.fig->tunnelled.measured) o.integer(r.fig->tunnelled.host); }},
      // Guest nodes found inside beyond the detector's guaranteed band (voxel_exact), both ways;
      // empty for detectors without a band.
      {"beyond_band", [](O o, R r) { if (contact(r) && r.pair->last.beyond_band >= 0) o.integer(r.pair->last.beyond_band); }},
      // The error against the second reference (--compare-also), m; empty without one.
      {"also_gap_max", [](O o, R r) { if (r.fig && r.fig->vs_also && r.fig->also_errors.distances) o.g9(r.fig->also_errors.gap_max); }},
      {"also_gap_mean", [](O o, R r) { if (r.fig && r.fig->vs_also && r.fig->also_errors.distances) o.g9(r.fig->also_errors.gap_mean); }},
      {"also_pos_err_max", [](O o, R r) { if (r.fig && r.fig->vs_also) o.g9(r.fig->also_errors.pos_err_max); }},
      {"also_pos_err_rms", [](O o, R r) { if (r.fig && r.fig->vs_also) o.g9(r.fig->also_errors.pos_err_rms); }},
  };
  return columns;
}

StepsWriter::StepsWriter(const std::string& path) : path_(path) {
  f_ = std::fopen(path.c_str(), "w");
  if (!f_) throw std::runtime_error("cannot write " + path);
  std::setvbuf(f_, nullptr, _IOFBF, 1 << 20);
  const auto& cols = steps_columns();
  for (std::size_t c = 0; c < cols.size(); ++c) std::fprintf(f_, c ? ",%s" : "%s", cols[c].name);
  std::fputc('\n', f_);
}

StepsWriter::~StepsWriter() {
  if (f_) std::fclose(f_);
}

void StepsWriter::row(const StepRow& r) {
  const CsvField out(f_);
  const auto& cols = steps_columns();
  for (std::size_t c = 0; c < cols.size(); ++c) {
    if (c) std::fputc(',', f_);
    cols[c].write(out, r);
  }
  std::fputc('\n', f_);
}

void StepsWriter::close() {
  const bool ok = std::ferror(f_) == 0;
  const int rc = std::fclose(f_);
  f_ = nullptr;
  if (rc != 0 || !ok) throw std::runtime_error("cannot write " + path_);
}

}  // namespace harness
