#pragma once
// Shared by the env tests: the eight HDR photographs of blender-data (docs/DESIGN.md §7), loaded once per
// test program, and a scratch folder.
#include <gtest/gtest.h>
#include <unistd.h>

#include <cmath>
#include <filesystem>
#include <glm/vec3.hpp>
#include <map>
#include <string>
#include <vector>

#include <glm/geometric.hpp>

#include "env/environment.h"
#include "env/latlong.h"

namespace envshadow::test {

inline const std::filesystem::path kWorldFolder = "/usr/share/blender/datafiles/studiolights/world";
inline const std::vector<std::string> kWorldNames = {"city",  "courtyard", "forest",  "interior",
                                                     "night", "studio",    "sunrise", "sunset"};

inline std::string world_path(const std::string& name) {
    return (kWorldFolder / (name + ".exr")).string();
}

// Loaded once per process; the maps are read-only afterwards.
inline const EnvironmentMap& world(const std::string& name) {
    static std::map<std::string, EnvironmentMap> cache;
    auto it = cache.find(name);
    if (it == cache.end())
        it = cache.emplace(name, load_environment(name.starts_with("builtin:") ? name : world_path(name))).first;
    return it->second;
}

// A prefiltered value's luminance against the direct integral's, relative (the prefiltering tests).
inline double relative_error(const glm::vec3& got, const glm::dvec3& want) {
    return std::abs(latlong::luminance(glm::dvec3(got)) - latlong::luminance(want)) / latlong::luminance(want);
}

// Directions the prefiltering tests look up: the zenith, the upper and lower hemispheres, near the horizon.
inline std::vector<glm::dvec3> test_directions() {
    return {glm::normalize(glm::dvec3(0.0, 1.0, 0.0)), glm::normalize(glm::dvec3(0.3, 0.8, -0.5)),
            glm::normalize(glm::dvec3(-0.7, 0.25, 0.4)), glm::normalize(glm::dvec3(0.9, 0.05, 0.2)),
            glm::normalize(glm::dvec3(0.1, -0.6, 0.8))};
}

inline std::filesystem::path scratch_folder() {
    const auto dir =
        std::filesystem::temp_directory_path() / ("envshadow_env_" + std::to_string(::getpid()) + "_" +
                                                  ::testing::UnitTest::GetInstance()->current_test_info()->name());
    std::filesystem::create_directories(dir);
    return dir;
}

}  // namespace envshadow::test

namespace envshadow::test {

// The integral of L dw written out here, independently of the code under test.
inline glm::dvec3 direct_integral(const EnvironmentMap& map) {
    glm::dvec3 sum(0.0);
    for (int j = 0; j < map.height; ++j) {
        const double dw =
            (2.0 * 3.14159265358979323846 / map.width) * (std::cos(3.14159265358979323846 * j / map.height) -
                                                          std::cos(3.14159265358979323846 * (j + 1) / map.height));
        for (int i = 0; i < map.width; ++i) sum += dw * glm::dvec3(map.at(i, j));
    }
    return sum;
}

}  // namespace envshadow::test
