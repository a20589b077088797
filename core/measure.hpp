// Measurement of a contact pair by exact references (implemented in reference/, so that
// core stays free of FCL and CGAL). A measurement only reads the world: it never changes
// the simulation.
#pragma once

#include "core/collision/detectors/collision_detector.hpp"
#include "core/scene/contact_spec.hpp"
#include "core/scene/reference_spec.hpp"
#include "core/world.hpp"

#include <cstdint>
#include <functional>
#include <memory>
#include <string>
#include <vector>

namespace harness {

// One pair on one measured step. `has_*` says which groups were measured.
struct Measurement {
  bool has_cgal = false, has_fcl = false, has_ccd = false, has_volume = false;
  // CGAL (exact predicates): nodes strictly inside the other body's closed surface.
  int true_pen_guest = 0, true_pen_host = 0;
  int tp = 0, fp = 0, fn = 0;  // detected guest nodes against truly penetrating guest nodes
  // detected host nodes (the other way round, two-sided contact) against truly penetrating host
  // nodes: a one-sided detector reports none, so every penetrating host node is a miss.
  int tp_host = 0, fp_host = 0, fn_host = 0;
  double max_depth = 0.0, mean_depth = 0.0;  // m, over penetrating nodes of both bodies
  // CGAL: nodes that have passed through the other body: entered it through one face and left it
  // through a face turned away from that one (outward normals with a negative dot product),
  // followed along each node's straight path between measured steps. A node that passes back
  // again no longer counts; one pushed back out where it came in, or one that wraps around the
  // other body without entering it, never counts.
  int tunnelled_guest = 0, tunnelled_host = 0;
  bool surfaces_intersect = false;
  double t_cgal_us = 0.0;
  double penetration_volume = 0.0;  // m^3, when has_volume
  double t_volume_us = 0.0;         // corefinement time, not included in t_cgal_us
  // FCL: intersecting triangle pairs and deepest local contact depth.
  int fcl_pairs = 0;
  double fcl_max_depth = 0.0;
  double t_fcl_us = 0.0;
  // libccd (GJK/EPA on convex hulls): signed distance, negative = penetration depth.
  double ccd_distance = 0.0;
  // Per node, body-local: 1 when truly penetrating (CGAL); null when not measured. They point
  // into the measurer and stay valid until its next measure().
  const std::vector<std::uint8_t>* pen_guest = nullptr;
  const std::vector<std::uint8_t>* pen_host = nullptr;
  // CGAL: per surface vertex (body-local, < n_surface) its signed distance to the other body's
  // surface, m (negative inside); null when not measured. Valid until the next measure(). Exact
  // for the vertices Measurer::needs asks for (all by default); the others get a lower bound >= 0
  // (their distance to the other body's bounding box).
  const std::vector<double>* sd_guest = nullptr;
  const std::vector<double>* sd_host = nullptr;
  // CGAL: per node (body-local) the parity of its passages through the other body (1: on the far
  // side of it, tunnelled_guest / tunnelled_host count these); null when not measured. Valid until
  // the next measure().
  const std::vector<std::uint8_t>* through_guest = nullptr;
  const std::vector<std::uint8_t>* through_host = nullptr;
  double t_ccd_us = 0.0;
};

class Measurer {
 public:
  virtual ~Measurer() = default;
  // Which surface vertices' signed distances must be exact at the next measure(): all of them
  // (the default), or only those inside the other body, those a detector reported this step,
  // and those whose distance in the reference (ref_guest, ref_host: per surface vertex, null for
  // none) is within `touch`: the only ones the figures read (depth, distance of pushed nodes,
  // gap of touching nodes). The recorder asks for all on steps that write them (frames, the
  // trajectory, the last step's surfaces.csv).
  struct DistanceNeeds {
    bool all = true;
    const std::vector<double>* ref_guest = nullptr;
    const std::vector<double>* ref_host = nullptr;
    double touch = 0.0;
  };
  DistanceNeeds needs;
  // `detected` is what the pair's detector reported this step (guest nodes, global indices);
  // `detected_host` what it reported the other way round (host nodes inside the guest; empty
  // for a one-sided pair).
  virtual void measure(const World& w, const ContactSpec& pair, const std::vector<Contact>& detected,
                       const std::vector<Contact>& detected_host, Measurement& out) = 0;
  void measure(const World& w, const ContactSpec& pair, const std::vector<Contact>& detected, Measurement& out) {
    measure(w, pair, detected, {}, out);
  }
};

using MeasurerFactory =
    std::function<std::unique_ptr<Measurer>(const World&, const ContactSpec&, const ReferenceSpec&)>;

}  // namespace harness
