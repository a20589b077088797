// Parameters of one contact pair as resolved from the scene (docs/scenes.md, "contacts"), and the
// names the scene uses for each choice (a detector or an eliminator is its file pair, registered in
// it; a force rule is one file, core/collision/rules/).
#pragma once

#include <string>
#include <utility>
#include <vector>

namespace harness {

enum class Region { half, full, overlap };
enum class HostNodes { all, surface };
// Which way the line and plane push along their direction (directions.hpp): the paper's rules
// (line: from the nearest host node toward the guest node; plane: agreeing with the host's
// outward normals), or both the same way: `guest` (from the host node, or the plane, toward the
// guest node) or `outward` (agreeing with the host's outward normals at the host nodes).
enum class Orient { paper, guest, outward };

// The cookie of a ContactSpec made from the scene's key table (b2DefaultWorldDef's pattern).
inline constexpr unsigned kContactSpecMade = 0x5CE4E7A8u;

// One pair's parameters. Every value but the bodies' indices comes from the scene's key table
// (core/scene/keys.cpp, rows "contact.*"), never from this struct: its members have no defaults
// of their own. A spec is made by the scene loader or by contact_spec_defaults()
// (core/scene/scene.hpp: the table's defaults, read as the loader reads an empty contact), which
// set `made`; check_pair (collision.hpp) refuses one without it. Set fields after making it.
struct ContactSpec {
  int host = -1;  // body index in World::bodies
  int guest = -1;
  // Which detection drives elimination, by name (core/collision/detectors/, registered by
  // collision_detector.hpp's HARNESS_DETECTOR; the exact ones need the reference library).
  std::string detector;
  double voxel_size;  // requested, m; rounded down to a power of two; 0 = automatic
  double cell_size;   // spatial hashing's cell, m; 0 = automatic (mean host edge)
  double volume_pixel;  // the volume response's image pixel, m; 0 = automatic (responses/volume.hpp)
  Region region;
  int margin;  // voxels added around the region
  HostNodes host_nodes;
  // The response (core/collision/responses/, registered by collision_eliminator.hpp's
  // HARNESS_ELIMINATOR): the direction rule of the push (line, plane, ...), or a position-based
  // correction (projection, volume), by name.
  std::string eliminator;
  Orient orient;
  // How large each contact's force is: a rule of the registry (core/collision/responses/
  // force_rule.hpp: constant, auto, penalty, ...) by name, and its parameters in its order.
  std::string force_rule;
  std::vector<double> force_parameters;
  double separation_time;  // s, of the automatic force: v_sep = L / separation_time
  double field_resample;  // distance_field: resample when a host vertex moved this share of a voxel
  double damping;  // N s/m per contact: F -> max(0, F - damping v_n) where F > 0 (0: none; a variant)
  // Also the other way round: the guest's surface keeps the host's nodes out as well (a second
  // detector with the roles swapped). The paper's model is one-sided (false).
  bool two_sided;
  // Pushes the wrong way (every direction negated): a broken method, for the tests that show an
  // accuracy threshold fails when the method is broken.
  bool invert_push;
  unsigned made = 0;  // kContactSpecMade when made from the key table
};

}  // namespace harness
