// The renderer's programs, keyed on the shader variant: changing each setting of the table builds the
// programs of a variant not seen before exactly once, and nothing for a setting that does not affect
// them or for a variant seen before.
#include <cmath>
#include <set>
#include <string>
#include <vector>

#include "gl_fixture.h"
#include "render/renderer.h"

namespace envshadow::testing {
namespace {

using render::Renderer;
using render::RenderSettings;
using render::SettingInfo;

// Every value a row lists, or its range's ends.
std::vector<std::string> values_of(const SettingInfo& setting) {
    if (!setting.choices.empty()) return setting.choices;
    std::vector<std::string> values;
    for (double bound : {setting.min, setting.max})
        if (std::isfinite(bound))
            values.push_back(setting.kind == render::SettingKind::integer ? std::to_string(int(bound))
                                                                          : std::to_string(bound));
    return values;
}

class ProgramCacheTest : public GlTest {};

TEST_P(ProgramCacheTest, EachVariantIsBuiltOnce) {
    const RenderSettings defaults;
    Renderer renderer(defaults);
    std::set<render::ShaderVariant> seen = {renderer.shader_variant()};
    int new_variants = 0;
    for (const SettingInfo& setting : render::setting_table()) {
        for (const std::string& value : values_of(setting)) {
            SCOPED_TRACE(std::string(setting.name) + " " + value);
            RenderSettings s = defaults;
            setting.parse(s, value);
            const std::size_t before = renderer.programs_built();
            renderer.set_settings(s);
            const bool new_variant = seen.insert(renderer.shader_variant()).second;
            new_variants += new_variant;
            EXPECT_TRUE(setting.effect == render::SettingEffect::programs || !new_variant);
            EXPECT_EQ(renderer.programs_built() - before, new_variant ? Renderer::kProgramsPerVariant : 0);
            // Back to a variant seen before: nothing built.
            renderer.set_settings(defaults);
            EXPECT_EQ(renderer.programs_built() - before, new_variant ? Renderer::kProgramsPerVariant : 0);
        }
    }
    EXPECT_GE(new_variants, 8);  // pcf, specular, diffuse, shading, shadows, 2 atlas modes, prepass, tiles, ubo
}

ENVSHADOW_INSTANTIATE_GL_TEST(ProgramCacheTest);

}  // namespace
}  // namespace envshadow::testing
