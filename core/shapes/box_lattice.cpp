// The box lattice (make_box): a volumetric lattice of (nx+1)(ny+1)(nz+1) nodes with structural,
// face-shear and body-diagonal springs whose constants make the cell isotropic (elastic_map.hpp).
#include "core/shapes/internal.hpp"

#include <string>
#include <utility>

namespace harness {

using shapes::require;
using shapes::require_finite;

namespace {

// The box lattice of make_box: nodes, springs, surface and lumped volumes, one step each.
struct BoxLattice {
  Vec3 min, max;
  int nx, ny, nz;
  int dims[3];
  std::vector<int> id;  // lattice index -> node index (boundary nodes first)
  ShapeModel out;

  CellSprings cell{};  // per unit E (elastic_map.hpp)

  BoxLattice(const Vec3& lo, const Vec3& hi, const Vec3i& cells)
      : min(lo), max(hi), nx(cells.x()), ny(cells.y()), nz(cells.z()), dims{nx, ny, nz} {
    cell = isotropic_cell((hi - lo).cwiseQuotient(cells.cast<double>()), &out.kappa_anisotropy);
  }
  // Cells of index c - 1 and c along an axis of n cells that exist (1 or 2).
  static int around(int c, int n) { return (c > 0 ? 1 : 0) + (c < n ? 1 : 0); }
  void spring(int a, int b, double kappa) {
    out.springs.push_back({a, b});
    out.spring_kappa.push_back(kappa);
    out.spring_role.push_back(SpringRole::volume);
  }
  int lid(int i, int j, int k) const { return (k * (ny + 1) + j) * (nx + 1) + i; }
  bool boundary(int i, int j, int k) const { return i == 0 || j == 0 || k == 0 || i == nx || j == ny || k == nz; }
  int at(int i, int j, int k) const { return id[lid(i, j, k)]; }
  int at(const int c[3]) const { return at(c[0], c[1], c[2]); }

  // Boundary nodes first, then interior, each in lattice order.
  void place_nodes() {
    const Vec3 step = (max - min).cwiseQuotient(Vec3(nx, ny, nz));
    const int n = (nx + 1) * (ny + 1) * (nz + 1);
    id.resize(static_cast<std::size_t>(n));
    out.nodes.resize(static_cast<std::size_t>(n));
    int next = 0;
    for (int pass = 0; pass < 2; ++pass)
      for (int k = 0; k <= nz; ++k)
        for (int j = 0; j <= ny; ++j)
          for (int i = 0; i <= nx; ++i) {
            if (boundary(i, j, k) != (pass == 0)) continue;
            id[lid(i, j, k)] = next;
            // The last layer is placed at max exactly, not min + n * step.
            out.nodes[next] = Vec3(i == nx ? max.x() : min.x() + i * step.x(), j == ny ? max.y() : min.y() + j * step.y(),
                                   k == nz ? max.z() : min.z() + k * step.z());
            if (pass == 0) ++out.n_surface;
            ++next;
          }
  }

  // Springs, each enumerated once: structural along +axis from every node, both diagonals of
  // every lattice face, the 4 diagonals of every cell.
  void add_springs() {
    for (int k = 0; k <= nz; ++k)
      for (int j = 0; j <= ny; ++j)
        for (int i = 0; i <= nx; ++i) {
          const int p[3] = {i, j, k};
          for (int a = 0; a < 3; ++a) {  // edge along a: a quarter from each cell around it
            int q[3] = {i, j, k};
            if (p[a] >= dims[a]) continue;
            ++q[a];
            const int u = (a + 1) % 3, w = (a + 2) % 3;
            spring(at(p), at(q), around(p[u], dims[u]) * around(p[w], dims[w]) * cell.edge[a] / 4.0);
          }
          for (int a = 0; a < 3; ++a) {  // face of the lattice spanned by axes u, w (normal a)
            const int u = (a + 1) % 3, w = (a + 2) % 3;
            if (p[u] >= dims[u] || p[w] >= dims[w]) continue;
            int c11[3] = {i, j, k}, c10[3] = {i, j, k}, c01[3] = {i, j, k};
            ++c11[u], ++c11[w], ++c10[u], ++c01[w];
            const double kappa = around(p[a], dims[a]) * cell.face[a] / 2.0;  // half from each cell
            spring(at(p), at(c11), kappa);
            spring(at(c10), at(c01), kappa);
          }
          if (i < nx && j < ny && k < nz) {
            spring(at(i, j, k), at(i + 1, j + 1, k + 1), cell.body);
            spring(at(i + 1, j, k), at(i, j + 1, k + 1), cell.body);
            spring(at(i, j + 1, k), at(i + 1, j, k + 1), cell.body);
            spring(at(i, j, k + 1), at(i + 1, j + 1, k), cell.body);
          }
        }
  }

  // Surface: both triangles of each boundary quad. On the face of normal +a (axes a, u, w
  // right-handed) the quad (p,q) -> (p+1,q) -> (p+1,q+1) -> (p,q+1) is counter-clockwise.
  // alternating: quads of odd (p + q) split along the other diagonal, (p+1,q) - (p,q+1).
  void add_surface(bool alternating) {
    for (int a = 0; a < 3; ++a) {
      const int u = (a + 1) % 3, w = (a + 2) % 3;
      for (int side = 0; side < 2; ++side)
        for (int q = 0; q < dims[w]; ++q)
          for (int pp = 0; pp < dims[u]; ++pp) {
            auto node = [&](int du, int dw) {
              int c[3];
              c[a] = side == 0 ? 0 : dims[a];
              c[u] = pp + du;
              c[w] = q + dw;
              return at(c);
            };
            const int n00 = node(0, 0), n10 = node(1, 0), n11 = node(1, 1), n01 = node(0, 1);
            if (alternating && (pp + q) % 2 == 1) {
              if (side == 1) {
                out.faces.push_back({n00, n10, n01});
                out.faces.push_back({n10, n11, n01});
              } else {
                out.faces.push_back({n00, n01, n10});
                out.faces.push_back({n10, n01, n11});
              }
            } else if (side == 1) {
              out.faces.push_back({n00, n10, n11});
              out.faces.push_back({n00, n11, n01});
            } else {
              out.faces.push_back({n00, n11, n10});
              out.faces.push_back({n00, n01, n11});
            }
          }
    }
  }

  // An eighth of every cell's volume to each of its corners.
  void add_volumes() {
    out.volume = (max - min).prod();
    out.node_volume.assign(out.nodes.size(), 0.0);
    const double eighth = out.volume / (static_cast<double>(nx) * ny * nz) / 8.0;
    for (int k = 0; k < nz; ++k)
      for (int j = 0; j < ny; ++j)
        for (int i = 0; i < nx; ++i)
          for (int c = 0; c < 8; ++c) out.node_volume[at(i + (c & 1), j + ((c >> 1) & 1), k + ((c >> 2) & 1))] += eighth;
  }
  // Every cell's 8 corners (Cell's corner order), for the bulk effect.
  void add_cells() {
    out.cells.reserve(static_cast<std::size_t>(nx) * ny * nz);
    for (int k = 0; k < nz; ++k)
      for (int j = 0; j < ny; ++j)
        for (int i = 0; i < nx; ++i) {
          Cell corners;
          for (int c = 0; c < 8; ++c) corners[c] = at(i + (c & 1), j + ((c >> 1) & 1), k + ((c >> 2) & 1));
          out.cells.push_back(corners);
        }
  }
};

}  // namespace

ShapeModel make_box(const Vec3& min, const Vec3& max, const Vec3i& cells, bool alternating) {
  require_finite(min, "box: min");
  require_finite(max, "box: max");
  require((max - min).minCoeff() > 0.0, "box: max must exceed min along every axis");
  require(cells.minCoeff() >= 1, "box: cells must be >= 1 along every axis");
  require((static_cast<long long>(cells.x()) + 1) * (static_cast<long long>(cells.y()) + 1) *
                  (static_cast<long long>(cells.z()) + 1) <=
              kMaxBoxNodes,
          "box: too many nodes (limit " + std::to_string(kMaxBoxNodes) + ")");
  BoxLattice box(min, max, cells);
  box.place_nodes();
  box.add_springs();
  box.add_surface(alternating);
  box.add_volumes();
  box.add_cells();
  return std::move(box.out);
}

}  // namespace harness
