#pragma once
// Shared by the environment-decomposition acceptance tests: the maps (loaded once per process), and
// every reference quantity recomputed here from the map's texels with the convention of docs/DESIGN.md §2
// (latlong.h), never with the integration code under test.
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <map>
#include <memory>
#include <numbers>
#include <string>
#include <vector>

#include <gtest/gtest.h>
#include <glm/geometric.hpp>
#include <glm/vec3.hpp>

#include "env/cells.h"
#include "env/environment.h"
#include "env/latlong.h"

namespace envshadow::contract {

inline constexpr double kFourPi = 4.0 * std::numbers::pi;
inline constexpr int kIssueCounts[] = {1, 16, 64, 128, 256};
inline constexpr Method kAllMethods[] = {Method::lloyd, Method::ccvt, Method::mediancut, Method::random, Method::fs};

inline const char* const kBlenderMaps[] = {"city",  "courtyard", "forest",  "interior",
                                           "night", "studio",    "sunrise", "sunset"};

inline std::string blender_map(const std::string& name) {
    return "/usr/share/blender/datafiles/studiolights/world/" + name + ".exr";
}

// One load per spec and process (gtest runs many tests in one process when run directly).
inline const EnvironmentMap& cached_map(const std::string& spec) {
    static std::map<std::string, std::unique_ptr<EnvironmentMap>> cache;
    auto& slot = cache[spec];
    if (!slot) slot = std::make_unique<EnvironmentMap>(load_environment(spec));
    return *slot;
}

inline std::size_t texel_index(int i, int j, int width) {
    return std::size_t(j) * std::size_t(width) + std::size_t(i);
}

// ∫ L dω, texel by texel, with the exact texel solid angle.
inline glm::dvec3 direct_integral(const EnvironmentMap& map) {
    glm::dvec3 total(0.0);
    for (int j = 0; j < map.height; ++j) {
        glm::dvec3 row(0.0);
        for (int i = 0; i < map.width; ++i) row += glm::dvec3(map.at(i, j));
        total += row * latlong::texel_solid_angle(j, map.width, map.height);
    }
    return total;
}

// I = lum(L) dω per texel (docs/DESIGN.md §2); where the whole map is black, dω (the documented fallback).
inline std::vector<double> texel_importance(const EnvironmentMap& map) {
    std::vector<double> importance(map.texels.size());
    double total = 0.0;
    for (int j = 0; j < map.height; ++j) {
        const double dw = latlong::texel_solid_angle(j, map.width, map.height);
        for (int i = 0; i < map.width; ++i)
            total += importance[texel_index(i, j, map.width)] = latlong::luminance(glm::dvec3(map.at(i, j))) * dw;
    }
    if (total <= 0.0)
        for (int j = 0; j < map.height; ++j)
            for (int i = 0; i < map.width; ++i)
                importance[texel_index(i, j, map.width)] = latlong::texel_solid_angle(j, map.width, map.height);
    return importance;
}

// Per-cell sums recomputed from the texel -> cell assignment alone.
struct CellSums {
    std::vector<glm::dvec3> radiance;               // Σ L dω
    std::vector<double> solid_angle;                // Σ dω
    std::vector<double> importance;                 // Σ I
    std::vector<glm::dvec3> importance_direction;   // Σ I ω
    std::vector<glm::dvec3> solid_angle_direction;  // Σ dω ω
    std::vector<long> texels;
};

inline CellSums cell_sums(const EnvironmentMap& map, const std::vector<double>& importance,
                          const std::vector<std::uint16_t>& texel_cell, std::size_t count) {
    CellSums s;
    s.radiance.assign(count, glm::dvec3(0.0));
    s.solid_angle.assign(count, 0.0);
    s.importance.assign(count, 0.0);
    s.importance_direction.assign(count, glm::dvec3(0.0));
    s.solid_angle_direction.assign(count, glm::dvec3(0.0));
    s.texels.assign(count, 0);
    for (int j = 0; j < map.height; ++j) {
        const double dw = latlong::texel_solid_angle(j, map.width, map.height);
        for (int i = 0; i < map.width; ++i) {
            const std::size_t t = texel_index(i, j, map.width);
            const std::size_t k = texel_cell[t];
            if (k >= count) continue;  // reported by the caller
            const glm::dvec3 w = latlong::texel_direction(i, j, map.width, map.height);
            s.radiance[k] += dw * glm::dvec3(map.texels[t]);
            s.solid_angle[k] += dw;
            s.importance[k] += importance[t];
            s.importance_direction[k] += importance[t] * w;
            s.solid_angle_direction[k] += dw * w;
            ++s.texels[k];
        }
    }
    return s;
}

// How many cells a method promises for N lights (docs/DESIGN.md §3, cells.h, sites.h): exactly N; fs N or
// N - 1 (the issue allows N ± 2); mediancut 2^k, k = floor(log2 N) (equal_importance_regions always
// gives as many sites as asked for).
inline bool count_as_promised(Method method, int lights, std::size_t cells) {
    const long n = long(cells);
    switch (method) {
        case Method::mediancut: {
            long power = 1;
            while (power * 2 <= lights) power *= 2;
            return n == power;
        }
        case Method::fs:
            return n == lights || n == lights - 1;
        default:
            return n == lights;
    }
}

// Every promise docs/DESIGN.md §3 makes about any decomposition, checked against sums recomputed here from
// map.texels and texel_cell. Failures name `context`; at most a few per kind are printed.
inline void expect_cells_contract(const EnvironmentMap& map, const Decomposition& d, const std::string& context) {
    SCOPED_TRACE(context);
    ASSERT_EQ(d.width, map.width);
    ASSERT_EQ(d.height, map.height);
    ASSERT_FALSE(d.cells.empty());
    ASSERT_EQ(d.texel_cell.size(), map.texels.size()) << "texel_cell must have W x H entries";
    const std::size_t count = d.cells.size();
    long out_of_range = 0;
    for (std::uint16_t k : d.texel_cell) out_of_range += k >= count;
    ASSERT_EQ(out_of_range, 0) << "texel_cell entries must index cells (" << count << " cells)";

    const glm::dvec3 integral = direct_integral(map);
    const std::vector<double> importance = texel_importance(map);
    const CellSums sums = cell_sums(map, importance, d.texel_cell, count);

    // Conservation: Σ L̃_i = ∫ L dω (per channel, 1e-4 relative) and Σ Δω_i = 4π.
    glm::dvec3 radiance_sum(0.0);
    double solid_angle_sum = 0.0;
    for (const Cell& cell : d.cells) {
        radiance_sum += glm::dvec3(cell.radiance);
        solid_angle_sum += cell.solid_angle;
    }
    const double scale = std::max({integral.r, integral.g, integral.b});
    for (int c = 0; c < 3; ++c) {
        EXPECT_NEAR(radiance_sum[c], integral[c], 1e-4 * integral[c] + 1e-12) << "Σ L̃ channel " << c;
        EXPECT_NEAR(d.integral[c], integral[c], 1e-6 * integral[c] + 1e-12) << "Decomposition::integral channel " << c;
    }
    EXPECT_NEAR(solid_angle_sum, kFourPi, 1e-4 * kFourPi) << "Σ Δω_i";

    int printed = 0;
    auto show = [&] { return ++printed <= 5; };  // the first few failures in full, then only the counts
    long bad_solid_angle = 0, bad_radiance = 0, bad_direction = 0, bad_cap = 0, bad_weighted = 0, bad_centre = 0;
    std::vector<double> weighted_cos(count, 0.0), solid_cos(count, 0.0);
    for (int j = 0; j < map.height; ++j) {
        const double dw = latlong::texel_solid_angle(j, map.width, map.height);
        for (int i = 0; i < map.width; ++i) {
            const std::size_t t = texel_index(i, j, map.width);
            const std::size_t k = d.texel_cell[t];
            const double cosine = glm::dot(latlong::texel_direction(i, j, map.width, map.height),
                                           glm::normalize(glm::dvec3(d.cells[k].direction)));
            weighted_cos[k] += importance[t] * cosine;
            solid_cos[k] += dw * cosine;
        }
    }
    for (std::size_t k = 0; k < count; ++k) {
        const Cell& cell = d.cells[k];
        // Each cell's solid angle and radiance are the sums over exactly its texels.
        if (std::abs(cell.solid_angle - sums.solid_angle[k]) > 1e-5 * sums.solid_angle[k] + 1e-9) {
            ++bad_solid_angle;
            if (show())
                ADD_FAILURE() << "cell " << k << ": "
                              << "solid_angle " << cell.solid_angle << " but its texels sum to " << sums.solid_angle[k];
        }
        for (int c = 0; c < 3; ++c)
            if (std::abs(cell.radiance[c] - sums.radiance[k][c]) > 1e-5 * sums.radiance[k][c] + 1e-7 * scale + 1e-12) {
                ++bad_radiance;
                if (show())
                    ADD_FAILURE() << "cell " << k << ": "
                                  << "radiance[" << c << "] " << cell.radiance[c] << " but its texels sum to "
                                  << sums.radiance[k][c];
            }
        const double length = glm::length(glm::dvec3(cell.direction));
        if (!(std::abs(length - 1.0) <= 1e-5)) {
            ++bad_direction;
            if (show())
                ADD_FAILURE() << "cell " << k << ": "
                              << "direction length " << length;
        }
        const double expected_cap = 1.0 - sums.solid_angle[k] / (2.0 * std::numbers::pi);
        if (!(cell.cos_radius >= -1.0f && cell.cos_radius <= 1.0f) || std::abs(cell.cos_radius - expected_cap) > 1e-5) {
            ++bad_cap;
            if (show())
                ADD_FAILURE() << "cell " << k << ": "
                              << "cos_radius " << cell.cos_radius << ", 1 - Δω/(2π) = " << expected_cap;
        }
        // docs/DESIGN.md §3: cos r^w = 2 (Σ I (ω·c) / Σ I) - 1; cells.h: solid-angle weights where Σ I = 0,
        // and 1 for an empty cell.
        double expected_weighted = 1.0;
        if (sums.importance[k] > 0.0)
            expected_weighted = 2.0 * weighted_cos[k] / sums.importance[k] - 1.0;
        else if (sums.solid_angle[k] > 0.0)
            expected_weighted = 2.0 * solid_cos[k] / sums.solid_angle[k] - 1.0;
        if (!(cell.cos_radius_weighted >= -1.0f && cell.cos_radius_weighted <= 1.0f) ||
            std::abs(cell.cos_radius_weighted - std::clamp(expected_weighted, -1.0, 1.0)) > 2e-5) {
            ++bad_weighted;
            if (show())
                ADD_FAILURE() << "cell " << k << ": "
                              << "cos_radius_weighted " << cell.cos_radius_weighted << ", recomputed "
                              << expected_weighted;
        }
        // cells.h: the centre is the normalised Σ I ω (where that is well defined).
        const glm::dvec3 mean_direction = sums.importance_direction[k];
        if (sums.importance[k] > 0.0 && glm::length(mean_direction) > 1e-3 * sums.importance[k]) {
            const double error = glm::length(glm::normalize(mean_direction) - glm::dvec3(cell.direction));
            if (error > 1e-4) {
                ++bad_centre;
                if (show())
                    ADD_FAILURE() << "cell " << k << ": "
                                  << "direction is " << error << " from the normalised Σ I ω";
            }
        }
    }
    EXPECT_EQ(bad_solid_angle + bad_radiance + bad_direction + bad_cap + bad_weighted + bad_centre, 0)
        << "solid_angle " << bad_solid_angle << ", radiance " << bad_radiance << ", direction " << bad_direction
        << ", cos_radius " << bad_cap << ", cos_radius_weighted " << bad_weighted << ", centre " << bad_centre
        << " cells wrong of " << count;
}

inline double mean(const std::vector<double>& v) {
    double s = 0.0;
    for (double x : v) s += x;
    return v.empty() ? 0.0 : s / double(v.size());
}

// Coefficient of variation (population standard deviation / mean).
inline double coefficient_of_variation(const std::vector<double>& v) {
    const double m = mean(v);
    double s = 0.0;
    for (double x : v) s += (x - m) * (x - m);
    return v.empty() || m == 0.0 ? 0.0 : std::sqrt(s / double(v.size())) / m;
}

inline std::vector<double> ranks(const std::vector<double>& v) {
    std::vector<std::size_t> order(v.size());
    for (std::size_t k = 0; k < v.size(); ++k) order[k] = k;
    std::sort(order.begin(), order.end(), [&](std::size_t a, std::size_t b) { return v[a] < v[b]; });
    std::vector<double> r(v.size());
    for (std::size_t k = 0; k < order.size();) {  // ties share their mean rank
        std::size_t e = k;
        while (e + 1 < order.size() && v[order[e + 1]] == v[order[k]]) ++e;
        for (std::size_t q = k; q <= e; ++q) r[order[q]] = 0.5 * double(k + e);
        k = e + 1;
    }
    return r;
}

inline double pearson(const std::vector<double>& a, const std::vector<double>& b) {
    const double ma = mean(a), mb = mean(b);
    double sab = 0.0, saa = 0.0, sbb = 0.0;
    for (std::size_t k = 0; k < a.size(); ++k) {
        sab += (a[k] - ma) * (b[k] - mb);
        saa += (a[k] - ma) * (a[k] - ma);
        sbb += (b[k] - mb) * (b[k] - mb);
    }
    return sab / std::sqrt(saa * sbb);
}

inline double spearman(const std::vector<double>& a, const std::vector<double>& b) {
    return pearson(ranks(a), ranks(b));
}

// The map turned 180° about +Y: columns rolled by W/2 (φ -> φ + π).
inline EnvironmentMap rolled_half_turn(const EnvironmentMap& map) {
    EnvironmentMap out = map;
    for (int j = 0; j < map.height; ++j)
        for (int i = 0; i < map.width; ++i) out.at((i + map.width / 2) % map.width, j) = map.at(i, j);
    out.source = map.source + " (rolled by W/2)";
    return out;
}

// Rows in which the cells of columns a and b differ.
inline int column_pair_crossings(const Decomposition& d, int a, int b) {
    int crossings = 0;
    for (int j = 0; j < d.height; ++j)
        crossings += d.texel_cell[texel_index(a, j, d.width)] != d.texel_cell[texel_index(b, j, d.width)];
    return crossings;
}

inline std::string describe(const std::string& spec, Method method, int lights) {
    return spec + " " + std::string(to_string(method)) + " N=" + std::to_string(lights);
}

}  // namespace envshadow::contract
