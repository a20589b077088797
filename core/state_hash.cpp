#include "core/state_hash.hpp"

#include <cstdint>
#include <cstdio>
#include <cstring>

namespace harness {

std::string state_hash(const World& w) {
  std::uint64_t h = 1469598103934665603ull;
  auto feed = [&h](const Points& p) {
    for (const Vec3& q : p)
      for (int a = 0; a < 3; ++a) {
        unsigned char b[sizeof(double)];
        const double d = q[a];
        std::memcpy(b, &d, sizeof d);
        for (unsigned char c : b) h = (h ^ c) * 1099511628211ull;
      }
  };
  feed(w.x);
  feed(w.v);
  char buf[17];
  std::snprintf(buf, sizeof buf, "%016llx", static_cast<unsigned long long>(h));
  return buf;
}

}  // namespace harness
