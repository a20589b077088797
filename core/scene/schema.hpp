// The scene format's JSON Schema (draft 2020-12), generated from the key table (keys.hpp): what
// `harness schema` prints; experiments/scene.schema.json is its output (`harness schema >
// experiments/scene.schema.json`), and tests check that the two are equal.
#pragma once

#include <nlohmann/json.hpp>

#include <string>

namespace harness {

// Its members in the order written (description, type, properties, required, ...).
nlohmann::ordered_json scene_schema();
// As `harness schema` prints it: two-space indentation, a value on one line where it fits.
std::string scene_schema_text();

}  // namespace harness
