// The key paths of summary.json that are read back, as JSON pointers, spelled here only:
// summary.cpp writes them through these names, `harness sweep` merges them into runs.csv
// (experiments/sweep.cpp), --compare reads a reference's dt and convergence (compare.cpp) and
// `harness reference` adds its record under kReference. Per pair keys are relative to
// kPairs + "/N". The other keys of summary.json are written once, in summary.cpp; the whole file
// is described in docs/outputs.md (generated: `harness outputs`, core/run/outputs_doc.cpp).
#pragma once

#include <string>

namespace harness::summary_key {

inline constexpr const char* kStatus = "/status";
inline constexpr const char* kSteps = "/steps_run";
inline constexpr const char* kFinite = "/finite";
inline constexpr const char* kResolvedScene = "/resolved_scene";
inline constexpr const char* kSceneDt = "/resolved_scene/time/dt";
inline constexpr const char* kStateHash = "/state_hash";
inline constexpr const char* kTiming = "/timing_us";
inline constexpr const char* kStability = "/stability";
inline constexpr const char* kMaxSubsteps = "/stability/max_substeps";
inline constexpr const char* kGuardViolations = "/stability/guard_violations";
inline constexpr const char* kKineticFinal = "/kinetic_energy_final";
inline constexpr const char* kKineticPeak = "/kinetic_energy_peak";
inline constexpr const char* kEnergy = "/energy";
inline constexpr const char* kSettled = "/settled";
inline constexpr const char* kResidual = "/residual";
inline constexpr const char* kSettleSteps = "/settle_steps";
inline constexpr const char* kPairs = "/pairs";
inline constexpr const char* kCompare = "/compare";
inline constexpr const char* kCompareConverged = "/compare/converged";
inline constexpr const char* kReference = "/reference";
inline constexpr const char* kReferenceConverged = "/reference/converged";
inline constexpr const char* kReferenceFloor = "/reference/floor";
inline constexpr const char* kStabilityVerdict = "/stability_verdict";
inline constexpr const char* kWindow = "/window";
// Under kWindow: the contact's mean power over the window against the power the scene put in.
inline constexpr const char* kContactPowerRatio = "contact_power_ratio";

// Under kTiming: median wall times of a step's parts, microseconds.
inline constexpr const char* kTimingParts[] = {"step", "physics", "detect", "eliminate", "cgal", "fcl"};
// Under kEnergy: the energy audit (energy.hpp).
inline constexpr const char* kWorkExternal = "work_external";
inline constexpr const char* kDissipated = "energy_dissipated";
inline constexpr const char* kWorkContact = "work_contact";
inline constexpr const char* kWorkContactPeak = "work_contact_peak";
inline constexpr const char* kBalanceError = "energy_balance_error";

// Per pair, under kPairs + "/N".
inline constexpr const char* kVoxelSizeUsed = "/voxel_size_used";
inline constexpr const char* kRegionRebuilds = "/region_rebuilds";
inline constexpr const char* kContactsTotal = "/contacts_total";
inline constexpr const char* kTruePenFinal = "/true_pen_final";
inline constexpr const char* kMaxDepthFinal = "/max_depth_final";
inline constexpr const char* kMaxDepthPeak = "/max_depth_peak";
inline constexpr const char* kRecall = "/recall";
inline constexpr const char* kPrecision = "/precision";
inline constexpr const char* kTunnelled = "/tunnelled";  // guest nodes
inline constexpr const char* kTunnelledHost = "/tunnelled_host";
inline constexpr const char* kErrorVsReference = "/error_vs_reference";
// The same figures against the second reference (--compare-also): its dir and convergence, the
// final figures (kErrorFigures but depth_max) and their window statistics (/window/...).
inline constexpr const char* kErrorVsReferenceAlso = "/error_vs_reference_also";
// Under kErrorVsReference.
inline constexpr const char* kErrorFigures[] = {"pos_err_max", "pos_err_rms", "gap_max", "gap_mean", "depth_max"};
// Under kErrorVsReference: the largest position error over the final window (stat_json: mean,
// max, amplitude = max - min, the chatter).
inline constexpr const char* kErrorWindow = "/window/pos_err_max";
// Under kErrorVsReference: the deepest true penetration over the final window (stat_json).
inline constexpr const char* kDepthWindow = "/window/depth_max";

// The pointer of a key of pair p.
inline std::string pair_key(int p, const char* key) { return std::string(kPairs) + "/" + std::to_string(p) + key; }

}  // namespace harness::summary_key
