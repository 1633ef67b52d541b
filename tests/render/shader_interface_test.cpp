// The numbers C++ and glsl/ share come from one table (render/shader_interface.h): every program the
// engine builds, in every variant, has each active uniform, sampler, image, storage block, vertex
// input and work group where the table says, and every table entry is used by some program.
#include <bit>
#include <cctype>
#include <map>
#include <set>
#include <string>
#include <vector>

#include "core/tonemap.h"
#include "gl_fixture.h"
#include "render/embedded_shaders.h"
#include "render/shader_interface.h"

namespace envshadow::testing {
namespace {

using ShaderInterfaceTest = GlTest;

struct BuiltProgram {
    std::string name;
    gl::Program program;
};

// The stages and defines the renderer, the GPU sampler and the display build (renderer.cpp
// build_programs, fs_sampler.cpp, display.cpp), with the variants that make every uniform active.
std::vector<BuiltProgram> engine_programs() {
    const gl::ShaderLibrary library = render::embedded_shaders();
    const std::vector<gl::ShaderStage> shade = {{GL_VERTEX_SHADER, "shade.vert"}, {GL_FRAGMENT_SHADER, "shade.frag"}};
    std::vector<BuiltProgram> programs;
    auto add = [&](std::string name, const std::vector<gl::ShaderStage>& stages,
                   const std::vector<std::string>& defines = {}, const std::vector<std::string>& feedback = {}) {
        programs.push_back({std::move(name), library.build(stages, defines, feedback)});
    };
    add("shadow_atlas.vert (clip distances)", {{GL_VERTEX_SHADER, "shadow_atlas.vert"}}, {"ATLAS_CLIP_DISTANCES"});
    add("shadow_atlas.vert (per tile, storage block)", {{GL_VERTEX_SHADER, "shadow_atlas.vert"}});
    add("shadow atlas, alpha-masked casters",
        {{GL_VERTEX_SHADER, "shadow_atlas.vert"}, {GL_FRAGMENT_SHADER, "shadow_atlas_mask.frag"}},
        {"ATLAS_CLIP_DISTANCES", "ALPHA_MASK"});
    add("shadow atlas, blended casters' translucent layer",
        {{GL_VERTEX_SHADER, "shadow_atlas.vert"}, {GL_FRAGMENT_SHADER, "shadow_atlas_translucent.frag"}},
        {"ATLAS_CLIP_DISTANCES", "ALPHA_MASK"});
    if (GLAD_GL_ARB_shader_viewport_layer_array)
        add("shadow_atlas.vert (viewport array)", {{GL_VERTEX_SHADER, "shadow_atlas.vert"}},
            {"ATLAS_VIEWPORT_ARRAY", "LIGHTS_UNIFORM_BLOCK"});
    add("shade (tile lists, uniform block)", shade, {"SHADOW_TILE_LISTS", "LIGHTS_UNIFORM_BLOCK"});
    add("shade (every light, wide PCF, cap, single)", shade, {"PCF_WIDE", "DIFFUSE_CAP", "SPECULAR_SINGLE"});
    add("shade (flat receiver)", shade, {"SHADOW_TILE_LISTS", "DIFFUSE_ONLY", "FLAT_RECEIVER"});
    add("shade (ratio, every light)", shade, {"SHADING_RATIO"});
    add("shade (ratio, glTF's BRDF)", shade, {"SHADING_RATIO", "SHADOW_TILE_LISTS", "METALLIC_ROUGHNESS"});
    add("shade (ratio, flat receiver)", shade, {"SHADING_RATIO", "SHADOW_TILE_LISTS", "DIFFUSE_ONLY", "FLAT_RECEIVER"});
    add("shade (soft shadows, tile lists, uniform block)", shade,
        {"SOFT_SHADOWS", "SHADOW_TILE_LISTS", "LIGHTS_UNIFORM_BLOCK"});
    add("shade (soft shadows, ratio, flat receiver)", shade,
        {"SOFT_SHADOWS", "SHADING_RATIO", "SHADOW_TILE_LISTS", "DIFFUSE_ONLY", "FLAT_RECEIVER"});
    add("shade (ratio, shadowed fraction pass, soft, flat receiver)", shade,
        {"SHADING_RATIO", "SOFT_SHADOWS", "SHADOW_TILE_LISTS", "DIFFUSE_ONLY", "FLAT_RECEIVER",
         "SHADOWED_FRACTION_OUT"});
    add("shade (shading from the shadowed fraction)", shade, {"SHADOWED_FRACTION_IN"});
    add("shade (shading from the shadowed fraction, glTF's BRDF)", shade,
        {"SHADOWED_FRACTION_IN", "METALLIC_ROUGHNESS"});
    add("shade (shadowed fraction pass, soft, the sun per pixel)", shade,
        {"SHADING_RATIO", "SOFT_SHADOWS", "SHADOW_TILE_LISTS", "SHADOWED_FRACTION_OUT", "SUN_PER_PIXEL"});
    add("shade (shading from the shadowed fraction, soft, the sun per pixel, glTF's BRDF)", shade,
        {"SHADING_RATIO", "SOFT_SHADOWS", "SHADOW_TILE_LISTS", "SHADOWED_FRACTION_OUT", "SUN_PER_PIXEL",
         "SHADOWED_FRACTION_IN", "METALLIC_ROUGHNESS"});
    add("depth pre-pass", {{GL_VERTEX_SHADER, "shade.vert"}, {GL_FRAGMENT_SHADER, "depth_prepass.frag"}});
    add("depth pre-pass, alpha-masked", {{GL_VERTEX_SHADER, "shade.vert"}, {GL_FRAGMENT_SHADER, "depth_prepass.frag"}},
        {"ALPHA_MASK"});
    add("shade (no pre-pass: the alpha test)", shade, {"ALPHA_TEST"});
    add("shade (blended, translucent shadows, soft, ratio)", shade,
        {"ALPHA_BLEND", "TRANSLUCENT_SHADOWS", "SOFT_SHADOWS", "SHADING_RATIO"});
    add("background", {{GL_VERTEX_SHADER, "background.vert"}, {GL_FRAGMENT_SHADER, "background.frag"}});
    add("fraction filter", {{GL_VERTEX_SHADER, "present.vert"}, {GL_FRAGMENT_SHADER, "fraction_filter.frag"}});
    add("shadow_tiles.comp", {{GL_COMPUTE_SHADER, "shadow_tiles.comp"}}, {"LIGHTS_UNIFORM_BLOCK"});
    add("shadow_tiles.comp (MSAA depth)", {{GL_COMPUTE_SHADER, "shadow_tiles.comp"}},
        {"LIGHTS_UNIFORM_BLOCK", "DEPTH_SAMPLES 4"});
    add("fs_importance.comp", {{GL_COMPUTE_SHADER, "fs_importance.comp"}});
    add("fs_lights.comp", {{GL_COMPUTE_SHADER, "fs_lights.comp"}});
    add("fs_cell_assign.comp", {{GL_COMPUTE_SHADER, "fs_cell_assign.comp"}});
    add("fs_cell_integrate.comp", {{GL_COMPUTE_SHADER, "fs_cell_integrate.comp"}});
    add("fs_sampler", {{GL_VERTEX_SHADER, "fs_sampler.vert"}, {GL_GEOMETRY_SHADER, "fs_sampler.geom"}},
        {"FS_IMPORTANCE_WIDTH 32", "FS_MAX_VERTICES 16", "FS_MERGE"}, {"fs_texel"});
    for (std::size_t op = 0; op < kToneMapCount; ++op)
        add("present (" + std::string(to_string(ToneMap(op))) + ")",
            {{GL_VERTEX_SHADER, "present.vert"}, {GL_FRAGMENT_SHADER, "present.frag"}}, {tone_map_define(ToneMap(op))});
    add("atlas preview", {{GL_VERTEX_SHADER, "present.vert"}, {GL_FRAGMENT_SHADER, "atlas_preview.frag"}});
    return programs;
}

// "TileLists" -> "tile_lists": a block's name in GLSL to its table name.
std::string snake_case(const std::string& camel) {
    std::string out;
    for (char c : camel) {
        if (std::isupper(static_cast<unsigned char>(c))) {
            if (!out.empty()) out += '_';
            out += char(std::tolower(static_cast<unsigned char>(c)));
        } else {
            out += c;
        }
    }
    return out;
}

std::string resource_name(GLuint program, GLenum interface, GLuint index) {
    char name[256] = {};
    glGetProgramResourceName(program, interface, index, sizeof(name), nullptr, name);
    return name;
}

GLint resource_property(GLuint program, GLenum interface, GLuint index, GLenum property) {
    GLint value = 0;
    glGetProgramResourceiv(program, interface, index, 1, &property, 1, nullptr, &value);
    return value;
}

GLint active_resources(GLuint program, GLenum interface) {
    GLint count = 0;
    glGetProgramInterfaceiv(program, interface, GL_ACTIVE_RESOURCES, &count);
    return count;
}

TEST_P(ShaderInterfaceTest, EveryProgramUsesTheTablesNumbers) {
    std::map<std::string, int> table;  // "loc/eye" -> 12
    for (const render::shader::Constant& c : render::shader::constants()) {
        const std::string key = std::string(c.kind) + "/" + c.name;
        EXPECT_TRUE(table.emplace(key, c.value).second) << key << " is in the table twice";
    }
    std::set<std::string> used;
    auto expect = [&](const std::string& program, const std::string& key, GLint actual) {
        const auto it = table.find(key);
        if (it == table.end()) {
            ADD_FAILURE() << program << ": " << key << " is not in render/shader_interface.h";
            return;
        }
        used.insert(key);
        EXPECT_EQ(actual, it->second) << program << ": " << key;
    };

    for (const BuiltProgram& built : engine_programs()) {
        const GLuint id = built.program.id();
        for (GLint i = 0; i < active_resources(id, GL_UNIFORM); ++i) {
            const GLuint index = GLuint(i);
            if (resource_property(id, GL_UNIFORM, index, GL_BLOCK_INDEX) != -1) continue;  // a block member
            const std::string name = resource_name(id, GL_UNIFORM, index);
            ASSERT_EQ(name.rfind("u_", 0), 0u) << built.name << ": uniform " << name << " is not named u_*";
            const GLint type = resource_property(id, GL_UNIFORM, index, GL_TYPE);
            const GLint location = resource_property(id, GL_UNIFORM, index, GL_LOCATION);
            EXPECT_EQ(glGetUniformLocation(id, name.c_str()), location);
            if (type == GL_SAMPLER_2D || type == GL_SAMPLER_2D_SHADOW || type == GL_SAMPLER_2D_MULTISAMPLE ||
                type == GL_IMAGE_2D) {
                GLint unit = -1;  // layout(binding = N): the sampler's or image's initial value
                glGetUniformiv(id, location, &unit);
                expect(built.name, (type == GL_IMAGE_2D ? "image/" : "unit/") + name.substr(2), unit);
            } else {
                // An array is named by its first element, "u_ggx_levels[0]"; its location is the table's.
                const std::string array = name.ends_with("[0]") ? name.substr(0, name.size() - 3) : name;
                expect(built.name, "loc/" + array.substr(2), location);
            }
        }
        for (GLenum block_interface : {GL_SHADER_STORAGE_BLOCK, GL_UNIFORM_BLOCK})
            for (GLint i = 0; i < active_resources(id, block_interface); ++i) {
                const std::string name = resource_name(id, block_interface, GLuint(i));
                expect(built.name, "binding/" + snake_case(name),
                       resource_property(id, block_interface, GLuint(i), GL_BUFFER_BINDING));
            }
        for (GLint i = 0; i < active_resources(id, GL_PROGRAM_INPUT); ++i) {
            const std::string name = resource_name(id, GL_PROGRAM_INPUT, GLuint(i));
            if (name.rfind("gl_", 0) == 0) continue;  // built-ins
            ASSERT_EQ(name.rfind("a_", 0), 0u) << built.name << ": input " << name << " is not named a_*";
            expect(built.name, "attrib/" + name.substr(2),
                   resource_property(id, GL_PROGRAM_INPUT, GLuint(i), GL_LOCATION));
        }
    }
    for (const auto& [key, value] : table) {
        if (key.rfind("size/", 0) == 0) continue;  // sizes: WorkGroupsAreTheTablesSizes and the C++ side
        EXPECT_TRUE(used.count(key)) << key << " is in the table but no program uses it";
    }
}

// shade.frag builds with any of the options renderer.cpp's build_programs sets, alone, in every pair and
// all together, each with the diffuse-only and flat-receiver defines too: each option's #if sits in its
// own include, so a combination that no other test draws could still break. (All 2048 combinations take
// a minute on llvmpipe; pairs catch an #if that assumes another option on or off.)
TEST_P(ShaderInterfaceTest, ShadeBuildsWithEveryPairOfOptions) {
    const gl::ShaderLibrary library = render::embedded_shaders();
    const std::vector<gl::ShaderStage> shade = {{GL_VERTEX_SHADER, "shade.vert"}, {GL_FRAGMENT_SHADER, "shade.frag"}};
    const std::vector<std::string> options = {
        "LIGHTS_UNIFORM_BLOCK", "DIFFUSE_CAP",   "SPECULAR_SINGLE",    "PCF_WIDE",
        "SHADOW_TILE_LISTS",    "SHADING_RATIO", "SOFT_SHADOWS",       "SHADOWED_FRACTION_OUT",
        "ALPHA_TEST",           "ALPHA_BLEND",   "TRANSLUCENT_SHADOWS"};
    const unsigned all = (1u << options.size()) - 1;
    int built = 0;
    for (unsigned mask = 0; mask <= all; ++mask) {
        if (std::popcount(mask) > 2 && mask != all) continue;
        std::vector<std::string> defines;
        for (std::size_t bit = 0; bit < options.size(); ++bit)
            if (mask & (1u << bit)) defines.push_back(options[bit]);
        // The material's programs (Renderer::ShadePrograms).
        for (const std::vector<std::string>& material : std::vector<std::vector<std::string>>{
                 {}, {"DIFFUSE_ONLY"}, {"DIFFUSE_ONLY", "FLAT_RECEIVER"}, {"METALLIC_ROUGHNESS"}}) {
            std::vector<std::string> all_defines = defines;
            all_defines.insert(all_defines.end(), material.begin(), material.end());
            std::string name;
            for (const std::string& define : all_defines) name += define + " ";
            EXPECT_NO_THROW(library.build(shade, all_defines)) << name;
            ++built;
        }
    }
    EXPECT_EQ(built, 4 * (1 + 11 + 55 + 1));
}

TEST_P(ShaderInterfaceTest, WorkGroupsAreTheTablesSizes) {
    const gl::ShaderLibrary library = render::embedded_shaders();
    auto work_group = [&](const char* file) {
        const gl::Program program = library.build({{GL_COMPUTE_SHADER, file}});
        GLint size[3] = {0, 0, 0};
        glGetProgramiv(program.id(), GL_COMPUTE_WORK_GROUP_SIZE, size);
        return std::vector<GLint>{size[0], size[1], size[2]};
    };
    using namespace render::shader;
    EXPECT_EQ(work_group("shadow_tiles.comp"), (std::vector<GLint>{size::screen_tile, size::screen_tile, 1}));
    EXPECT_EQ(work_group("fs_importance.comp"), (std::vector<GLint>{size::fs_work_group, 1, 1}));
    EXPECT_EQ(work_group("fs_lights.comp"), (std::vector<GLint>{size::fs_work_group, 1, 1}));
    EXPECT_EQ(work_group("fs_cell_assign.comp"), (std::vector<GLint>{size::fs_work_group, 1, 1}));
    EXPECT_EQ(work_group("fs_cell_integrate.comp"), (std::vector<GLint>{size::fs_work_group, 1, 1}));
}

TEST_P(ShaderInterfaceTest, EveryStageGetsEveryDefineRightAfterItsVersion) {
    const gl::ShaderLibrary library = render::embedded_shaders();
    std::string table_defines;
    for (const render::shader::Constant& c : render::shader::constants())
        table_defines += "#define " + c.define_name() + " " + std::to_string(c.value) + "\n";
    int stages = 0;
    for (const glsl::File& file : glsl::files()) {
        const std::string source = file.source;
        if (source.rfind("#version", 0) != 0 && source.find("\n#version") == std::string::npos) continue;  // an include
        ++stages;
        const std::string text = library.assemble(file.name).text;
        const std::size_t after_version = text.find('\n') + 1;
        EXPECT_EQ(text.compare(after_version, table_defines.size(), table_defines), 0) << file.name;
    }
    EXPECT_GE(stages, 16);  // the engine's and the tests' stages
}

ENVSHADOW_INSTANTIATE_GL_TEST(ShaderInterfaceTest);

}  // namespace
}  // namespace envshadow::testing
