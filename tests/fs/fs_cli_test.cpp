// `envshadow render --method fs-gpu` end to end on both headless backends, on the default scene under
// builtin:sky: it renders, says what the GPU sampler made, gives the same image twice, a different one
// when --time moves the sun, and the same one for the same time of day reached through the spec's time
// and --time (one hour per second).
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <string>

#include <gtest/gtest.h>

#include "core/image.h"

namespace envshadow {
namespace {

namespace fs = std::filesystem;

std::string run(const std::string& command, int& status) {
    std::string output;
    FILE* pipe = popen((command + " 2>&1").c_str(), "r");
    char buffer[4096];
    while (pipe && fgets(buffer, sizeof buffer, pipe)) output += buffer;
    status = pipe ? pclose(pipe) : -1;
    return output;
}

class FsGpuCli : public ::testing::TestWithParam<const char*> {};

// Renders the default scene under `env` at `time`; returns the EXR.
Image render(const char* backend, const std::string& env, double time, const std::string& name) {
    const fs::path exr = fs::path(ENVSHADOW_BINARY_DIR) / "fs" / (name + "_" + backend + ".exr");
    fs::create_directories(exr.parent_path());
    int status = 0;
    const std::string output =
        run(std::string(ENVSHADOW_EXE) + " render --scene " + ENVSHADOW_SOURCE_DIR + "/assets/scenes/default.json" +
                " --env " + env + " --method fs-gpu --lights 32 --width 160 --height 90 --backend " + backend +
                " --time " + std::to_string(time) + " --exr " + exr.string(),
            status);
    EXPECT_EQ(status, 0) << output;
    EXPECT_NE(output.find("fs-gpu: "), std::string::npos) << output;
    return read_exr(exr).image;
}

double mean_abs_difference(const Image& a, const Image& b) {
    double sum = 0.0;
    for (size_t p = 0; p < a.pixels.size(); ++p)
        for (int c = 0; c < 3; ++c) sum += std::abs(double(a.pixels[p][c]) - double(b.pixels[p][c]));
    return sum / double(3 * a.pixels.size());
}

double mean(const Image& a) {
    double sum = 0.0;
    for (const glm::vec4& p : a.pixels) sum += (p.r + p.g + p.b) / 3.0;
    return sum / double(a.pixels.size());
}

TEST_P(FsGpuCli, RendersAndBuiltinSkyFollowsTime) {
    const Image morning = render(GetParam(), "builtin:sky", -3.0, "morning");
    const Image morning_again = render(GetParam(), "builtin:sky", -3.0, "morning_again");
    const Image afternoon = render(GetParam(), "builtin:sky", 3.0, "afternoon");
    const Image afternoon_from_spec = render(GetParam(), "builtin:sky:time=9", 6.0, "afternoon_from_spec");
    ASSERT_EQ(morning.pixels.size(), size_t(160 * 90));
    ASSERT_EQ(afternoon.pixels.size(), morning.pixels.size());
    EXPECT_EQ(mean_abs_difference(morning, morning_again), 0.0);               // deterministic
    EXPECT_GT(mean_abs_difference(morning, afternoon), 0.05 * mean(morning));  // the sun moved
    EXPECT_EQ(mean_abs_difference(afternoon, afternoon_from_spec), 0.0);       // 12 h + 3 h = 9 h + 6 h
}

INSTANTIATE_TEST_SUITE_P(Headless, FsGpuCli, ::testing::Values("egl", "osmesa"));

}  // namespace
}  // namespace envshadow
