#pragma once
// Test-side references for the Floyd-Steinberg GPU sampler, written from the papers and docs/DESIGN.md,
// independent of engine/render: importance maps in double, a serpentine Floyd-Steinberg scan in
// double (Szirmay-Kalos et al. §1.3.1), maps to scan, and the upload of a map as a GL texture.
#include <algorithm>
#include <cmath>
#include <string>
#include <vector>

#include <glm/geometric.hpp>
#include <glm/vec2.hpp>
#include <glm/vec3.hpp>

#include "core/image.h"
#include "env/environment.h"
#include "env/latlong.h"
#include "gl/objects.h"

namespace envshadow::testing {

inline const char* kCityExr = "/usr/share/blender/datafiles/studiolights/world/city.exr";

// I = lum(L) dw per texel (docs/DESIGN.md §2), row-major.
inline std::vector<double> importance_map(const EnvironmentMap& map) {
    std::vector<double> importance(map.texels.size());
    for (int j = 0; j < map.height; ++j) {
        const double solid_angle = latlong::texel_solid_angle(j, map.width, map.height);
        for (int i = 0; i < map.width; ++i)
            importance[size_t(j) * map.width + i] = latlong::luminance(glm::dvec3(map.at(i, j))) * solid_angle;
    }
    return importance;
}

// Box downsampling by an integer factor that keeps sum L dw per coarse texel: each coarse texel gets
// the solid-angle-weighted mean of its f x f texels, so lum(L) dw of the coarse map equals the sum of
// the fine texels' importance.
inline EnvironmentMap downsample(const EnvironmentMap& map, int width, int height) {
    const int fx = map.width / width, fy = map.height / height;
    EnvironmentMap coarse{width, height, std::vector<glm::vec3>(size_t(width) * height), map.source};
    for (int j = 0; j < height; ++j)
        for (int i = 0; i < width; ++i) {
            glm::dvec3 sum(0.0);
            for (int y = j * fy; y < (j + 1) * fy; ++y)
                for (int x = i * fx; x < (i + 1) * fx; ++x)
                    sum += glm::dvec3(map.at(x, y)) * latlong::texel_solid_angle(y, map.width, map.height);
            coarse.at(i, j) = glm::vec3(sum / latlong::texel_solid_angle(j, width, height));
        }
    return coarse;
}

struct DiffusionWeights {
    double next, below, below_next;
};
inline constexpr DiffusionWeights kListingWeights{0.375, 0.375, 0.25};  // Szirmay-Kalos et al., Listing 1.1

// docs/FS_GPU.md: the next-texel weight that makes a uniform region's warm-up half the mean sample
// spacing, next = 1 - sqrt(M / N), at least 3/8; the rest 3 : 2 below and below-next.
inline DiffusionWeights warmup_matched_weights(int samples, int width, int height) {
    const double next = std::max(0.375, 1.0 - std::sqrt(double(samples) / (double(width) * height)));
    return {next, 0.6 * (1.0 - next), 0.4 * (1.0 - next)};
}

struct ReferenceSample {
    glm::ivec2 texel;
    int multiplicity;
};

// Floyd-Steinberg sampling as Szirmay-Kalos et al. §1.3.1 describe it: threshold S / (2M); a texel whose
// importance plus carried error exceeds it is a sample and the error drops by S / M; serpentine rows;
// the error goes to the next texel, below and below the next in the given shares, and the carries run
// on along the serpentine path across row ends, as in Listing 1.1. With `multi_level`, a texel takes
// one sample per threshold crossed, floor((e - S/2M) / (S/M)) + 1 of them, and the error drops by
// that many times S / M. Double precision.
inline std::vector<ReferenceSample> reference_floyd_steinberg(const std::vector<double>& importance, int width,
                                                              int height, int samples,
                                                              DiffusionWeights weights = kListingWeights,
                                                              bool multi_level = false) {
    double sum = 0.0;
    for (double value : importance) sum += value;
    const double threshold = sum / (2.0 * samples);
    std::vector<double> next_row(size_t(width), 0.0);
    double next_pixel = 0.0, below_next = 0.0;
    std::vector<ReferenceSample> chosen;
    for (int j = 0; j < height; ++j)
        for (int step = 0; step < width; ++step) {
            const int i = j % 2 == 0 ? step : width - 1 - step;
            double error = importance[size_t(j) * width + i] + next_row[size_t(i)] + next_pixel;
            if (error > threshold) {
                const int count = multi_level ? int(std::floor((error - threshold) / (2.0 * threshold))) + 1 : 1;
                chosen.push_back({{i, j}, count});
                error -= 2.0 * threshold * count;
            }
            next_row[size_t(i)] = weights.below * error + below_next;
            next_pixel = weights.next * error;
            below_next = weights.below_next * error;
        }
    return chosen;
}

inline int total_samples(const std::vector<ReferenceSample>& samples) {
    int total = 0;
    for (const ReferenceSample& s : samples) total += s.multiplicity;
    return total;
}

// The CPU method fs's rules (engine/env sites_floyd_steinberg; transcribed here until it lands on main,
// then the test compares with it directly): blocks of B x B texels (B from block_size), the share
// along the row clamp(1 - I_block / (S/M), 3/8, 15/16) and the rest 3 : 2 below and below-next, the
// next texel's share going below at the row's end, the diagonal wrapping around the seam, nothing
// carried across rows, everything along the row in the last row. Texel importance in float, as
// there; sums and the scan in double. Returns the chosen blocks and their importance-weighted mean
// directions.
inline int block_size(int width, int height, int samples) {
    int block = 1;
    while (block < height) {
        const long long coarser =
            (long long)((width + 2 * block - 1) / (2 * block)) * ((height + 2 * block - 1) / (2 * block));
        if (coarser < 64LL * samples) break;
        block *= 2;
    }
    return block;
}

struct BlockSample {
    glm::ivec2 block;
    glm::dvec3 direction;
};

inline std::vector<BlockSample> reference_adaptive_blocks(const EnvironmentMap& map, int samples) {
    const int width = map.width, height = map.height, block = block_size(width, height, samples);
    const int columns = (width + block - 1) / block, rows = (height + block - 1) / block;
    std::vector<double> blocks(size_t(columns) * rows, 0.0);
    std::vector<glm::dvec3> moments(blocks.size(), glm::dvec3(0.0));
    double total = 0.0;
    for (int j = 0; j < height; ++j) {
        const double solid_angle = latlong::texel_solid_angle(j, width, height);
        for (int i = 0; i < width; ++i) {
            const double w = float(latlong::luminance(glm::dvec3(map.at(i, j))) * solid_angle);
            blocks[size_t(j / block) * columns + i / block] += w;
            moments[size_t(j / block) * columns + i / block] += w * latlong::texel_direction(i, j, width, height);
            total += w;
        }
    }
    const double threshold = total / (2.0 * samples);
    std::vector<double> row_error(size_t(columns), 0.0), next_row_error(size_t(columns), 0.0);
    std::vector<BlockSample> chosen;
    double carried = 0.0;
    for (int by = 0; by < rows; ++by) {
        const int step = by % 2 == 0 ? 1 : -1;
        const bool last_row = by == rows - 1;
        for (int n = 0; n < columns; ++n) {
            const int bx = step > 0 ? n : columns - 1 - n;
            const size_t b = size_t(by) * columns + bx;
            double e = blocks[b] + row_error[size_t(bx)] + carried;
            carried = 0.0;
            if (e > threshold) {
                const glm::ivec2 centre(std::min(width - 1, bx * block + block / 2),
                                        std::min(height - 1, by * block + block / 2));
                const double length = glm::length(moments[b]);
                chosen.push_back({{bx, by},
                                  length > 1e-9 * blocks[b] && blocks[b] > 0.0
                                      ? moments[b] / length
                                      : latlong::texel_direction(centre.x, centre.y, width, height)});
                e -= 2.0 * threshold;
            }
            const bool last_in_row = n == columns - 1;
            const double along = std::clamp(1.0 - blocks[b] / (2.0 * threshold), 0.375, 15.0 / 16.0);
            const double below = (1.0 - along) * 0.6, diagonal = (1.0 - along) * 0.4;
            const int below_next = (bx + step + columns) % columns;
            if (!last_row) {
                if (!last_in_row) {
                    carried = along * e;
                    next_row_error[size_t(bx)] += below * e;
                } else {
                    next_row_error[size_t(bx)] += (along + below) * e;
                }
                next_row_error[size_t(below_next)] += diagonal * e;
            } else if (!last_in_row) {
                carried = e;
            }
        }
        std::swap(row_error, next_row_error);
        std::fill(next_row_error.begin(), next_row_error.end(), 0.0);
    }
    return chosen;
}

// An analytic sky: a blue gradient above the horizon, grey ground, a sun disc of `sun_radiance`
// (yellowish) and angular radius `sun_radius` (radians) about `sun`.
inline EnvironmentMap analytic_sky(int width, glm::dvec3 sun, double sun_radiance = 2000.0, double sun_radius = 0.02) {
    EnvironmentMap map{width, width / 2, std::vector<glm::vec3>(size_t(width) * (width / 2)), "analytic sky"};
    sun = glm::normalize(sun);
    for (int j = 0; j < map.height; ++j)
        for (int i = 0; i < map.width; ++i) {
            const glm::dvec3 d = latlong::texel_direction(i, j, map.width, map.height);
            glm::dvec3 radiance = d.y > 0.0 ? glm::dvec3(0.25, 0.45, 1.0) * (0.3 + 0.7 * d.y) : glm::dvec3(0.12);
            if (glm::dot(d, sun) > std::cos(sun_radius)) radiance = sun_radiance * glm::dvec3(1.0, 0.9, 0.7);
            map.at(i, j) = glm::vec3(radiance);
        }
    return map;
}

// Sun direction from elevation and azimuth (radians), azimuth measured from +X towards +Z.
inline glm::dvec3 sun_at(double elevation, double azimuth) {
    return {std::cos(elevation) * std::cos(azimuth), std::sin(elevation), std::cos(elevation) * std::sin(azimuth)};
}

// The blender-data city photograph through the project's loader (negatives clamped, docs/DESIGN.md §2).
inline EnvironmentMap city_map() {
    return load_environment(kCityExr);
}

// The map as an RGBA32F texture, texel (i, j) = map texel (i, j) (row 0, the zenith, first).
inline gl::Texture upload(const EnvironmentMap& map) {
    gl::Texture texture = gl::Texture::create_2d(GL_RGBA32F, map.width, map.height);
    glTextureSubImage2D(texture.id(), 0, 0, 0, map.width, map.height, GL_RGB, GL_FLOAT, map.texels.data());
    return texture;
}

}  // namespace envshadow::testing
