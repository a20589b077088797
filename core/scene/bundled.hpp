// The bundled scenes (experiments/scenes/): where they are and how a name is resolved. Shared by
// the command line (`harness run NAME`, `harness list`) and the Python module (Scene.load).
#pragma once

#include <filesystem>
#include <string>
#include <vector>

namespace harness {

// The folders searched for bundled scenes, in order: $HARNESS_SCENES, experiments/scenes next to
// the running program's build (bin/../../experiments/scenes), the source tree's.
std::vector<std::filesystem::path> scene_roots();

// A path that exists, or the name of a bundled scene ("cylinder_press", "hard/fast_impact",
// "bullet/sphere_collision": the variants Bullet can represent). Throws InputError(arg, ...) when
// neither.
std::string resolve_scene(const std::string& arg);

}  // namespace harness
