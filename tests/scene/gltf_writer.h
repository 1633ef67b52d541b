#pragma once
// Writes small glTF files (.gltf + .bin) for the scene tests, so that each test states its geometry
// and node tree in the open and the expected results can be worked out by hand.
#include <cstdint>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

#include <gtest/gtest.h>
#include <glm/vec2.hpp>
#include <glm/vec3.hpp>
#include <nlohmann/json.hpp>

#include "common/test_folder.h"
#include "core/error.h"

namespace envshadow::test {

// The real glTF 2.0 models of Debian's assimp-testmodels (scripts/install-deps.sh installs them).
inline const std::filesystem::path kAssimpModels = "/usr/share/assimp/models/glTF2";

// `load(file)` throws an InputError of one line, "<file>: <reason>", whose reason mentions `expected`.
template <class Load>
void expect_one_line_error(const std::filesystem::path& file, const std::string& expected, Load load) {
    try {
        load(file);
        ADD_FAILURE() << file << " loaded without an error";
    } catch (const InputError& e) {
        const std::string message = e.what();
        EXPECT_EQ(message.rfind(file.string() + ": ", 0), 0u) << message;
        EXPECT_NE(message.find(expected), std::string::npos) << message;
        EXPECT_EQ(message.find('\n'), std::string::npos) << message;
    }
}

// A fresh folder per test.
inline std::filesystem::path test_folder() {
    return fresh_test_folder("envshadow_scene");
}

class GltfWriter {
public:
    GltfWriter() {
        doc["asset"] = {{"version", "2.0"}};
        doc["buffers"] = nlohmann::json::array();
        doc["bufferViews"] = nlohmann::json::array();
        doc["accessors"] = nlohmann::json::array();
        doc["meshes"] = nlohmann::json::array();
        doc["nodes"] = nlohmann::json::array();
    }

    int view(const void* data, std::size_t bytes, std::size_t stride = 0) {
        while (bin.size() % 4 != 0) bin.push_back(0);
        nlohmann::json v = {{"buffer", 0}, {"byteOffset", bin.size()}, {"byteLength", bytes}};
        if (stride != 0) v["byteStride"] = stride;
        const auto* p = static_cast<const unsigned char*>(data);
        bin.insert(bin.end(), p, p + bytes);
        doc["bufferViews"].push_back(v);
        return int(doc["bufferViews"].size()) - 1;
    }

    int accessor(int view_index, int component_type, std::size_t count, const char* type) {
        doc["accessors"].push_back(
            {{"bufferView", view_index}, {"componentType", component_type}, {"count", count}, {"type", type}});
        return int(doc["accessors"].size()) - 1;
    }

    int vec3s(const std::vector<glm::vec3>& values) {
        return accessor(view(values.data(), values.size() * 12), 5126, values.size(), "VEC3");
    }

    int vec2s(const std::vector<glm::vec2>& values) {
        return accessor(view(values.data(), values.size() * 8), 5126, values.size(), "VEC2");
    }

    int indices(const std::vector<std::uint16_t>& values) {
        return accessor(view(values.data(), values.size() * 2), 5123, values.size(), "SCALAR");
    }

    // One primitive (mode 4 unless given) of a new mesh; returns the mesh index.
    int mesh(int positions, int index_accessor = -1, int normals = -1, int mode = 4) {
        nlohmann::json primitive = {{"attributes", {{"POSITION", positions}}}, {"mode", mode}};
        if (index_accessor >= 0) primitive["indices"] = index_accessor;
        if (normals >= 0) primitive["attributes"]["NORMAL"] = normals;
        doc["meshes"].push_back({{"primitives", nlohmann::json::array({primitive})}});
        return int(doc["meshes"].size()) - 1;
    }

    int node(nlohmann::json node) {
        doc["nodes"].push_back(std::move(node));
        return int(doc["nodes"].size()) - 1;
    }

    void scene(std::vector<int> roots) {
        doc["scenes"] = nlohmann::json::array({{{"nodes", roots}}});
        doc["scene"] = 0;
    }

    // Writes <folder>/<name>.gltf and, when there is data, <name>.bin; returns the .gltf path.
    std::filesystem::path write(const std::filesystem::path& folder, const std::string& name) {
        nlohmann::json out = doc;
        if (!bin.empty()) {
            out["buffers"] = nlohmann::json::array({{{"uri", name + ".bin"}, {"byteLength", bin.size()}}});
            std::ofstream(folder / (name + ".bin"), std::ios::binary)
                .write(reinterpret_cast<const char*>(bin.data()), std::streamsize(bin.size()));
        }
        const auto path = folder / (name + ".gltf");
        std::ofstream(path) << out.dump(1);
        return path;
    }

    nlohmann::json doc;
    std::vector<unsigned char> bin;
};

}  // namespace envshadow::test
