// VoxelExactDetector ("voxel_exact"): the paper's local voxel grid with an exact narrow phase,
// what the paper leaves to future work ("improve collision elimination method using information
// about points in voxels"). Each step:
//   1. the paper's Initializer re-attaches the grid to the host (initializer.hpp: area of
//      interest, centred on the host's box, power-of-two voxels, region half / full / overlap,
//      margin), exactly as for the voxel detector;
//   2. VoxelData lists the host's SURFACE vertices (body-local 0..n_surface-1), whatever
//      host_nodes says: the narrow phase needs surface vertices and their triangles, and interior
//      nodes would only lengthen the lists (host_nodes is ignored, not refused, so that a scene
//      switches detector with one key). The lists are rebuilt every step: the grid moves with the
//      host's box centre, so an incremental update would touch every vertex anyway, and a fill of
//      the surface alone is already cheaper than the voxel detector's fill of every host node;
//   3. for each guest node in a voxel of the region (the SIMD VoxelIndexer batch rejects the rest),
//      the candidates are the host triangles incident to the vertices listed in its voxel and its
//      26 neighbours (those inside the region: the "block"), deduplicated with a stamp per
//      triangle. An empty block means no contact: the node is deeper than the grid can see (or
//      far outside), a miss the references count, as for the paper's detector;
//   4. the candidate nearest to the node (Ericson's region-based closest point, which also names
//      the feature: vertex, edge or interior) gives the closest point p and distance d; the node
//      is inside when (x - p) . N < 0, N the angle-weighted pseudonormal of that feature
//      (Baerentzen and Aanaes 2005: the face normal; the sum of the two face normals of an edge;
//      the sum of a vertex's incident face normals weighted by their angles at it), taken from
//      the mesh's topology, not from the candidates. A node on the surface is outside (CGAL's
//      strict test).
//
// The band. Every point of a triangle lies within L/sqrt(3) of one of its vertices (L its longest
// edge: the circumradius of an acute triangle is at most L/sqrt(3), and in a right or obtuse one
// every point is within L/2 of a vertex). Let r(x) be the distance from the node x to the
// boundary of its block clipped to the region (per axis the nearer face of the box of at most
// 3 x 3 x 3 voxels around x's voxel that lies inside the grid; r >= v inside, r < v where the
// block meets the region's edge), and L_max the longest host surface edge at this step's
// positions. If the nearest candidate is at
//     d_c < band(x) = r(x) - L_max / sqrt(3)        (less a rounding slack of ~1e-12 relative),
// then the truly nearest surface point q (|x - q| <= d_c) lies on a triangle with a vertex within
// d_c + L_max/sqrt(3) < r(x) of x, i.e. listed in the block: that triangle is a candidate, so
// d_c is the exact distance and p an exact closest point, and the pseudonormal verdict is
// exact. Conversely every node inside at true depth d < band(x) has such a vertex in its block
// and is found (no false negatives within the band). The grid-edge rule is r(x) itself: where
// the block sticks out of the region (half, overlap, or the full region's boundary) host
// vertices outside are not listed, and r(x) is measured to the region's face instead, so such a
// node's band shrinks (often below zero) rather than being trusted. (The rule v - L_max of the
// issue is the special case r = v with every vertex of the triangle in the block; this band is
// wider: r >= v and L_max/sqrt(3) < L_max, and still exact.)
// Beyond the band. A node found inside with d_c >= band(x) is still a contact (pushed best
// effort along its candidate normal: dropping it would leave a deeper node unresisted) and is
// counted in beyond_band() (steps.csv `beyond_band`, summary.json `beyond_band_total` /
// `beyond_band_peak`), never silently dropped. So is a node strictly inside the host's box whose
// block lists no host vertex at all (undecided(): deeper than the grid sees, or in a hollow of the
// box; no force acts on it, and the run says how many there are). A node found outside beyond the band is reported
// as outside (most are; the references measure the rest).
//
// Voxel size. An explicit voxel_size is rounded down to a power of two as the paper's. Automatic
// (0): the paper's automatic size (initializer.hpp: the smallest power of two at or above the host's
// node spacing, its mean surface edge at rest), doubled until
// v > L_max / sqrt(3) at rest, so that every node has a positive band at rest (the bundled scenes
// and the bench keep the paper's size). A wider band needs a larger voxel_size: the candidates
// grow as v^2 on a surface.
//
// Contacts: Contact{guest, key = the host triangle holding p} in guest node order, as the hash
// and exact detectors report them. Per contact the detector keeps p's barycentric weights on that
// triangle, the depth d and the outward direction n = (p - x) / |p - x| (the negative gradient
// of the depth: the penalty 1/2 k d^2 then has force k d n on the node and -w_k k d n on the
// triangle's vertices, its exact gradient by the envelope theorem, so the depth penalty with
// barycentric reactions is conservative); when |p - x| vanishes to rounding, the unit
// pseudonormal. nearest_hosts() gives the triangle's vertices nearest first (so the line rule
// puts a constant or automatic force's reaction on the nearest vertex, as for cgal and hash),
// contact_direction() n, contact_point() the weights, n and d.
//
// Speed. A guest node outside the host's bounding box (or on it) is outside the closed surface:
// it is rejected before any candidate is looked at (most nodes of the region's margin). The
// candidates of a voxel are the same for every guest node in it: each thread keeps those of up
// to kEntries voxels (direct-mapped by voxel index) with their triangles' bounding boxes side
// by side (each entry's storage starts at kEntryCap candidates and doubles when a voxel lists
// more: a host with long triangles, such as a shell, lists hundreds per voxel). Per node the squared distance to each box (two lanes at a time) bounds the distance
// to its triangle from below: the candidate with the least bound is evaluated first, then only
// those whose bound is below the best distance so far (a skipped one can at most tie: any
// nearest point gives the exact distance and verdict; ties go to the first found in the voxel's
// fixed candidate order). L_max is one parallel pass over the host's unique surface edges.
// No heap allocation per step after initialize(), except when the host outgrows the region (a
// rebuild), once when the thread count is first raised, and when a cache entry first has to
// hold more candidates than it ever held (its storage doubles: a few times in a run). With several threads the guest
// nodes are looked up in chunks whose contacts are appended in chunk order, as in voxel.cpp:
// contacts, their data and beyond_band() are the same, bit for bit, for any thread count.
#pragma once

#include "core/collision/detectors/collision_detector.hpp"
#include "core/collision/initializer.hpp"
#include "core/collision/voxel_data.hpp"

#include <cstdint>
#include <memory>
#include <vector>

namespace harness {

class VoxelExactDetector final : public CollisionDetector {
 public:
  // Feature of a triangle (t[0], t[1], t[2]) nearest to a node: vertex t[k] (k = 0..2), edge
  // (t[k], t[k+1 mod 3]) (3 + k), or the interior (6).
  static constexpr int kInterior = 6;
  // Each thread keeps the candidates of up to kEntries voxels (a direct-mapped cache) with their
  // bounding boxes, room for kEntryCap candidates each at first (doubled when a voxel has more).
  static constexpr int kEntries = 256;
  static constexpr int kEntryBits = 8;  // log2(kEntries)
  static constexpr int kEntryCap = 32;

  // What detect() found for a guest node it reports as a contact.
  struct Hit {
    int tri;           // host face (index into Body::faces) holding the closest point p
    int feature;       // of that face, as above
    bool within;       // depth < band: the answer is exact
    double depth;      // m, > 0
    double band;       // m, band(x) at the node this step
    double weight[3];  // barycentric weights of p on the face's vertices (sum 1)
    double normal[3];  // outward unit direction (above)
  };

  const char* name() const override { return "voxel_exact"; }
  // Throws std::invalid_argument as the Initializer does, and for a host without a closed,
  // consistently oriented 2-manifold surface (every edge in exactly two faces, once each way).
  void initialize(const World& w, const ContactSpec& spec) override;
  void detect(const World& w, std::vector<Contact>& out) override;
  int nearest_hosts(const World& w, const Contact& c, int k, int* out) const override;
  bool contact_direction(const World& w, const Contact& c, Vec3& n) const override;
  bool contact_point(const World& w, const Contact& c, ContactPoint& out) const override;
  double voxel_size() const override { return init_.voxel_size(); }
  int rebuilds() const override { return init_.rebuilds(); }
  bool region(Vec3& lo, Vec3& hi) const override;
  int beyond_band() const override { return beyond_; }
  // Of beyond_band(): the guest nodes strictly inside the host's box whose block lists no host
  // vertex (undecided: the grid cannot tell inside from outside there; no force acts on them).
  int undecided() const { return undecided_; }

  // The contact's data (null when c is not a contact of the last detect()).
  const Hit* hit(const Contact& c) const;
  // band(x) on this step's grid and L_max (after detect()); -infinity outside the region.
  double band_at(const Vec3& x) const;
  // L_max of the last detect(), m.
  double longest_edge() const { return lmax_; }
  const VoxelData& grid() const { return grid_; }
  const Initializer& initializer() const { return init_; }
  // The voxel size an automatic request (voxel_size 0) gets on the current positions (above).
  static double automatic_voxel_size(const World& w, const ContactSpec& spec);

 private:
  // One cached voxel's candidates.
  struct Entry {
    std::uint32_t step = 0;  // detect() it belongs to (0: none)
    int cell = -1;
    int count = 0;           // candidates
    int cap = 0;             // room in tri and box (candidates): box holds 6 rows of cap
    double tlo[3] = {}, thi[3] = {};  // its block, grid coordinates (t = (x - c) / v)
    std::vector<int> tri;       // candidate faces
    std::vector<double> box;    // 6 x cap: lo x, y, z, hi x, y, z of each candidate
  };
  // One thread's cache of candidates.
  struct Workspace {
    std::vector<std::uint32_t> stamp;  // per host face: the gather that last took it
    std::uint32_t gather = 0;
    Entry entry[kEntries];
    std::vector<int> gathered;  // a voxel's candidates (capacity: every face), gathered first here
    std::vector<double> bound;  // per candidate of one node: squared distance to its box (+ 4)
  };

  // The cache entry of `cell`, gathered if it is not there.
  Entry& candidates(const World& w, int cell, Workspace& ws) const;
  // The node's answer; true (and `out` set) when it is inside.
  bool evaluate(const World& w, const Vec3& x, int cell, Workspace& ws, Hit& out) const;
  // Scans the guest nodes [begin, end) (global) in order: emit(contact) for each one inside, its
  // hit stored; adds the nodes found beyond the band to `beyond`.
  template <class Emit>
  void scan(const World& w, const VoxelIndexer& idx, int begin, int end, Workspace& ws, Emit&& emit, int& beyond,
            int& undecided);
  double band_of(const Vec3& x, const double tlo[3], const double thi[3]) const;
  Vec3 pseudonormal(const World& w, int face, int feature) const;
  Vec3 unit_normal(const World& w, int face) const;
  double longest_edge_now(const World& w) const;
  void ensure_workspaces(int threads);

  Initializer init_;
  VoxelData grid_;
  int host_begin_ = 0, n_surface_ = 0, guest_begin_ = 0, guest_size_ = 0;
  std::vector<Tri> faces_;               // host faces, body-local vertices
  std::vector<int> vf_start_, vf_faces_;  // vertex -> incident faces (CSR)
  std::vector<int> adjacent_;            // 3 per face: the face across edge (t[k], t[k+1])
  std::vector<Edge> edges_;              // unique surface edges, global node indices
  double lmax_ = 0.0;                    // longest surface edge this step, m
  double lterm_ = 0.0;                   // L_max / sqrt(3) with its slack, m
  std::uint32_t now_ = 0;                // detect() counter (0: none yet)
  int beyond_ = 0;
  int undecided_ = 0;
  // Per guest node (body-local): its hit, valid when hit_step_ says this detect() wrote it. Not
  // value-initialised (only the contacts' entries are ever written or read).
  std::unique_ptr<Hit[]> hits_;
  std::vector<std::uint32_t> hit_step_;
  std::vector<Workspace> ws_;            // one per thread
  std::vector<Contact> scratch_;         // parallel lookup: per-chunk contacts (guest size)
};

}  // namespace harness
