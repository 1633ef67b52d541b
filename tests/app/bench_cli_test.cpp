// `envshadow bench` end to end on both headless backends: a two-point sweep, and the table printed
// for people agrees with the JSON written for machines.
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

namespace envshadow {
namespace {

namespace fs = std::filesystem;

std::string run(const std::string& command, int& status) {
    std::string output;
    FILE* pipe = popen(command.c_str(), "r");
    char buffer[4096];
    while (pipe && fgets(buffer, sizeof buffer, pipe)) output += buffer;
    status = pipe ? pclose(pipe) : -1;
    return output;
}

class BenchCli : public ::testing::TestWithParam<const char*> {};

TEST_P(BenchCli, SweepTableAndJsonAgree) {
    const fs::path json = fs::path(ENVSHADOW_BINARY_DIR) / "bench" / (std::string("bench_") + GetParam() + ".json");
    fs::create_directories(json.parent_path());
    fs::remove(json);
    const std::string command = std::string(ENVSHADOW_EXE) + " bench --scene " + ENVSHADOW_SOURCE_DIR +
                                "/assets/scenes/flyover.json --sweep lights=8,16 --frames 3 --warmup 1 "
                                "--width 160 --height 96 --tile 128 --backend " + GetParam() + " --json " + json.string() +
                                " 2>/dev/null";
    int status = 0;
    const std::string table = run(command, status);
    ASSERT_EQ(status, 0) << command << "\n" << table;
    const nlohmann::json result = nlohmann::json::parse(std::ifstream(json));
    ASSERT_EQ(result["rows"].size(), 2u);
    EXPECT_NE(result["renderer"].get<std::string>(), "");
    EXPECT_EQ(result["triangles"].get<int>(), 30042);
    for (const auto& row : result["rows"]) {
        const std::string setting = row["setting"];
        // The table's row for this setting: "lights=8   8  <drawn> 128  160x96  <median> / <p95> ..."
        std::istringstream lines(table);
        std::string line, found;
        while (std::getline(lines, line))
            if (line.rfind(setting + " ", 0) == 0) found = line;
        ASSERT_FALSE(found.empty()) << setting << " missing from\n" << table;
        std::istringstream fields(found);
        std::string label, resolution, slash;
        int n = 0, drawn = 0, tile = 0;
        double median = 0, p95 = 0, fps = 0;
        fields >> label >> n >> drawn >> tile >> resolution >> median >> slash >> p95 >> fps;
        EXPECT_EQ(n, row["lights"].get<int>());
        EXPECT_EQ(drawn, row["lights_drawn"].get<int>());
        EXPECT_EQ(tile, 128);
        EXPECT_EQ(resolution, "160x96");
        EXPECT_NEAR(median, row["frame_ms"]["median"].get<double>(), 0.006);
        EXPECT_NEAR(p95, row["frame_ms"]["p95"].get<double>(), 0.006);
        EXPECT_NEAR(fps, row["fps"]["median"].get<double>(), 0.06);
        EXPECT_LE(row["frame_ms"]["median"].get<double>(), row["frame_ms"]["p95"].get<double>());
        // Every pass was timed on the GPU, and the shadow atlas was drawn every frame.
        EXPECT_GT(row["gpu_ms"]["shadow atlas"]["median"].get<double>(), 0.0);
        EXPECT_GT(row["gpu_ms"]["shading"]["median"].get<double>(), 0.0);
    }
    EXPECT_EQ(result["rows"][0]["lights"].get<int>(), 8);
    EXPECT_EQ(result["rows"][1]["lights"].get<int>(), 16);
}

INSTANTIATE_TEST_SUITE_P(Backends, BenchCli, ::testing::Values("egl", "osmesa"));

}  // namespace
}  // namespace envshadow
