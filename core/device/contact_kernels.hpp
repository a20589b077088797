// The contact's kernel bodies (kernels.hpp says how they are shared): per contact pair and
// direction, the paper's grid attached to the host (initializer.hpp's geometry, rebuilds when the
// host outgrows the region), filled with the host's nodes by a counting sort (voxel_data.hpp's
// lists: each voxel's nodes in increasing order), each guest node's push (voxel.hpp with the line
// or the plane rule, or voxel_exact.hpp's exact narrow phase; constant or penalty force:
// directions.hpp, force_rules.hpp), and the pushes applied in Collision's order.
#pragma once

#include "core/device/closest_kernels.hpp"
#include "core/device/kernels.hpp"

namespace harness::dev {

enum : int { kRegionHalf = 0, kRegionFull = 1, kRegionOverlap = 2 };
enum : int { kDetVoxel = 0, kDetVoxelExact = 1 };
enum : int { kElimLine = 0, kElimPlane = 1 };
enum : int { kForceConstant = 0, kForcePenalty = 1 };

// One direction's grid (Initializer and GridGeometry), in device memory: built at the rest state
// as the CPU's, updated every step by one thread.
struct GridState {
  double voxel = 0.0;
  int region = kRegionHalf, margin = 1;
  long long capacity = 0;  // voxels allocated
  double built_h[3] = {0, 0, 0};
  int n[3] = {0, 0, 0}, cap_lo[3] = {0, 0, 0}, cap_dims[3] = {0, 0, 0}, lo[3] = {0, 0, 0}, dims[3] = {0, 0, 0};
  int half_axis = -1, half_sign = 1;
  int rebuilds = 0;
  int error = 0;  // 1: a rebuild needed more voxels than allocated
  // This step: the host's box and the grid's geometry.
  double host_lo[3] = {0, 0, 0}, host_hi[3] = {0, 0, 0}, c[3] = {0, 0, 0};
  int glo[3] = {0, 0, 0}, gdims[3] = {0, 0, 0};
};

// Initializer::build: the region for host half extents h at centre c (guest centre gc).
HARNESS_HD inline bool grid_build(GridState& G, const double h[3], const double c[3], const double gc[3]) {
  const double m = G.margin;
  double n[3], dims_full[3], full_count = 1.0;
  for (int a = 0; a < 3; ++a) {
    n[a] = floor(h[a] / G.voxel) + 2.0;
    dims_full[a] = 2.0 * (n[a] + m);
    full_count *= dims_full[a];
  }
  int axis = -1, sign = 1;
  if (G.region == kRegionHalf) {
    double best = 0.0;
    for (int a = 0; a < 3; ++a) {
      const double d = gc[a] - c[a];
      const double ad = fabs(d);
      const double r = h[a] > 0.0 ? ad / h[a] : (ad > 0.0 ? INFINITY : 0.0);
      if (r > best) best = r, axis = a;
    }
    if (axis >= 0) sign = gc[axis] - c[axis] >= 0.0 ? 1 : -1;
  }
  double region_count = full_count;
  if (axis >= 0) region_count = full_count / dims_full[axis] * (n[axis] + 2.0 * m);
  const double alloc = G.region == kRegionOverlap ? full_count : region_count;
  if (!(alloc <= static_cast<double>(G.capacity))) {
    G.error = 1;
    return false;
  }
  for (int a = 0; a < 3; ++a) {
    G.built_h[a] = h[a];
    G.n[a] = static_cast<int>(n[a]);
    G.cap_lo[a] = -(G.n[a] + G.margin);
    G.cap_dims[a] = 2 * (G.n[a] + G.margin);
    G.lo[a] = G.cap_lo[a];
    G.dims[a] = G.cap_dims[a];
  }
  G.half_axis = axis, G.half_sign = sign;
  if (axis >= 0) {
    G.dims[axis] = G.n[axis] + 2 * G.margin;
    G.lo[axis] = sign > 0 ? -G.margin : -G.n[axis] - G.margin;
  }
  return true;
}

// Initializer::update from this step's boxes of the host (hlo, hhi) and the guest (glo_, ghi).
HARNESS_HD inline void grid_update(GridState& G, const double hlo[3], const double hhi[3], const double glo_[3],
                                   const double ghi[3]) {
  double c[3], h[3];
  bool finite = true;
  for (int a = 0; a < 3; ++a) {
    c[a] = 0.5 * (hlo[a] + hhi[a]);
    h[a] = 0.5 * (hhi[a] - hlo[a]);
    G.c[a] = c[a], G.host_lo[a] = hlo[a], G.host_hi[a] = hhi[a];
    finite = finite && isfinite(c[a]) && isfinite(h[a]);
  }
  for (int a = 0; a < 3; ++a) G.glo[a] = 0, G.gdims[a] = 0;
  if (!finite) return;
  if (h[0] > G.built_h[0] + G.voxel || h[1] > G.built_h[1] + G.voxel || h[2] > G.built_h[2] + G.voxel) {
    double gc[3];
    for (int a = 0; a < 3; ++a) gc[a] = 0.5 * (glo_[a] + ghi[a]);
    if (!grid_build(G, h, c, gc)) return;  // G.error set: the run stops with an error
    ++G.rebuilds;
  }
  if (G.region != kRegionOverlap) {
    for (int a = 0; a < 3; ++a) G.glo[a] = G.lo[a], G.gdims[a] = G.dims[a];
    return;
  }
  const double inv_v = 1.0 / G.voxel, m = G.margin;
  int lo[3], dims[3];
  for (int a = 0; a < 3; ++a) {
    double a0 = dmax(floor((hlo[a] - c[a]) * inv_v), floor((glo_[a] - c[a]) * inv_v)) - m;
    double a1 = dmin(floor((hhi[a] - c[a]) * inv_v), floor((ghi[a] - c[a]) * inv_v)) + m;
    a0 = dmax(a0, static_cast<double>(G.cap_lo[a]));
    a1 = dmin(a1, static_cast<double>(G.cap_lo[a] + G.cap_dims[a] - 1));
    if (!(a1 >= a0)) return;  // disjoint: no voxels
    lo[a] = static_cast<int>(a0);
    dims[a] = static_cast<int>(a1 - a0) + 1;
  }
  for (int a = 0; a < 3; ++a) G.glo[a] = lo[a], G.gdims[a] = dims[a];
}

HARNESS_HD inline int ifloor(double t) {
  const int i = static_cast<int>(t);
  return i - (t < i);
}
// VoxelIndexer: the voxel of p in this step's grid, or -1 (outside, or not finite).
HARNESS_HD inline int cell_of(const GridState& G, V3 p, int ijk[3] = nullptr) {
  const double inv = 1.0 / G.voxel;
  const double t0 = (p.x - G.c[0]) * inv, t1 = (p.y - G.c[1]) * inv, t2 = (p.z - G.c[2]) * inv;
  const double l0 = G.glo[0], l1 = G.glo[1], l2 = G.glo[2];
  const bool in = (t0 >= l0) & (t0 < l0 + G.gdims[0]) & (t1 >= l1) & (t1 < l1 + G.gdims[1]) & (t2 >= l2) &
                  (t2 < l2 + G.gdims[2]);
  if (!in) return -1;
  const int i = ifloor(t0) - G.glo[0], j = ifloor(t1) - G.glo[1], k = ifloor(t2) - G.glo[2];
  if (ijk) ijk[0] = i, ijk[1] = j, ijk[2] = k;
  return i + G.gdims[0] * (j + G.gdims[1] * k);
}

// One guest node's push (collision_eliminator.hpp's Push).
struct Push {
  int count;
  int hosts[3];
  double w[3];
  double n[3];
  double mag;
};

// One direction of one pair: its grid, the host's lists and surface, the guest's pushes and the
// hosts' reaction lists.
struct DirView {
  GridState* G = nullptr;
  int host_begin = 0, host_size = 0, host_surface = 0;
  int listed_begin = 0, listed = 0;  // host nodes in the lists
  int guest_begin = 0, guest_size = 0;
  int detector = kDetVoxel, eliminator = kElimLine, force_rule = kForceConstant;
  double force = 0.0, stiffness = 0.0;
  bool invert = false;
  // The grid's counting sort (capacity + 1 entries for cnt and start).
  int* cnt = nullptr;
  int* start = nullptr;
  int* cellof = nullptr;  // per listed node
  int* slot = nullptr;    // per listed node
  int* sorted = nullptr;  // global node indices, per voxel in increasing order
  // The keys path (a direction with few listed nodes): the listed nodes sorted by (voxel, node),
  // scell[k] the voxel of sorted[k] (kNoCell outside the grid); a voxel's list is found by binary
  // search instead of the counting sort's start[] (no array over the voxels). Null: start[].
  int* scell = nullptr;
  // The host's surface (body-local vertices): faces, vertex -> faces, edge neighbours.
  int nfaces = 0;
  const int* faces = nullptr;
  const int* vf_start = nullptr;
  const int* vf_faces = nullptr;
  const int* adjacent = nullptr;
  Push* push = nullptr;  // per guest node
  int* rc = nullptr;      // per host node + 1: reaction counts
  int* rstart = nullptr;  // per host node + 1
  int* rrec = nullptr;    // reactions, 3 per guest node: push * 4 + k
  int* rslot = nullptr;   // per push * 4 + k: where its reaction went
  int* contacts = nullptr;  // counter of this step's contacts
};

constexpr int kNoCell = 0x7fffffff;
constexpr int kKeysMax = 4096;  // listed nodes up to which a direction takes the keys path

// The sorted entries [b, e) of voxel `cell`.
HARNESS_HD inline void cell_range(const DirView& D, int cell, int& b, int& e) {
  if (!D.scell) {
    b = D.start[cell], e = D.start[cell + 1];
    return;
  }
  int lo = 0, hi = D.listed;  // first entry >= cell
  while (lo < hi) {
    const int m = (lo + hi) >> 1;
    if (D.scell[m] < cell) lo = m + 1;
    else hi = m;
  }
  b = lo, hi = D.listed;  // first entry > cell
  while (lo < hi) {
    const int m = (lo + hi) >> 1;
    if (D.scell[m] <= cell) lo = m + 1;
    else hi = m;
  }
  e = lo;
}
HARNESS_HD inline bool occupied(const DirView& D, int cell) {
  int b, e;
  cell_range(D, cell, b, e);
  return e > b;
}
// Calls fn(node) for every host node listed in the 3 x 3 x 3 block of voxels around ijk (those
// inside the grid): voxels in z, y, x order, each voxel's nodes in increasing order (the order of
// VoxelDetector::nearest_hosts and of voxel_exact's candidates).
template <class Fn>
HARNESS_HD inline void for_block_nodes(const DirView& D, const int ijk[3], Fn&& fn) {
  const GridState& G = *D.G;
  for (int dz = -1; dz <= 1; ++dz) {
    const int z = ijk[2] + dz;
    if (z < 0 || z >= G.gdims[2]) continue;
    for (int dy = -1; dy <= 1; ++dy) {
      const int y = ijk[1] + dy;
      if (y < 0 || y >= G.gdims[1]) continue;
      for (int dx = -1; dx <= 1; ++dx) {
        const int xx = ijk[0] + dx;
        if (xx < 0 || xx >= G.gdims[0]) continue;
        int cb, ce;
        cell_range(D, xx + G.gdims[0] * (y + G.gdims[1] * z), cb, ce);
        for (int s = cb; s < ce; ++s) fn(D.sorted[s]);
      }
    }
  }
}

// The keys path's key of listed node j: (voxel, j), the voxel kNoCell outside the grid.
HARNESS_HD inline unsigned long long fill_key(const DirView& D, const double* x, int j) {
  const int c = cell_of(*D.G, load3(x, D.listed_begin + j));
  return (static_cast<unsigned long long>(c < 0 ? kNoCell : c) << 32) | static_cast<unsigned>(j);
}
HARNESS_HD inline void key_store(const DirView& D, unsigned long long key, int k) {
  D.scell[k] = static_cast<int>(key >> 32);
  D.sorted[k] = D.listed_begin + static_cast<int>(key & 0xffffffffu);
}

// ---- The grid's fill: count, (scan), place, sort each voxel's list.
HARNESS_HD inline void fill_count(const DirView& D, const double* x, int j) {
  const int c = cell_of(*D.G, load3(x, D.listed_begin + j));
  D.cellof[j] = c;
  if (c >= 0) atomic_add(D.cnt + c, 1);
}
HARNESS_HD inline void fill_place(const DirView& D, int j) {
  const int c = D.cellof[j];
  if (c < 0) return;
  const int s = D.start[c] + atomic_add(D.cnt + c, -1) - 1;  // cnt back at 0 when all are placed
  D.sorted[s] = D.listed_begin + j;
  D.slot[j] = s;
}
HARNESS_HD inline void sort_range(int* a, int b, int e) {
  for (int i = b + 1; i < e; ++i) {
    const int v = a[i];
    int k = i;
    while (k > b && a[k - 1] > v) a[k] = a[k - 1], --k;
    a[k] = v;
  }
}
HARNESS_HD inline void fill_sort(const DirView& D, int j) {
  const int c = D.cellof[j];
  if (c >= 0 && D.slot[j] == D.start[c]) sort_range(D.sorted, D.start[c], D.start[c + 1]);
}

// ---- Directions (directions.hpp).
HARNESS_HD inline V3 vertex_normal(const DirView& D, const double* x, int s) {
  V3 n{0.0, 0.0, 0.0};
  for (int k = D.vf_start[s]; k < D.vf_start[s + 1]; ++k) {
    const int* t = D.faces + 3 * D.vf_faces[k];
    const V3 a = load3(x, D.host_begin + t[0]);
    n = n + cross(load3(x, D.host_begin + t[1]) - a, load3(x, D.host_begin + t[2]) - a);
  }
  return n;
}
HARNESS_HD inline V3 outward_hint(const DirView& D, const double* x, int node, V3 center) {
  const int s = node - D.host_begin;
  if (s < D.host_surface && D.nfaces > 0) {
    const V3 n = unit_or_zero(vertex_normal(D, x, s));
    if (sqnorm(n) > 0.0) return n;
  }
  return unit_or_zero(load3(x, node) - center);
}
HARNESS_HD inline V3 line_direction(const DirView& D, const double* x, int g, int h, V3 center) {
  V3 n = unit_or_zero(load3(x, g) - load3(x, h));
  if (sqnorm(n) > 0.0) return n;
  n = outward_hint(D, x, h, center);
  if (sqnorm(n) > 0.0) return n;
  n = unit_or_zero(load3(x, g) - center);
  if (sqnorm(n) > 0.0) return n;
  return V3{0.0, 0.0, 1.0};
}
HARNESS_HD inline bool plane_normal(V3 p0, V3 p1, V3 p2, V3 hint, V3 second, V3& n) {
  const V3 e1 = p1 - p0, e2 = p2 - p0;
  const double s2 = dmax(dmax(sqnorm(e1), sqnorm(e2)), sqnorm(p2 - p1));
  const V3 c = cross(e1, e2);
  if (!(norm(c) >= 1e-12 * s2) || !(s2 > 0.0)) return false;
  V3 u = unit_or_zero(c);
  if (sqnorm(u) == 0.0) return false;
  double side = dot(u, hint);
  if (side == 0.0 || !isfinite(side)) side = dot(u, second);
  if (side < 0.0) u = -u;
  n = u;
  return true;
}
// geometry.cpp's closest_on_triangle and barycentric.
HARNESS_HD inline V3 closest_on_triangle(V3 p, V3 a, V3 b, V3 c) {
  const V3 ab = b - a, ac = c - a, ap = p - a;
  const double d1 = dot(ab, ap), d2 = dot(ac, ap);
  if (d1 <= 0 && d2 <= 0) return a;
  const V3 bp = p - b;
  const double d3 = dot(ab, bp), d4 = dot(ac, bp);
  if (d3 >= 0 && d4 <= d3) return b;
  const double vc = d1 * d4 - d3 * d2;
  if (vc <= 0 && d1 >= 0 && d3 <= 0) return a + ab * (d1 / (d1 - d3));
  const V3 cp = p - c;
  const double d5 = dot(ab, cp), d6 = dot(ac, cp);
  if (d6 >= 0 && d5 <= d6) return c;
  const double vb = d5 * d2 - d1 * d6;
  if (vb <= 0 && d2 >= 0 && d6 <= 0) return a + ac * (d2 / (d2 - d6));
  const double va = d3 * d6 - d5 * d4;
  if (va <= 0 && (d4 - d3) >= 0 && (d5 - d6) >= 0) return b + (c - b) * ((d4 - d3) / ((d4 - d3) + (d5 - d6)));
  const double denom = 1.0 / (va + vb + vc);
  return a + ab * (vb * denom) + ac * (vc * denom);
}
HARNESS_HD inline void barycentric(V3 q, V3 a, V3 b, V3 c, double w[3]) {
  const V3 v0 = b - a, v1 = c - a, v2 = q - a;
  const double d00 = dot(v0, v0), d01 = dot(v0, v1), d11 = dot(v1, v1), d20 = dot(v2, v0), d21 = dot(v2, v1);
  const double den = d00 * d11 - d01 * d01;
  if (!(fabs(den) > 1e-30 * (d00 * d11 + 1e-300))) {
    const double da = sqnorm(q - a), db = sqnorm(q - b), dc = sqnorm(q - c);
    w[0] = w[1] = w[2] = 0.0;
    w[da <= db && da <= dc ? 0 : db <= dc ? 1 : 2] = 1.0;
    return;
  }
  w[1] = dmin(dmax((d11 * d20 - d01 * d21) / den, 0.0), 1.0);
  w[2] = dmin(dmax((d00 * d21 - d01 * d20) / den, 0.0), 1.0 - w[1]);
  w[0] = 1.0 - w[1] - w[2];
}

// ---- One guest node's push (the guest body's local node j).
HARNESS_HD inline void nearest3_offer(const double* x, V3 p, int node, int* out, double* d, int& n) {
  const double e = sqnorm(load3(x, node) - p);
  auto before = [&](int k) { return e < d[k] || (e == d[k] && node < out[k]); };
  if (n == 3 && !before(2)) return;
  int j = n < 3 ? n++ : 2;
  while (j > 0 && before(j - 1)) out[j] = out[j - 1], d[j] = d[j - 1], --j;
  out[j] = node, d[j] = e;
}

HARNESS_HD inline void set_line(Push& P, int h, V3 n) {
  P.count = 1, P.hosts[0] = h, P.w[0] = 1.0, P.n[0] = n.x, P.n[1] = n.y, P.n[2] = n.z;
}

// The voxel detector's contact (the guest node's voxel is occupied) with the line or plane rule.
HARNESS_HD inline void voxel_push(const DirView& D, const double* x, int g, int cell, const int ijk[3], Push& P) {
  const GridState& G = *D.G;
  const V3 p = load3(x, g), center{G.c[0], G.c[1], G.c[2]};
  if (D.eliminator == kElimLine) {
    int best = -1;
    double e = 0.0;
    int cb, ce;
    cell_range(D, cell, cb, ce);
    for (int s = cb; s < ce; ++s) {
      const int node = D.sorted[s];
      const double d = sqnorm(load3(x, node) - p);
      if (best < 0 || d < e || (d == e && node < best)) best = node, e = d;
    }
    V3 n = unit_or_zero(p - load3(x, best));
    if (sqnorm(n) == 0.0) n = line_direction(D, x, g, best, center);
    set_line(P, best, n);
    if (D.force_rule == kForcePenalty) {
      const V3 hint = outward_hint(D, x, best, center);
      P.n[0] = hint.x, P.n[1] = hint.y, P.n[2] = hint.z;
      P.mag = dot(load3(x, best) - p, hint);  // the depth, made a force below
    }
    return;
  }
  int h[3] = {-1, -1, -1}, k = 0;
  double d[3] = {0, 0, 0};
  for_block_nodes(D, ijk, [&](int node) { nearest3_offer(x, p, node, h, d, k); });
  if (k == 3) {
    const V3 a = load3(x, h[0]), b = load3(x, h[1]), q = load3(x, h[2]);
    const V3 centroid = (a + b + q) / 3.0;
    const V3 hint = outward_hint(D, x, h[0], center) + outward_hint(D, x, h[1], center) + outward_hint(D, x, h[2], center);
    V3 n;
    if (plane_normal(a, b, q, hint, centroid - center, n)) {
      P.count = 3;
      for (int j = 0; j < 3; ++j) P.hosts[j] = h[j], P.w[j] = 1.0 / 3.0;
      P.n[0] = n.x, P.n[1] = n.y, P.n[2] = n.z;
      if (D.force_rule == kForcePenalty) {
        P.mag = dot(a - p, n);
        barycentric(closest_on_triangle(p, a, b, q), a, b, q, P.w);
      }
      return;
    }
  }
  set_line(P, h[0], line_direction(D, x, g, h[0], center));
  if (D.force_rule == kForcePenalty) {
    const V3 hint = outward_hint(D, x, h[0], center);
    P.n[0] = hint.x, P.n[1] = hint.y, P.n[2] = hint.z;
    P.mag = dot(load3(x, h[0]) - p, hint);
  }
}

}  // namespace harness::dev

#include "core/device/exact_kernels.hpp"  // voxel_exact's narrow phase

namespace harness::dev {

// The voxel of guest node j if it may be a contact (-1: none), with its indices.
HARNESS_HD inline int guest_cell(const DirView& D, const double* x, int j, int ijk[3]) {
  const V3 p = load3(x, D.guest_begin + j);
  const int cell = cell_of(*D.G, p, ijk);
  if (cell < 0) return -1;
  if (D.detector == kDetVoxel) return occupied(D, cell) ? cell : -1;
  return in_host_box(*D.G, p) ? cell : -1;
}
// The force rule on a found push, its direction inverted for the broken method, and the count.
HARNESS_HD inline void finish_push(const DirView& D, Push& P) {
  if (D.force_rule == kForcePenalty) {  // penalty_contact_forces: k max(0, depth) along the normal
    const double f = D.stiffness * dmax(0.0, P.mag);
    const bool nz = (P.n[0] * P.n[0] + P.n[1] * P.n[1]) + P.n[2] * P.n[2] > 0.0;
    P.mag = isfinite(f) && nz ? f : 0.0;
  } else {
    P.mag = D.force;
  }
  if (D.invert)
    for (int k = 0; k < 3; ++k) P.n[k] = -P.n[k];
  atomic_add(D.contacts, 1);
}

// Guest node j's push, its force magnitude (the force rule), and the contact count.
HARNESS_HD inline void guest_push(const DirView& D, const double* x, int j) {
  Push& P = D.push[j];
  P.count = 0, P.mag = 0.0;
  int ijk[3];
  const int cell = guest_cell(D, x, j, ijk);
  if (cell < 0) return;
  const int g = D.guest_begin + j;
  if (D.detector == kDetVoxel) voxel_push(D, x, g, cell, ijk, P);
  else if (!voxel_exact_push(D, x, g, ijk, P)) return;
  finish_push(D, P);
}

// ---- The reactions: each host node's list of (push, k), sorted by push.
HARNESS_HD inline void react_count(const DirView& D, int j) {
  const Push& P = D.push[j];
  for (int k = 0; k < P.count; ++k) atomic_add(D.rc + (P.hosts[k] - D.host_begin), 1);
}
HARNESS_HD inline void react_place(const DirView& D, int j) {
  const Push& P = D.push[j];
  for (int k = 0; k < P.count; ++k) {
    const int hl = P.hosts[k] - D.host_begin;
    const int s = D.rstart[hl] + atomic_add(D.rc + hl, -1) - 1;
    D.rrec[s] = 4 * j + k;
    D.rslot[4 * j + k] = s;
  }
}
HARNESS_HD inline void react_sort(const DirView& D, int j) {
  const Push& P = D.push[j];
  for (int k = 0; k < P.count; ++k) {
    const int hl = P.hosts[k] - D.host_begin;
    if (D.rslot[4 * j + k] == D.rstart[hl]) sort_range(D.rrec, D.rstart[hl], D.rstart[hl + 1]);
  }
}

HARNESS_HD inline void add_guest(const DirView& D, double* f, int i) {
  const Push& P = D.push[i - D.guest_begin];
  if (P.count == 0) return;
  for (int k = 0; k < 3; ++k) f[3 * i + k] += P.mag * P.n[k];
}
HARNESS_HD inline void add_reactions(const DirView& D, double* f, int i) {
  const int hl = i - D.host_begin;
  for (int s = D.rstart[hl]; s < D.rstart[hl + 1]; ++s) {
    const Push& P = D.push[D.rrec[s] / 4];
    const double w = P.w[D.rrec[s] % 4];
    for (int k = 0; k < 3; ++k) f[3 * i + k] -= w * (P.mag * P.n[k]);
  }
}
// Node i of the pair's bodies: its forces in Collision's order (this way's pushes, then the other
// way's), each node's additions in push order. rev null: one-sided.
HARNESS_HD inline void apply_pair(const DirView& fwd, const DirView* rev, double* f, int i) {
  if (i >= fwd.host_begin && i < fwd.host_begin + fwd.host_size) {
    add_reactions(fwd, f, i);
    if (rev) add_guest(*rev, f, i);
  } else {
    add_guest(fwd, f, i);
    if (rev) add_reactions(*rev, f, i);
  }
}

// The bounding box fold (points_bounds: NaN ignored; min and max exact in any order).
HARNESS_HD inline void bounds_fold(const double* x, int i, double lohi[6]) {
  for (int a = 0; a < 3; ++a) {
    const double p = x[3 * i + a];
    lohi[a] = p < lohi[a] ? p : lohi[a];
    lohi[3 + a] = lohi[3 + a] < p ? p : lohi[3 + a];
  }
}
HARNESS_HD inline void bounds_merge(double lohi[6], const double* other) {
  for (int a = 0; a < 3; ++a) {
    lohi[a] = other[a] < lohi[a] ? other[a] : lohi[a];
    lohi[3 + a] = lohi[3 + a] < other[3 + a] ? other[3 + a] : lohi[3 + a];
  }
}

}  // namespace harness::dev
