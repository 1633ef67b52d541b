#include "env/cell_overlay.h"

#include <cmath>

#include "env/latlong.h"

namespace envshadow {

float auto_exposure_stops(const EnvironmentMap& map) {
    double log_sum = 0.0;
    for (const glm::vec3& t : map.texels) log_sum += std::log(1e-4 + latlong::luminance(glm::dvec3(t)));
    const double log_average = std::exp(log_sum / double(map.texels.size()));
    return float(std::log2(0.18 / log_average));
}

Image8 draw_map(const EnvironmentMap& map) {
    Image linear(map.width, map.height, glm::vec4(0.0f, 0.0f, 0.0f, 1.0f));
    for (int j = 0; j < map.height; ++j)
        for (int i = 0; i < map.width; ++i) linear.at(i, j) = glm::vec4(map.at(i, j), 1.0f);
    return tonemap_to_srgb8(linear, auto_exposure_stops(map));
}

Image8 draw_cells(const EnvironmentMap& map, const Decomposition& decomposition) {
    Image8 picture = draw_map(map);

    auto cell = [&](int i, int j) { return decomposition.texel_cell[size_t(j) * size_t(map.width) + size_t(i)]; };
    auto paint = [&](int i, int j, std::uint8_t r, std::uint8_t g, std::uint8_t b) {
        std::uint8_t* p = picture.at(((i % map.width) + map.width) % map.width, j);
        p[0] = r;
        p[1] = g;
        p[2] = b;
    };
    for (int j = 0; j < map.height; ++j)
        for (int i = 0; i < map.width; ++i) {
            const bool right = cell(i, j) != cell((i + 1) % map.width, j);
            const bool below = j + 1 < map.height && cell(i, j) != cell(i, j + 1);
            if (right || below) paint(i, j, 255, 255, 255);
        }
    // Markers keep a fixed size in pixels; near the poles they cover more longitude, as the map does.
    const int radius = std::max(1, map.height / 128);
    for (const Cell& c : decomposition.cells) {
        const glm::dvec2 uv = latlong::uv(glm::dvec3(c.direction));
        const int ci = int(std::floor(uv.x * map.width)),
                  cj = std::min(map.height - 1, int(std::floor(uv.y * map.height)));
        for (int dj = -radius - 1; dj <= radius + 1; ++dj)
            for (int di = -radius - 1; di <= radius + 1; ++di) {
                const int j = cj + dj;
                if (j < 0 || j >= map.height) continue;
                const int d2 = di * di + dj * dj;
                if (d2 <= radius * radius)
                    paint(ci + di, j, 255, 40, 40);
                else if (d2 <= (radius + 1) * (radius + 1))
                    paint(ci + di, j, 0, 0, 0);
            }
    }
    return picture;
}

}  // namespace envshadow
