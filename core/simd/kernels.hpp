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
// FMA), and sums stay scalar, in spring order per node. The voxel indices are integers computed
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

// The spring gather of the nodes [i0, i1) of one body, all of whose springs follow one law:
// f[i] += sum over node i's half-edges h, in spring order, of c(L0[h], |d|) d, d = x[other[h]]
// - x[i], half-edges of zero length adding nothing (core/spring_forces.hpp, SpringGather).
// x and f hold three doubles per node.
struct SpringRun {
  const int* start;     // CSR over half-edges
  const int* other;     // the other end of each half-edge
  const double* rest;   // rest length of each half-edge
  const double* stiff;  // stiffness of each half-edge's spring
  const double* x;
  double* f;
  double beta;          // the body's nonlinearity (BodyLaw)
  int i0, i1;
};

// Dashpots of the nodes [i0, i1), all of whose springs have damping c: f[i] += sum over the
// half-edges of (c (v_j - v_i).d / |d|^2) d, in spring order, zero-length half-edges skipped.
struct DashpotRun {
  const int* start;
  const int* other;
  const double* x;
  const double* v;
  double* f;
  double c;
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
  void (*springs_linear)(const SpringRun& r);
  void (*springs_cubic)(const SpringRun& r);
  void (*dashpots)(const DashpotRun& r);
};

// The kernels compiled for `isa` (which must be one the processor supports).
const Kernels& kernels(Isa isa);
// The kernels of the active level (harness::isa()).
const Kernels& kernels();

}  // namespace simd
}  // namespace harness
