// `envshadow bench` end to end on both headless backends: a two-point sweep, and the table printed
// for people agrees with the JSON written for machines.
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>

#include <sys/wait.h>

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
                                "--width 160 --height 96 --tile 128 --backend " +
                                GetParam() + " --json " + json.string() + " 2>/dev/null";
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
    // Flyover stands on a ground, so by default (--hemisphere auto) only the upper hemisphere is cut
    // into cells and every cell asked for is drawn (with the full sphere about 40% lie below it).
    EXPECT_NE(table.find("upper hemisphere"), std::string::npos) << table;
    for (const auto& row : result["rows"]) EXPECT_EQ(row["lights_drawn"].get<int>(), row["lights"].get<int>());
}

// --method fs-gpu: no decomposition; the GPU sampler runs before every frame on the importance map asked
// for (the CPU method's blocks, or a size), and its wall time is a column of its own, inside the frame's.
TEST_P(BenchCli, GpuSamplingIsTimedEveryFrameAtEachImportanceSize) {
    for (const std::string size : {"blocks", "256x128", "1024x512"}) {
        const fs::path json =
            fs::path(ENVSHADOW_BINARY_DIR) / "bench" / ("bench_fs_" + size + "_" + GetParam() + ".json");
        fs::create_directories(json.parent_path());
        fs::remove(json);
        const std::string command = std::string(ENVSHADOW_EXE) + " bench --scene " + ENVSHADOW_SOURCE_DIR +
                                    "/assets/scenes/flyover.json --env builtin:sky --method fs-gpu --fs-importance " +
                                    size +
                                    " --lights 32 --frames 2 --warmup 1 --width 160 --height 96 --tile 128 --backend " +
                                    GetParam() + " --json " + json.string() + " 2>&1";
        int status = 0;
        const std::string table = run(command, status);
        ASSERT_EQ(status, 0) << command << "\n" << table;
        const nlohmann::json result = nlohmann::json::parse(std::ifstream(json));
        EXPECT_EQ(result["method"], "fs-gpu");
        EXPECT_EQ(result["fs_importance"], size);
        const auto& row = result["rows"][0];
        EXPECT_EQ(row["decompose_ms"].get<double>(), 0.0);
        EXPECT_GT(row["lights_drawn"].get<int>(), 0);
        const double sampling = row["gpu_ms"]["fs-gpu sampling (wall)"]["median"];
        EXPECT_GT(sampling, 0.0);
        EXPECT_LT(sampling, row["frame_ms"]["median"].get<double>());
    }
    int status = 0;
    const std::string bad =
        run(std::string(ENVSHADOW_EXE) + " bench --scene " + ENVSHADOW_SOURCE_DIR +
                "/assets/scenes/flyover.json --method fs-gpu --fs-importance 100x50 --frames 1 2>&1",
            status);
    EXPECT_EQ(WEXITSTATUS(status), 2) << bad;
    EXPECT_NE(bad.find("--fs-importance"), std::string::npos) << bad;
}

INSTANTIATE_TEST_SUITE_P(Backends, BenchCli, ::testing::Values("egl", "osmesa"));

}  // namespace
}  // namespace envshadow
