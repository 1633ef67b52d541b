// glsl/tonemap.glsl against its C++ twin (engine/core/tonemap.cpp, image.cpp's srgb_encode):
// glsl/tonemap_probe.comp, built once per operator with its TONEMAP_* define, tone-maps and encodes
// a grid of colours (every channel over 0 .. 100, dark to far past white); every sRGB value must
// agree within 1/255, and the bytes tonemap_to_srgb8 writes within one step.
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <glm/vec4.hpp>
#include <vector>

#include "core/image.h"
#include "core/tonemap.h"
#include "gl/objects.h"
#include "gl_fixture.h"

namespace envshadow::testing {
namespace {

std::vector<glm::vec4> probe_inputs() {
    const float levels[] = {0.0f, 1e-4f, 0.002f, 0.01f, 0.03f, 0.08f, 0.18f, 0.4f,
                            0.7f, 1.0f,  1.6f,   3.0f,  8.0f,  25.0f, 100.0f};
    std::vector<glm::vec4> inputs;
    for (float r : levels)
        for (float g : levels)
            for (float b : levels) inputs.push_back({r, g, b, 1.0f});
    return inputs;
}

using ToneMapGlslTest = GlTest;

TEST_P(ToneMapGlslTest, EveryOperatorEqualsTheCppTwin) {
    const std::vector<glm::vec4> inputs = probe_inputs();
    const auto count = GLuint(inputs.size());
    Image image(int(inputs.size()), 1);
    for (std::size_t k = 0; k < inputs.size(); ++k) image.pixels[k] = inputs[k];
    for (std::size_t op_index = 0; op_index < kToneMapCount; ++op_index) {
        const ToneMap op = ToneMap(op_index);
        SCOPED_TRACE(std::string(to_string(op)));
        gl::Program program =
            project_shaders().build({{GL_COMPUTE_SHADER, "tonemap_probe.comp"}}, {tone_map_define(op)});
        const std::vector<glm::vec4> outputs = run_compute_probe(program, inputs, count);

        const Image8 bytes = tonemap_to_srgb8(image, 0.0f, op);
        double worst = 0.0;
        int failures = 0;
        for (std::size_t k = 0; k < inputs.size(); ++k) {
            const glm::vec3 display = tone_map(op, glm::vec3(inputs[k]));
            for (int c = 0; c < 3; ++c) {
                const double want = srgb_encode(display[c]), got = outputs[k][c];
                worst = std::max(worst, std::abs(got - want));
                const int byte_step = std::abs(int(std::lround(255.0 * got)) - int(bytes.rgba[k * 4 + std::size_t(c)]));
                if ((!(std::abs(got - want) <= 1.0 / 255.0) || byte_step > 1) && ++failures <= 20)
                    ADD_FAILURE() << "GLSL " << got << ", C++ " << want << " (byte "
                                  << int(bytes.rgba[k * 4 + std::size_t(c)]) << ") channel " << c << " of ("
                                  << inputs[k].r << ", " << inputs[k].g << ", " << inputs[k].b << ")";
            }
        }
        EXPECT_EQ(failures, 0) << "of " << inputs.size() << " colours";
        std::printf("%s: worst |GLSL - C++| over %zu colours: %.3g\n", std::string(to_string(op)).c_str(),
                    inputs.size(), worst);
    }
}

ENVSHADOW_INSTANTIATE_GL_TEST(ToneMapGlslTest);

}  // namespace
}  // namespace envshadow::testing
