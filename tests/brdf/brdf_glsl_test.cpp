// glsl/brdf.glsl against its C++ twin (engine/env/brdf.cpp, itself checked against numerical
// integration in brdf_test.cpp): glsl/brdf_probe.comp evaluates the three averages over a grid of
// inputs into an SSBO; every value must agree to 1e-4 relative, or within an absolute floor (the
// averages lie in [0, 1]): 1e-6 for the specular ones, 2e-5 for the clamped cosine, whose exact value
// near a cap that touches the horizon is a float cancellation of terms of order 1.
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <glm/vec4.hpp>
#include <numbers>
#include <vector>

#include "env/brdf.h"
#include "gl/objects.h"
#include "gl_fixture.h"

namespace envshadow::testing {
namespace {

constexpr double kPi = std::numbers::pi;
constexpr double kRelative = 1e-4;
constexpr double kAbsolute[3] = {1e-6, 1e-6, 2e-5};  // blended, single, clamped cosine

// x: cos psi_c, y: cos r, z: n, w: cos theta_c (brdf_probe.comp's layout).
std::vector<glm::vec4> probe_inputs() {
    std::vector<float> cos_rs;
    for (double r : {1e-3, 0.005, 0.01, 0.02, 0.05, 0.1, kPi / 8.0, 0.7, 1.2, kPi / 2.0, 2.0, 2.8})
        cos_rs.push_back(float(std::cos(r)));
    cos_rs.push_back(1.0f);
    cos_rs.push_back(-1.0f);
    std::vector<float> cosines;  // for both cos psi_c and cos theta_c: dense near 1 (the lobe) and 0 (the horizon)
    for (int k = 0; k <= 64; ++k) cosines.push_back(float(std::cos(kPi * k / 64.0)));
    for (double angle : {1e-4, 5e-4, 2e-3, 0.008, 0.015, 0.03}) cosines.push_back(float(std::cos(angle)));
    for (double offset : {-0.02, -0.005, -1e-3, -1e-4, 1e-4, 1e-3, 0.005, 0.02}) cosines.push_back(float(offset));

    std::vector<glm::vec4> inputs;
    for (float n : {1.0f, 10.0f, 100.0f, 1000.0f, 10000.0f}) {
        for (float cos_r : cos_rs) {
            std::vector<float> cs = cosines;
            cs.push_back(cos_r);                               // on the rim
            cs.push_back(std::nextafter(cos_r, 2.0f));         // just inside
            cs.push_back(float(0.5 * (1.0 + double(cos_r))));  // halfway
            for (size_t k = 0; k < cs.size(); ++k) {
                // cos theta_c runs over the same values in another order, so every pair of cap and
                // centre is met across the shininess loop.
                const float t = cosines[(k * 7 + size_t(n) % 13) % cosines.size()];
                inputs.push_back({cs[k], cos_r, n, t});
            }
        }
    }
    return inputs;
}

using BrdfGlslTest = GlTest;

TEST_P(BrdfGlslTest, GlslAveragesEqualTheCppTwin) {
    const std::vector<glm::vec4> inputs = probe_inputs();
    const auto count = GLuint(inputs.size());
    gl::Program program = project_shaders().build({{GL_COMPUTE_SHADER, "brdf_probe.comp"}});
    const std::vector<glm::vec4> outputs = run_compute_probe(program, inputs, count);

    const char* names[] = {"average_specular_blended", "average_specular_single", "average_clamped_cosine"};
    double worst[3] = {0.0, 0.0, 0.0};  // relative error, over values above the floor
    int failures = 0;
    for (size_t k = 0; k < inputs.size(); ++k) {
        const glm::vec4 in = inputs[k];
        const double expected[3] = {brdf::average_specular_blended(in.x, in.y, in.z),
                                    brdf::average_specular_single(in.x, in.z),
                                    brdf::average_clamped_cosine(in.w, in.y)};
        for (int f = 0; f < 3; ++f) {
            const double got = outputs[k][f], want = expected[f];
            const double error = std::abs(got - want);
            if (want > kAbsolute[f]) worst[f] = std::max(worst[f], error / want);
            if (!(error <= kRelative * want + kAbsolute[f]) && ++failures <= 4000) {
                ADD_FAILURE() << names[f] << ": GLSL " << got << ", C++ " << want << " (rel " << error / want
                              << ") for cos_psi_c=" << in.x << " cos_r=" << in.y << " n=" << in.z
                              << " cos_theta_c=" << in.w;
            }
        }
    }
    EXPECT_EQ(failures, 0) << "of " << inputs.size() << " inputs";
    std::printf(
        "worst relative error over %zu inputs (values above the floor): blended %.3g, single %.3g, "
        "clamped cosine %.3g\n",
        inputs.size(), worst[0], worst[1], worst[2]);
}

ENVSHADOW_INSTANTIATE_GL_TEST(BrdfGlslTest);

}  // namespace
}  // namespace envshadow::testing
