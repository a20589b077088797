// What the three registries share (force rules: responses/force_rule.cpp; eliminators:
// responses/responses.cpp; detectors: detectors/detectors.cpp): each entry is a Def with a
// `name`, made by the maker a line HARNESS_...(stem) defines and CMake lists (harness_registry).
#pragma once

#include <algorithm>
#include <stdexcept>
#include <string>
#include <vector>

namespace harness {

// The entries in order: `first` (the scene format's default) ahead, the rest in file order.
// Throws std::logic_error (a bug) for an entry without a name or a name defined twice.
template <class Def>
std::vector<Def> registry_order(std::vector<Def> v, const std::string& first, const char* what) {
  std::stable_partition(v.begin(), v.end(), [&](const Def& d) { return first == d.name; });
  for (std::size_t i = 0; i < v.size(); ++i) {
    if (!*v[i].name) throw std::logic_error(std::string("a ") + what + " without a name");
    for (std::size_t j = 0; j < i; ++j)
      if (std::string(v[i].name) == v[j].name) throw std::logic_error(std::string(what) + " " + v[i].name + " defined twice");
  }
  return v;
}

// The entry of that name, or nullptr.
template <class Def>
const Def* find_named(const std::vector<Def>& all, const std::string& name) {
  for (const Def& d : all)
    if (name == d.name) return &d;
  return nullptr;
}

}  // namespace harness
