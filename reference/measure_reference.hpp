// The exact references of a contact pair (README.md, "Outputs of a run"): CGAL ground truth,
// FCL triangle pairs, libccd signed distance of the convex hulls. A measurer reads the world and
// never changes it; it keeps its meshes and trees between calls.
#pragma once

#include "core/clock.hpp"
#include "core/measure.hpp"
#include "reference/cgal_surface.hpp"
#include "reference/fcl_surface.hpp"

#include <cstdint>
#include <map>
#include <memory>
#include <string>
#include <vector>

namespace harness {

// Per measure() call, for the solvers the spec asks for:
//  cgal: every node of each body (interior nodes too) classified against the other body's
//        closed surface; residual depths; the signed distance of every surface vertex to the
//        other body's surface (negative inside); tp/fp/fn of `detected`; surfaces_intersect with the
//        bounded-side test (containment counts); nodes that have passed through the other body
//        (tunnelled_guest / tunnelled_host: Passages below); t_cgal_us. With spec.volume also the penetration
//        volume by corefinement (has_volume false when CGAL cannot give it), timed apart in
//        t_volume_us and not in t_cgal_us.
//  fcl:  intersecting triangle pairs of the two surfaces and the deepest local contact depth;
//        t_fcl_us (vertex replacement and refit included).
//  ccd:  convex hulls of each body's nodes, recomputed, and their signed distance by GJK/EPA;
//        t_ccd_us (hulls included).
// spec.every is the caller's business: every call measures. A state with a non-finite position
// is not measured (all has_* false): exact predicates abort on NaN.
// Each node's passages through the other body, followed from one measure() call to the next
// along the straight path between them: the crossings of that path with the other body's surface
// (CgalSurface::crossings), reconciled with the node's exact side at both ends. On entering, the
// crossed face's outward normal is kept; on leaving through a face whose normal has a negative dot
// product with it, the node's parity flips (it is on the other side of the body now).
struct Passages {
  std::vector<Vec3> prev;              // position at the last call
  std::vector<std::uint8_t> inside;    // strictly inside at the last call
  std::vector<Vec3> entry;             // while inside: outward normal of the face it entered by
  std::vector<std::uint8_t> through;   // parity of the passages through
  bool started = false;
  // Follows the nodes of `b` (pen: this call's inside flags, body-local) against `other`;
  // returns how many have passed through.
  int update(const World& w, const Body& b, const CgalSurface& other, const std::vector<std::uint8_t>& pen);

 private:
  std::vector<SurfaceCrossing> hits_;
};

class ReferenceMeasurer final : public Measurer {
 public:
  ReferenceMeasurer(const World& w, const ContactSpec& pair, const ReferenceSpec& spec,
                    FclBv bv = FclBv::aabb, FclRefitPolicy refit = {});
  using Measurer::measure;
  void measure(const World& w, const ContactSpec& pair, const std::vector<Contact>& detected,
               const std::vector<Contact>& detected_host, Measurement& out) override;

  // The CGAL surfaces as last updated (tests, diagnostics).
  const CgalSurface& cgal_surface(bool host) const { return host ? cg_host_ : cg_guest_; }
  // Per guest node (body-local index): truly penetrating at the last CGAL measurement.
  const std::vector<std::uint8_t>& guest_penetrating() const { return pen_guest_; }

 private:
  // The parts of measure: CGAL's truly penetrating nodes, depths, tunnelling and the detector's
  // scores against them; FCL's intersecting triangle pairs; libccd's convex hull distance.
  void measure_cgal(const World& w, Clock::time_point t0, const std::vector<Contact>& detected,
                    const std::vector<Contact>& detected_host, Measurement& out);
  void score_detected(const World& w, const std::vector<Contact>& detected, const std::vector<Contact>& detected_host,
                      Measurement& out);
  void measure_fcl(const World& w, Measurement& out);
  void measure_ccd(const World& w, Measurement& out);

  ReferenceSpec spec_;
  int host_ = -1, guest_ = -1;
  CgalSurface cg_host_, cg_guest_;
  FclSurface fc_host_, fc_guest_;
  std::vector<std::uint8_t> pen_guest_;
  std::vector<std::uint8_t> pen_host_;
  std::vector<int> hint_guest_, hint_host_;  // per surface vertex: its closest face when last measured
  std::vector<double> sd_guest_, sd_host_;  // per surface vertex: signed distance to the other body, m
  std::vector<std::uint8_t> need_guest_, need_host_;  // per surface vertex: its distance must be exact
  Passages pass_guest_, pass_host_;         // guest nodes through the host, host nodes through the guest
  std::vector<int> seen_;       // per guest node: stamp of the last call that counted it as detected
  std::vector<int> seen_host_;  // the same per host node
  int stamp_ = 0;
  std::vector<TrianglePair> pairs_;
  Points hull_v_[2];
  std::vector<Tri> hull_f_[2];
};

// The factory the harness program installs (a MeasurerFactory).
std::unique_ptr<Measurer> make_reference_measurer(const World& w, const ContactSpec& pair,
                                                  const ReferenceSpec& spec);

// "FCL 0.7.0, CGAL 5.5.1"
std::string reference_versions();
// {{"FCL", "0.7.0"}, {"CGAL", "5.5.1"}}: for summary.json's `versions` (RunOptions::versions).
std::map<std::string, std::string> reference_version_map();

}  // namespace harness
