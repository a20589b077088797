#include "core/energy.hpp"

#include <algorithm>
#include <cmath>

namespace harness {

double EnergyLedger::balance_error() const {
  const double lhs = staggered - staggered0;
  const double rhs = work_external - dissipated + work_contact;
  const double scale = std::max({std::fabs(initial), std::fabs(staggered0), std::fabs(staggered), std::fabs(work_external),
                                 std::fabs(dissipated), std::fabs(work_contact)});
  return scale > 0.0 ? (lhs - rhs) / scale : 0.0;
}

}  // namespace harness
