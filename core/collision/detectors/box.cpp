#include "core/collision/detectors/box.hpp"

#include <algorithm>
#include <limits>
#include <stdexcept>
#include <utility>

namespace harness {

void BoxDetector::initialize(const World& w, const ContactSpec& spec) {
  const Body& g = w.bodies[spec.guest];
  const Body& h = w.bodies[spec.host];
  if (h.n_surface <= 0) throw std::invalid_argument("box detector: the host '" + h.name + "' has no surface");
  guest_begin_ = g.begin, guest_end_ = g.end;
  host_begin_ = h.begin, host_surface_ = h.n_surface;
}

void BoxDetector::detect(const World& w, std::vector<Contact>& out) {
  out.clear();
  // The host's box: its surface vertices bound it (the surface encloses the interior nodes).
  lo_ = Vec3::Constant(std::numeric_limits<double>::infinity());
  hi_ = -lo_;
  for (int s = 0; s < host_surface_; ++s) {
    const Vec3& p = w.x[host_begin_ + s];
    lo_ = lo_.cwiseMin(p), hi_ = hi_.cwiseMax(p);
  }
  stepped_ = true;
  for (int i = guest_begin_; i < guest_end_; ++i) {
    const Vec3& p = w.x[i];
    if ((p.array() >= lo_.array()).all() && (p.array() <= hi_.array()).all()) out.push_back(Contact{i, -1});
  }
}

int BoxDetector::nearest_hosts(const World& w, const Contact& c, int k, int* out) const {
  if (k <= 0) return 0;
  const Vec3& p = w.x[c.guest];
  constexpr int kMax = 8;
  k = std::min(k, std::min(kMax, host_surface_));
  std::pair<double, int> best[kMax];
  int n = 0;
  for (int s = 0; s < host_surface_; ++s) {
    const int node = host_begin_ + s;
    const double d = (w.x[node] - p).squaredNorm();
    if (n < k) {
      best[n++] = {d, node};
      std::push_heap(best, best + n);
    } else if (d < best[0].first) {
      std::pop_heap(best, best + n);
      best[n - 1] = {d, node};
      std::push_heap(best, best + n);
    }
  }
  std::sort_heap(best, best + n);
  for (int j = 0; j < n; ++j) out[j] = best[j].second;
  return n;
}

bool BoxDetector::region(Vec3& lo, Vec3& hi) const {
  if (!stepped_) return false;
  lo = lo_, hi = hi_;
  return true;
}

HARNESS_DETECTOR(box) {
  DetectorDef d;
  d.name = "box";
  d.doc = "every guest node inside the host's bounding box: the baseline a broad phase must beat";
  d.make = [] { return std::unique_ptr<CollisionDetector>(std::make_unique<BoxDetector>()); };
  return d;
}

}  // namespace harness
