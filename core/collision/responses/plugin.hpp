// A contact response from a shared library built outside the harness (contacts.N.response =
// "plugin:PATH"; its interface: core/plugin/harness/response.h; docs/plugins.md). Loaded once per
// pair when the simulation is made, it becomes the pair's OwnResponse (collision.hpp), as a Python
// callable does.
#pragma once

#include "core/collision/collision.hpp"
#include "core/scene/scene.hpp"

namespace harness {

// The pair's plug-in, loaded (dlopen) and made with its parameters. Throws InputError naming
// `scene.file: contacts.N.response` (a file that is missing or not a shared library, a missing
// symbol, another interface version) or `...response_parameters` (the plug-in refused them).
// The library stays loaded while a copy of the response lives.
OwnResponse load_response_plugin(const Scene& scene, const ContactPairSpec& pair);

}  // namespace harness
