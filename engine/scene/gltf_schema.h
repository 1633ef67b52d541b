#pragma once
// Structural check of a glTF 2.0 JSON document against the core schema's property types (tinygltf
// silently ignores many wrongly typed values). Extensions and extras are only checked to be objects
// where the schema says so.
#include <filesystem>

#include <nlohmann/json_fwd.hpp>

namespace envshadow {

// Throws InputError "<file>: <json path>: <reason>" at the first property of the wrong type, a
// missing required property, or a fixed-size array of the wrong length.
void check_gltf_json(const std::filesystem::path& file, const nlohmann::json& document);

}  // namespace envshadow
