// cell_overlay.h's draw_cells: the map's size, white borders exactly between different cells (the wrap
// included), a red dot on every centre. On builtin:constant the tone-mapped map is mid grey, so white
// and red pixels can only be drawn ones.
#include <cmath>
#include <cstdint>

#include <gtest/gtest.h>

#include "contract_helpers.h"
#include "env/cell_overlay.h"

namespace envshadow::contract {
namespace {

bool white(const std::uint8_t* p) {
    return p[0] == 255 && p[1] == 255 && p[2] == 255;
}
bool red(const std::uint8_t* p) {
    return p[0] > 200 && p[1] < 100 && p[2] < 100;
}

TEST(EnvContractOverlay, BordersOnlyBetweenCellsAndADotOnEveryCentre) {
    const EnvironmentMap& map = cached_map("builtin:constant");
    for (int lights : {1, 16}) {
        const Decomposition d = decompose(map, {.method = Method::lloyd, .lights = lights});
        const Image8 picture = draw_cells(map, d);
        ASSERT_EQ(picture.width, map.width);
        ASSERT_EQ(picture.height, map.height);
        ASSERT_EQ(picture.rgba.size(), std::size_t(map.width) * std::size_t(map.height) * 4);
        auto cell = [&](int i, int j) { return d.texel_cell[texel_index((i + map.width) % map.width, j, map.width)]; };
        int whites = 0, border_texels = 0;
        for (int j = 0; j < map.height; ++j)
            for (int i = 0; i < map.width; ++i) {
                const bool border = cell(i, j) != cell(i + 1, j) || cell(i, j) != cell(i - 1, j) ||
                                    (j + 1 < map.height && cell(i, j) != cell(i, j + 1)) ||
                                    (j > 0 && cell(i, j) != cell(i, j - 1));
                border_texels += border;
                if (white(picture.at(i, j))) {
                    ++whites;
                    EXPECT_TRUE(border) << "N=" << lights << ": white pixel " << i << "," << j << " inside a cell";
                }
            }
        if (lights == 1) {
            EXPECT_EQ(whites, 0) << "one cell has no border";
        } else {
            EXPECT_GT(whites, border_texels / 4) << "borders are drawn";
        }
        for (const Cell& c : d.cells) {
            const glm::dvec2 uv = latlong::uv(glm::dvec3(c.direction));
            const int i = std::min(map.width - 1, int(uv.x * map.width)),
                      j = std::min(map.height - 1, int(uv.y * map.height));
            EXPECT_TRUE(red(picture.at(i, j)))
                << "N=" << lights << ": no red dot at the centre texel " << i << "," << j;
        }
    }
}

}  // namespace
}  // namespace envshadow::contract
