#include "core/collision/intersection_volume.hpp"

#include <algorithm>
#include <cmath>

namespace harness {

namespace {

struct Box {
  Vec3 lo = Vec3::Constant(1e300), hi = Vec3::Constant(-1e300);
};

Box surface_box(const Body& b, const Points& x) {
  Box box;
  for (int s = 0; s < b.n_surface; ++s) {
    box.lo = box.lo.cwiseMin(x[b.surface_node(s)]);
    box.hi = box.hi.cwiseMax(x[b.surface_node(s)]);
  }
  return box;
}

// One crossing of a pixel's ray with a triangle.
struct Fragment {
  double depth;
  int body;      // 0: a, 1: b
  int enters;    // +1 the ray enters the body here, -1 it leaves
  int tri;       // face index in its body
  double w[3];   // barycentric weights of the face's vertices at the pixel centre
};

// The top-left rule for a counter-clockwise triangle in (u, v): an edge (p -> q) owns the centres
// that lie exactly on it when it is a top edge (horizontal, going left) or a left edge (going down).
bool owns(double du, double dv) { return (dv == 0.0 && du < 0.0) || dv < 0.0; }

class Image {
 public:
  Image(int k, const Box& box, double pixel) : k_(k), u_((k + 1) % 3), v_((k + 2) % 3), h_(pixel) {
    lo_u_ = box.lo[u_], lo_v_ = box.lo[v_];
    nu_ = std::max(1, static_cast<int>(std::ceil((box.hi[u_] - lo_u_) / h_)));
    nv_ = std::max(1, static_cast<int>(std::ceil((box.hi[v_] - lo_v_) / h_)));
  }

  void rasterise(const Body& body, const Points& x, int which) {
    for (std::size_t t = 0; t < body.faces.size(); ++t) {
      const Tri& f = body.faces[t];
      Vec3 p[3] = {x[body.surface_node(f[0])], x[body.surface_node(f[1])], x[body.surface_node(f[2])]};
      int idx[3] = {0, 1, 2};
      // signed area in (u, v): > 0 counter-clockwise, i.e. the outward normal has n_k > 0 (the
      // ray along +k leaves the body there)
      const double area = (p[1][u_] - p[0][u_]) * (p[2][v_] - p[0][v_]) - (p[1][v_] - p[0][v_]) * (p[2][u_] - p[0][u_]);
      if (area == 0.0) continue;  // edge-on: no ray crosses it
      const int enters = area > 0.0 ? -1 : +1;
      if (area < 0.0) std::swap(idx[1], idx[2]);  // counter-clockwise from here on
      const Vec3& a = p[idx[0]];
      const Vec3& b = p[idx[1]];
      const Vec3& c = p[idx[2]];
      const double umin = std::min({a[u_], b[u_], c[u_]}), umax = std::max({a[u_], b[u_], c[u_]});
      const double vmin = std::min({a[v_], b[v_], c[v_]}), vmax = std::max({a[v_], b[v_], c[v_]});
      // the centres the box may hold, one more each way: the edge functions decide (a centre on
      // the box's side must reach the triangle that owns it whatever the rounding of the division)
      const int i0 = std::max(0, static_cast<int>(std::ceil((umin - lo_u_) / h_ - 0.5)) - 1);
      const int i1 = std::min(nu_ - 1, static_cast<int>(std::floor((umax - lo_u_) / h_ - 0.5)) + 1);
      const int j0 = std::max(0, static_cast<int>(std::ceil((vmin - lo_v_) / h_ - 0.5)) - 1);
      const int j1 = std::min(nv_ - 1, static_cast<int>(std::floor((vmax - lo_v_) / h_ - 0.5)) + 1);
      const double A = std::abs(area);
      for (int i = i0; i <= i1; ++i) {
        const double cu = lo_u_ + (i + 0.5) * h_;
        for (int j = j0; j <= j1; ++j) {
          const double cv = lo_v_ + (j + 0.5) * h_;
          double e[3];
          const Vec3* q[3] = {&a, &b, &c};
          const int id[3] = {f[idx[0]], f[idx[1]], f[idx[2]]};
          bool in = true;
          for (int m = 0; m < 3 && in; ++m) {
            // An edge's function is computed from its lower-numbered vertex whichever triangle asks:
            // the two triangles that share it get exactly opposite values, so a centre on it is
            // never lost nor counted twice through rounding.
            const int n = (m + 1) % 3;
            const bool forward = id[m] < id[n];
            const Vec3& s = forward ? *q[m] : *q[n];
            const Vec3& t2 = forward ? *q[n] : *q[m];
            const double du = t2[u_] - s[u_], dv = t2[v_] - s[v_];
            const double raw = du * (cv - s[v_]) - dv * (cu - s[u_]);
            e[m] = forward ? raw : -raw;
            in = e[m] > 0.0 || (e[m] == 0.0 && (forward ? owns(du, dv) : owns(-du, -dv)));
          }
          if (!in) continue;
          // e[m] is twice the area opposite the vertex after edge m: weights of c, a, b
          Fragment fr;
          double wq[3] = {e[1] / A, e[2] / A, e[0] / A};  // weights of a, b, c
          fr.depth = wq[0] * a[k_] + wq[1] * b[k_] + wq[2] * c[k_];
          fr.body = which;
          fr.enters = enters;
          fr.tri = static_cast<int>(t);
          for (int m = 0; m < 3; ++m) fr.w[idx[m]] = wq[m];
          frags_.push_back(fr);
          pixel_of_.push_back(i * nv_ + j);
        }
      }
    }
  }

  // V_k, and its gradient into ga, gb (component k). The fragments are grouped by pixel (a
  // counting sort: one flat array, no list per pixel), then each pixel's sorted by depth.
  double integrate(const Body& A, const Body& B, std::vector<Vec3>& ga, std::vector<Vec3>& gb) {
    const double px = h_ * h_;
    double length = 0.0;
    const std::size_t P = static_cast<std::size_t>(nu_) * nv_;
    std::vector<int> start_of(P + 1, 0);
    for (int p : pixel_of_) ++start_of[static_cast<std::size_t>(p) + 1];
    for (std::size_t p = 0; p < P; ++p) start_of[p + 1] += start_of[p];
    std::vector<Fragment> by_pixel(frags_.size());
    {
      std::vector<int> at(start_of.begin(), start_of.end() - 1);
      for (std::size_t n = 0; n < frags_.size(); ++n) by_pixel[static_cast<std::size_t>(at[pixel_of_[n]]++)] = frags_[n];
    }
    for (std::size_t p = 0; p < P; ++p) {
      Fragment* first = by_pixel.data() + start_of[p];
      Fragment* last = by_pixel.data() + start_of[p + 1];
      if (last - first < 4) continue;  // a shared interval needs both bodies crossed twice
      std::sort(first, last, [](const Fragment& a, const Fragment& b) {
        return a.depth < b.depth || (a.depth == b.depth && a.enters < b.enters);  // leave before enter
      });
      int wind[2] = {0, 0};
      bool shared = false;
      double start = 0.0;
      for (const Fragment* it = first; it != last; ++it) {
        const Fragment& f = *it;
        wind[f.body] += f.enters;
        const bool now = wind[0] > 0 && wind[1] > 0;
        if (now == shared) continue;
        const Tri& tri = (f.body == 0 ? A : B).faces[f.tri];
        std::vector<Vec3>& g = f.body == 0 ? ga : gb;
        const double sign = now ? -1.0 : +1.0;  // opens: deeper shortens it; closes: deeper lengthens it
        for (int m = 0; m < 3; ++m) g[tri[m]][k_] += sign * px * f.w[m];
        if (now) start = f.depth;
        else length += f.depth - start;
        shared = now;
      }
    }
    return px * length;
  }

  long long pixels() const { return static_cast<long long>(nu_) * nv_; }
  long long fragments() const { return static_cast<long long>(frags_.size()); }

 private:
  int k_, u_, v_;
  double h_;
  double lo_u_ = 0.0, lo_v_ = 0.0;
  int nu_ = 1, nv_ = 1;
  std::vector<Fragment> frags_;  // in rasterisation order
  std::vector<int> pixel_of_;    // each fragment's pixel (i * nv + j)
};

}  // namespace

IntersectionVolume intersection_volume(const World& w, const Points& x, int a, int b, double pixel) {
  IntersectionVolume out;
  const Body& A = w.bodies[a];
  const Body& B = w.bodies[b];
  out.grad_a.assign(A.n_surface, Vec3::Zero());
  out.grad_b.assign(B.n_surface, Vec3::Zero());
  if (A.faces.empty() || B.faces.empty() || !(pixel > 0.0)) return out;
  const Box ba = surface_box(A, x), bb = surface_box(B, x);
  Box box;
  box.lo = ba.lo.cwiseMax(bb.lo);
  box.hi = ba.hi.cwiseMin(bb.hi);
  if ((box.lo.array() >= box.hi.array()).any()) return out;
  for (int k = 0; k < 3; ++k) {
    Image img(k, box, pixel);
    img.rasterise(A, x, 0);
    img.rasterise(B, x, 1);
    out.per_axis[k] = img.integrate(A, B, out.grad_a, out.grad_b);
    out.pixels += img.pixels();
    out.fragments += img.fragments();
  }
  out.volume = (out.per_axis[0] + out.per_axis[1] + out.per_axis[2]) / 3.0;
  return out;
}

}  // namespace harness
