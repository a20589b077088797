// The SIMD kernels of core, each written once (kernels.inl) and compiled once per instruction
// set (kernels_<isa>.cpp); simd::kernels() hands out the set of the active level (core/cpu.hpp).
//
// How one body becomes four. kernels.inl holds each kernel as a template over a "lane" type: W
// doubles (or W 32-bit integers) and a handful of operations on them (load, set1, loads and
// gathers of the x, y, z of W points, + - * /, sqrt, floor, comparisons to a mask, movemask,
// select, min/max, store, conversion to int), defined in lanes.inl with the intrinsics of the
// translation unit's instruction set: W = 1 (plain C++), 4 (AVX, AVX2) or 8 (AVX-512). A
// kernel runs its loop W elements at a time and the remainder with the W = 1 type, in the same
// translation unit.
//
// Why separate translation units with per-ISA -m flags (CMakeLists.txt) rather than `#pragma
// GCC target` regions: the whole body, every helper inlined into it, is compiled for that
// instruction set, and the scalar tail too (no SSE/AVX transitions). The hazard of -m flags is
// the one-definition rule: an inline or template function that two translation units
// instantiate is emitted in both, and the linker keeps one copy, possibly the AVX-512 one, for
// every caller. So a kernel translation unit defines everything in an unnamed namespace inside
// harness::simd::<isa> (internal linkage: its one external name is its table of kernels),
// includes only <cstdint>, <cstddef>, the intrinsics headers (intrinsics are never emitted out
// of line), this header and core/springs.hpp, and calls nothing from them but templates
// instantiated with its own lane types (so internal too): no Eigen, no std algorithms, no
// double-typed inline functions of a shared header.
//
// Why the bits are identical at every level (and to the serial scatter and voxel_of): every
// lane does exactly the scalar operations, in the scalar order, with IEEE double arithmetic
// (correctly rounded +, -, *, /, sqrt; the build has -ffp-contract=off, and no level enables
// FMA), and sums follow one order at every level (SpringSumRun). The voxel indices are integers computed
// exactly in double; min and max are exact. tests/core/test_cpu.cpp checks every level.
#pragma once

#include <cstddef>
#include <cstdint>

namespace harness {

enum class Isa;

namespace simd {

// A voxel grid as the indexer kernel takes it (VoxelIndexer): per axis t = (x - c) * inv, the
// point is inside when lo <= t < hi on every axis, its voxel sum over the axes of (floor(t) -
// lo) * (1, dx, dxy). lo and hi are integers; the voxel count must fit an int.
struct VoxelGrid {
  double c[3];
  double inv;
  double lo[3], hi[3];
  double dx, dxy;  // dims.x, dims.x dims.y
};

// The force pass of core/spring_forces.hpp (SpringGather), in two halves. Every node lists its
// half-edges in two CSR lists, in spring order: "upper" (the other end has a higher index; a
// spring's first end for a spring on one node) and "lower" (the other end lower). A spring is
// evaluated once, at its upper half-edge; each node then sums its half-edges.
//
// SpringEvalRun: the upper half-edges [h0, h1) of one body (one law, one dashpot coefficient),
// independent of each other: for half-edge h from node i = self[h] to j = other[h],
//   d = x_j - x_i, l2 = (dx dx + dy dy) + dz dz, l = sqrt(l2), r = 1 / l, c = the law's
//   tension over length (springs.hpp), s = damping (u.d) (r r) with u = v_j - v_i and
//   u.d = (ux dx + uy dy) + uz dz, t = the tangent stiffness over l2;
//   F[h] = c d (springs), G[h] = s d (dashpots), both 0 d (+-0) for a spring of zero length
//   (l2 <= 0, NaN excluded: it propagates); R[h] = 2 t ((|dx| + |dy|) + |dz|) |d_a| (rows)
//   where l2 > 0, else 0; e[h] = the spring's energy. The force on node j is -F, -G exactly (d
//   there is exactly -d); its rows R. F, G and R hold x y z 0 at 4 h (the point form the
//   positions are loaded in: no transposition on the way out).
struct SpringEvalRun {
  const int* self;
  const int* other;
  const double* rest;    // rest length L0, m
  const double* inv_rest;  // 1 / L0 (a correctly rounded division), 1/m
  const double* stiff;   // stiffness, N/m
  const double* x;       // three doubles per node
  const double* v;
  double* F;             // per upper half-edge h (the box), x y z 0 at 4 h; null: no springs
  double* G;             // null: no dashpots
  double* R;             // null: no rows
  double* e;             // per upper half-edge; null: no energy
  double beta;           // the body's nonlinearity
  double damping;        // the body's dashpot coefficient, N s/m
  int h0, h1;
};

// SpringSumRun: the nodes [i0, i1): per node and component, four interleaved partial sums over
// its upper half-edges (+F, +G, +R, +e) then its lower ones (-F, -G, +R through lo_slot, the
// same spring's upper half-edge), half-edge q of each list into partial q % 4, in list order;
// each sum is (p0 + p1) + (p2 + p3); then f[i] = (f[i] + springs) + dashpots, rows[i] += rows.
// The boxes F, G, R hold a half-edge's x y z 0 together (four doubles at 4 h): the four-lane
// levels read an entry with one load.
struct SpringSumRun {
  const int* up_start;
  const int* lo_start;
  const int* lo_slot;
  const double* F;       // x y z 0 at 4 h; null: no springs
  const double* G;       // null: no dashpots
  const double* R;       // null: no rows
  const double* e;       // null: no energy
  double* f;             // += per node, three doubles (with F or G)
  double* f_spring;      // = the springs' sum per node, or null (audit)
  double* f_dashpot;     // = the dashpots' sum per node, or null (audit)
  double* energy;        // = the node's upper springs' energy, or null (audit)
  double* rows;          // += Gershgorin rows, three per node, or null (guard)
  int i0, i1;
};

struct Kernels {
  // out[k] = the voxel of point k (three doubles each) for k < n, -1 outside the grid.
  void (*voxel_cells)(const VoxelGrid& g, const double* xyz, std::size_t n, int* out);
  // Folds the coordinates of n points (three doubles each) into lohi = lo xyz, hi xyz, as
  // lo = (p < lo) ? p : lo and hi = (hi < p) ? p : hi per coordinate (NaN ignored; which zero
  // wins a tie between -0 and +0 depends on the order).
  void (*bounds)(const double* xyz, std::size_t n, double* lohi);
  // lo = smallest c[k] as unsigned (~0u when n = 0), hi = largest c[k] (-1 when n = 0).
  void (*cell_range)(const int* c, std::size_t n, unsigned& lo, int& hi);
  // The force pass (SpringEvalRun by the body's law, then SpringSumRun).
  void (*spring_eval_linear)(const SpringEvalRun& r);
  void (*spring_eval_cubic)(const SpringEvalRun& r);
  void (*spring_eval_exponential)(const SpringEvalRun& r);
  void (*spring_sum)(const SpringSumRun& r);
  // Sum over k < n of 1 / sqrt(a[k]) in the force pass's lanes: its one square root and one
  // division per spring and nothing else, the arithmetic no memory layout removes (harness bench).
  double (*sqrt_div)(const double* a, std::size_t n);
  // Sum over k < n of 1 / |x[other[k]] - x[self[k]]| (points of three doubles), the ends loaded as
  // the evaluation half loads them: what any force pass must do per spring (read both ends, one
  // square root, one division) and nothing more (harness bench).
  double (*pass_floor)(const double* x, const int* self, const int* other, std::size_t n);
};

// The kernels compiled for `isa` (which must be one the processor supports).
const Kernels& kernels(Isa isa);
// The kernels of the active level (harness::isa()).
const Kernels& kernels();

}  // namespace simd
}  // namespace harness
