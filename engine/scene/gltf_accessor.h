#pragma once
// Typed, bounds-checked reading of glTF accessors for the animation, skin and morph data
// (scene/gltf_animation.h): the component type, normalized integers, count and byte stride are
// checked against what the caller expects and against the buffer view and buffer; any failure is an
// InputError "<file>: <what> (accessor N): expected VEC4 float, got SCALAR". Sparse accessors are not
// supported (an error that says so). Internal to envshadow_scene: the header names tinygltf's Model.
#include <cstddef>
#include <cstdint>
#include <filesystem>
#include <string>
#include <vector>

namespace tinygltf {
class Model;
}

namespace envshadow {

// What an accessor may hold. `type`: TINYGLTF_TYPE_* (SCALAR, VEC3, VEC4, MAT4); `floats`: float
// components; `normalized`: normalized unsigned byte / short (and signed, `signed_normalized`);
// `unsigned_ints`: unsigned byte / short integers (not normalized), read as they are.
struct AccessorSpec {
    int type = 0;
    bool floats = true;
    bool normalized = false;
    bool signed_normalized = false;
    bool unsigned_ints = false;
};

class GltfAccessors {
public:
    GltfAccessors(const std::filesystem::path& file, const tinygltf::Model& model) : file_(file), model_(model) {}

    // The accessor's values as floats, components per element in a row (count * components values);
    // normalized integers mapped to [0, 1] (or [-1, 1]). `what` names the user of the accessor.
    std::vector<float> floats(int index, const AccessorSpec& spec, const std::string& what) const;
    // Unsigned integer components (JOINTS_0).
    std::vector<std::uint32_t> uints(int index, const AccessorSpec& spec, const std::string& what) const;
    std::size_t count(int index, const std::string& what) const;

    const std::filesystem::path& file() const { return file_; }
    [[noreturn]] void fail(const std::string& reason) const;

private:
    struct Raw {
        const unsigned char* bytes = nullptr;
        std::size_t stride = 0, count = 0;
        int components = 0, component_type = 0;
        bool normalized = false;
    };
    Raw raw(int index, const AccessorSpec& spec, const std::string& what) const;

    const std::filesystem::path& file_;
    const tinygltf::Model& model_;
};

}  // namespace envshadow
