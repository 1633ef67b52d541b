// glsl/ggx.glsl against its C++ twin (engine/env/gltf_brdf.h: GGX's D and Smith's visibility): glsl/ggx_probe.comp
// evaluates them over a grid of inputs into an SSBO.
#include <cmath>
#include <vector>

#include <glm/vec4.hpp>

#include "env/gltf_brdf.h"
#include "gl/objects.h"
#include "gl_fixture.h"

namespace envshadow::testing {
namespace {

// x: cos theta_h, y: n.l, z: n.v, w: alpha^2 (ggx_probe.comp's layout): angles in multiples of alpha
// about the peak and across the hemisphere, every n.l with a n.v of its own.
std::vector<glm::vec4> probe_inputs() {
    constexpr double kCosines[] = {0.02, 0.1, 0.3, 0.6, 1.0};
    std::vector<glm::vec4> inputs;
    for (double alpha : {1e-3, 0.01, 0.09, 0.2, 0.5, 0.7, 0.9, 0.95, 0.99, 1.0}) {
        std::vector<double> angles = {0.3, 0.6, 1.0, 1.4};  // theta_h
        for (double multiple : {0.0, 0.25, 0.5, 1.0, 2.0, 4.0, 8.0, 16.0})
            if (multiple * alpha < 1.5) angles.push_back(multiple * alpha);
        std::size_t k = 0;
        for (double angle : angles)
            for (double n_dot_l : kCosines)
                inputs.push_back(
                    glm::vec4(float(std::cos(angle)), float(n_dot_l), float(kCosines[k++ % 5]), float(alpha * alpha)));
    }
    return inputs;
}

using GgxGlslTest = GlTest;

TEST_P(GgxGlslTest, GlslLobesEqualTheCppTwin) {
    const std::vector<glm::vec4> inputs = probe_inputs();
    gl::Program program = project_shaders().build({{GL_COMPUTE_SHADER, "ggx_probe.comp"}});
    const std::vector<glm::vec4> outputs = run_compute_probe(program, inputs, GLuint(inputs.size()));

    int failures = 0;
    const auto check = [&](const char* name, double got, double want, double tolerance, const glm::vec4& in) {
        if (std::abs(got - want) <= tolerance) return;
        if (++failures <= 40)
            ADD_FAILURE() << name << ": GLSL " << got << ", expected " << want << " for cos theta_h=" << in.x
                          << " n.l=" << in.y << " n.v=" << in.z << " alpha^2=" << in.w;
    };
    for (std::size_t i = 0; i < inputs.size(); ++i) {
        const glm::vec4 in = inputs[i];
        const double alpha = std::sqrt(double(in.w));
        const double peak = gltf_brdf::ggx_distribution(1.0, alpha);
        const double d = gltf_brdf::ggx_distribution(in.x, alpha);
        check("ggx_distribution", outputs[i].x, d, 2e-4 * d + 1e-6 * peak, in);
        const double v = gltf_brdf::smith_visibility(in.y, in.z, alpha);
        check("smith_visibility", outputs[i].y, v, 1e-4 * v, in);
    }
    EXPECT_EQ(failures, 0) << "of " << inputs.size() << " inputs";
}

ENVSHADOW_INSTANTIATE_GL_TEST(GgxGlslTest);

}  // namespace
}  // namespace envshadow::testing
