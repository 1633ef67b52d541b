#pragma once
// Shared by the libFuzzer targets: every loader takes a path, so each input is written to a file in
// a private folder; the error contract (docs/DESIGN.md §6) is checked on every input, so a multi-line
// message, one that does not name the file, or any exception other than InputError is a finding.
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <string>

#include <unistd.h>

#include "core/error.h"
#include "env/environment.h"
#include "scene/scene.h"

namespace envshadow::fuzz {

// A folder of this process's own, made once (libFuzzer's -fork and -jobs run several processes).
inline const std::filesystem::path& work_folder() {
    static const std::filesystem::path folder = [] {
        auto dir = std::filesystem::temp_directory_path() / ("envshadow-fuzz-" + std::to_string(::getpid()));
        std::filesystem::create_directories(dir);
        return dir;
    }();
    return folder;
}

inline std::filesystem::path write_input(const std::string& name, const std::uint8_t* data, std::size_t size) {
    const auto path = work_folder() / name;
    // Removed first: truncating in place makes ext4 flush the file on close (auto_da_alloc), ~3 ms.
    std::error_code ignored;
    std::filesystem::remove(path, ignored);
    std::ofstream out(path, std::ios::binary | std::ios::trunc);
    out.write(reinterpret_cast<const char*>(data), std::streamsize(size));
    out.close();
    if (!out) {
        std::fprintf(stderr, "fuzz harness: cannot write %s\n", path.c_str());
        std::abort();
    }
    return path;
}

[[noreturn]] inline void finding(const std::string& what) {
    std::fprintf(stderr, "contract violated: %s\n", what.c_str());
    std::abort();
}

// "<file>: <reason>" on one line.
inline void check_error_message(const InputError& error, const std::filesystem::path& file) {
    const std::string message = error.what();
    if (message.rfind(file.string() + ": ", 0) != 0) finding("message does not start with the file: " + message);
    if (message.find_first_of("\r\n") != std::string::npos) finding("message spans lines: " + message);
    if (message.size() <= file.string().size() + 2) finding("message gives no reason: " + message);
}

inline bool finite(const glm::vec3& v) {
    return std::isfinite(v.x) && std::isfinite(v.y) && std::isfinite(v.z);
}

// What every consumer of a Mesh relies on (scene/scene.h).
inline void check_mesh(const Mesh& mesh) {
    if (mesh.indices.empty() || mesh.indices.size() % 3 != 0) finding("mesh without whole triangles");
    if (mesh.normals.size() != mesh.positions.size()) finding("normals and positions differ in count");
    for (const std::uint32_t i : mesh.indices)
        if (i >= mesh.positions.size()) finding("index out of range");
    for (std::size_t v = 0; v < mesh.positions.size(); ++v) {
        if (!finite(mesh.positions[v])) finding("non-finite position");
        if (!finite(mesh.normals[v])) finding("non-finite normal");
    }
    if (!finite(mesh.bounds_min) || !finite(mesh.bounds_max)) finding("non-finite bounds");
}

// What every consumer of an EnvironmentMap relies on (env/environment.h).
inline void check_environment(const EnvironmentMap& map) {
    if (map.width < 2 || map.width != 2 * map.height || map.width > kMaxEnvironmentWidth)
        finding("map of " + std::to_string(map.width) + "x" + std::to_string(map.height));
    if (map.texels.size() != std::size_t(map.width) * std::size_t(map.height)) finding("texel count");
    for (const glm::vec3& t : map.texels)
        if (!finite(t) || t.r < 0.0f || t.g < 0.0f || t.b < 0.0f) finding("negative or non-finite texel");
}

}  // namespace envshadow::fuzz
