// Warnings a user needs before trusting a run, found once at the start (on the built scene):
//   - an explicit contacts.N.voxel_size that was rounded down to a power of two (from, to);
//   - the paper's voxel model (detector voxel) with a voxel finer than the host's node spacing
//     (mean surface edge): a voxel inside the host can hold none of its nodes, so guest nodes
//     there go undetected;
//   - node spacing that lets one body pass between the other's nodes (tunnelling expected): the
//     guest's mean surface edge longer than the voxel (the voxel model reports a guest node only
//     when a host node shares its voxel), or either body's mean surface edge longer than the
//     other body's thinnest rest extent.
// Printed as "harness: warning: KEY: message"; with --strict each is an error (exit 2) before
// anything is written. Tunnelled nodes found at the end are reported by the run itself.
#pragma once

#include "core/simulation.hpp"

#include <string>
#include <vector>

namespace harness {

struct Warning {
  std::string key;      // scene key path, e.g. "contacts.0.voxel_size"
  std::string message;
};

std::vector<Warning> start_warnings(const Simulation& sim);

}  // namespace harness
