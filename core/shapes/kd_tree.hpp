// A static k-d tree over a subset of points (implicit layout: the median of each range is its
// node), for k-nearest and radius queries: the volume fill's surface-to-interior springs.
#pragma once

#include "core/shapes/internal.hpp"

#include <algorithm>
#include <utility>
#include <vector>

namespace harness::shapes {

class KdTree {
 public:
  KdTree(const Points& pts, std::vector<int> ids) : pts_(pts), ids_(std::move(ids)) {
    axis_.assign(ids_.size(), 0);
    build(0, isize(ids_));
  }
  bool empty() const { return ids_.empty(); }
  // The k nearest points to q, nearest first.
  std::vector<int> nearest(const Vec3& q, int k) const {
    std::vector<std::pair<double, int>> best;  // sorted by distance, at most k
    knn(0, isize(ids_), q, k, best);
    std::vector<int> out;
    for (const auto& b : best) out.push_back(b.second);
    return out;
  }
  std::vector<int> within(const Vec3& q, double r) const {
    std::vector<int> out;
    radius(0, isize(ids_), q, r * r, out);
    return out;
  }

 private:
  void build(int lo, int hi) {
    if (hi - lo <= 1) return;
    Vec3 mn = pts_[ids_[lo]], mx = mn;
    for (int i = lo; i < hi; ++i) {
      mn = mn.cwiseMin(pts_[ids_[i]]);
      mx = mx.cwiseMax(pts_[ids_[i]]);
    }
    Eigen::Index ax = 0;
    (mx - mn).maxCoeff(&ax);
    const int axis = static_cast<int>(ax);
    const int mid = (lo + hi) / 2;
    std::nth_element(ids_.begin() + lo, ids_.begin() + mid, ids_.begin() + hi,
                     [&](int a, int b) { return pts_[a][axis] < pts_[b][axis]; });
    axis_[mid] = axis;
    build(lo, mid);
    build(mid + 1, hi);
  }
  void knn(int lo, int hi, const Vec3& q, int k, std::vector<std::pair<double, int>>& best) const {
    if (lo >= hi) return;
    const int mid = (lo + hi) / 2;
    const int id = ids_[mid];
    const double d2 = (pts_[id] - q).squaredNorm();
    if (isize(best) < k || (!best.empty() && d2 < best.back().first)) {  // (k <= 0: nothing)
      best.insert(std::upper_bound(best.begin(), best.end(), std::make_pair(d2, id)),
                  std::make_pair(d2, id));
      if (isize(best) > k) best.pop_back();
    }
    const double diff = q[axis_[mid]] - pts_[id][axis_[mid]];
    const bool left_first = diff < 0.0;
    knn(left_first ? lo : mid + 1, left_first ? mid : hi, q, k, best);
    if (isize(best) < k || (!best.empty() && diff * diff < best.back().first))
      knn(left_first ? mid + 1 : lo, left_first ? hi : mid, q, k, best);
  }
  void radius(int lo, int hi, const Vec3& q, double r2, std::vector<int>& out) const {
    if (lo >= hi) return;
    const int mid = (lo + hi) / 2;
    const int id = ids_[mid];
    if ((pts_[id] - q).squaredNorm() <= r2) out.push_back(id);
    const double diff = q[axis_[mid]] - pts_[id][axis_[mid]];
    if (diff <= 0.0 || diff * diff <= r2) radius(lo, mid, q, r2, out);
    if (diff >= 0.0 || diff * diff <= r2) radius(mid + 1, hi, q, r2, out);
  }

  const Points& pts_;
  std::vector<int> ids_;
  std::vector<int> axis_;
};

}  // namespace harness::shapes
