// DevicePlan: a built Simulation flattened into the arrays the kernel bodies read (kernels.hpp,
// contact_kernels.hpp), in host memory; an executor uses them where they are (the CPU) or copies
// them to the device (CUDA). Views point into a plan's (or a device copy's) arrays.
#pragma once

#include "core/device/plan_data.hpp"
#include "core/simulation.hpp"

#include <vector>

namespace harness::dev {

// The plan of a built Simulation; throws InputError (check_device_support) for what a device
// cannot step.
DevicePlan make_plan(const Simulation& sim);

// A grid's voxel capacity: room for the host to grow (a rebuild) to twice its extent per axis.
long long grid_capacity(const GridState& g);

}  // namespace harness::dev
