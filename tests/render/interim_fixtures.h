#pragma once
// TEMPORARY stand-in for engine/env's decomposition of the builtin maps, until it lands on main:
// cells of builtin:constant (equal Fibonacci cells) and of builtin:sky (a sun cell at the given
// elevation, azimuth 60 degrees, a dim blue upper hemisphere and a dark lower one). Then renderer_test.cpp's cells_of()
// calls decompose(load_environment(...)) and this file goes.
#include <cmath>
#include <numbers>
#include <string>
#include <vector>

#include <glm/geometric.hpp>

#include "env/cells.h"

namespace envshadow::testing::interim {

// Fibonacci directions over the sphere (or the upper hemisphere).
inline std::vector<glm::vec3> fibonacci(int n, bool upper_only) {
    std::vector<glm::vec3> d;
    const float golden = std::numbers::pi_v<float> * (3.0f - std::sqrt(5.0f));
    for (int i = 0; i < n; ++i) {
        const float y = upper_only ? 1.0f - (float(i) + 0.5f) / float(n) : 1.0f - 2.0f * (float(i) + 0.5f) / float(n);
        const float r = std::sqrt(std::max(0.0f, 1.0f - y * y));
        d.push_back({r * std::cos(golden * float(i)), y, r * std::sin(golden * float(i))});
    }
    return d;
}

inline Cell make_cell(glm::vec3 direction, glm::vec3 radiance, float solid_angle) {
    Cell c;
    c.direction = glm::normalize(direction);
    c.radiance = radiance;
    c.solid_angle = solid_angle;
    c.cos_radius = c.cos_radius_weighted = 1.0f - solid_angle / (2.0f * std::numbers::pi_v<float>);
    return c;
}

// "builtin:constant" or "builtin:sky[:elevation=E]".
inline std::vector<Cell> cells_of(const std::string& environment, int n) {
    std::vector<Cell> cells;
    if (environment == "builtin:constant") {
        const float solid_angle = 4.0f * std::numbers::pi_v<float> / float(n);
        for (const glm::vec3& d : fibonacci(n, false))
            cells.push_back(make_cell(d, glm::vec3(solid_angle), solid_angle));
        return cells;
    }
    float elevation = 35.0f;
    if (const auto at = environment.find("elevation="); at != std::string::npos)
        elevation = std::stof(environment.substr(at + 10));
    const float e = elevation * std::numbers::pi_v<float> / 180.0f, a = std::numbers::pi_v<float> / 3.0f;
    cells.push_back(
        make_cell({std::cos(e) * std::cos(a), std::sin(e), std::cos(e) * std::sin(a)}, glm::vec3(20.0f), 1e-3f));
    const int sky = (n - 1) / 2, ground = n - 1 - sky;  // a blue upper hemisphere, a dark lower one
    for (const glm::vec3& d : fibonacci(sky, true)) {
        const float solid_angle = 2.0f * std::numbers::pi_v<float> / float(sky);
        cells.push_back(make_cell(d, glm::vec3(0.3f, 0.45f, 0.7f) * solid_angle, solid_angle));
    }
    for (const glm::vec3& d : fibonacci(ground, true)) {
        const float solid_angle = 2.0f * std::numbers::pi_v<float> / float(ground);
        cells.push_back(make_cell(glm::vec3(d.x, -d.y, d.z), glm::vec3(0.05f) * solid_angle, solid_angle));
    }
    return cells;
}

}  // namespace envshadow::testing::interim
