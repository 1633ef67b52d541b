// `envshadow decompose` through the real executable (docs/DESIGN.md §6): its JSON, its picture, and its exit
// codes (2 for bad usage, 3 for bad input, one line on stderr, no output file left behind). The integral
// is checked against the map's texels read with core's read_exr, not with the code under test.
#include <sys/wait.h>

#include <unistd.h>
#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <numbers>
#include <sstream>
#include <string>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include "core/image.h"
#include "env/latlong.h"

namespace envshadow {
namespace {

namespace fs = std::filesystem;

struct CommandRun {
    int status = -1;
    std::string out, err;
};

std::string slurp(const fs::path& file) {
    std::ifstream in(file);
    std::stringstream text;
    text << in.rdbuf();
    return text.str();
}

// A folder of this test's own (ctest runs tests as parallel processes).
class EnvContractCli : public ::testing::Test {
protected:
    void SetUp() override {
        const auto* info = ::testing::UnitTest::GetInstance()->current_test_info();
        dir_ = fs::path(ENVSHADOW_BINARY_DIR) / "env_contract_cli" /
               (std::string(info->name()) + "_" + std::to_string(::getpid()));
        fs::remove_all(dir_);
        fs::create_directories(dir_);
    }
    void TearDown() override { fs::remove_all(dir_); }

    fs::path file(const std::string& name) const { return dir_ / name; }

    CommandRun decompose(const std::string& arguments) const {
        const std::string command = std::string(ENVSHADOW_EXE) + " decompose " + arguments + " > '" +
                                    file("stdout.txt").string() + "' 2> '" + file("stderr.txt").string() + "'";
        const int raw = std::system(command.c_str());
        return {WIFEXITED(raw) ? WEXITSTATUS(raw) : -1, slurp(file("stdout.txt")), slurp(file("stderr.txt"))};
    }

    // The files a run left besides its own stdout/stderr captures.
    int outputs_left() const {
        int count = 0;
        for (const auto& entry : fs::directory_iterator(dir_))
            count += entry.path().filename() != "stdout.txt" && entry.path().filename() != "stderr.txt";
        return count;
    }

    fs::path dir_;
};

const std::string kCourtyard = "/usr/share/blender/datafiles/studiolights/world/courtyard.exr";

std::string shell_quoted(const fs::path& p) {
    return "'" + p.string() + "'";
}

TEST_F(EnvContractCli, JsonHasTheKeysOfDesignAndConservesTheIntegral) {
    // ∫ L dω of the map, from its texels (docs/DESIGN.md §2's exact texel solid angle).
    const ExrContents exr = read_exr(kCourtyard);
    double integral[3] = {0.0, 0.0, 0.0};
    for (int j = 0; j < exr.image.height; ++j)
        for (int i = 0; i < exr.image.width; ++i)
            for (int c = 0; c < 3; ++c)
                integral[c] += double(std::max(0.0f, exr.image.at(i, j)[c])) *
                               latlong::texel_solid_angle(j, exr.image.width, exr.image.height);

    for (const std::string method : {"lloyd", "ccvt", "mediancut", "random", "fs"}) {
        SCOPED_TRACE(method);
        const fs::path json_file = file(method + ".json"), png_file = file(method + ".png");
        const CommandRun run =
            decompose("--env " + shell_quoted(kCourtyard) + " --lights 16 --method " + method + " --seed 3 --json " +
                      shell_quoted(json_file) + " --png " + shell_quoted(png_file));
        ASSERT_EQ(run.status, 0) << run.out << run.err;
        nlohmann::json j;
        ASSERT_NO_THROW(j = nlohmann::json::parse(slurp(json_file))) << slurp(json_file);
        for (const char* key : {"method", "width", "height", "lights", "integral", "seconds"})
            ASSERT_TRUE(j.contains(key)) << "missing key " << key;
        EXPECT_EQ(j["method"], method);
        EXPECT_EQ(j["width"], 1024);
        EXPECT_EQ(j["height"], 512);
        ASSERT_TRUE(j["seconds"].is_number());
        EXPECT_GE(j["seconds"].get<double>(), 0.0);
        ASSERT_TRUE(j["lights"].is_array());
        EXPECT_GE(j["lights"].size(), method == std::string("fs") ? 15u : 16u);
        EXPECT_LE(j["lights"].size(), 16u);
        double radiance_sum[3] = {0.0, 0.0, 0.0}, solid_angle_sum = 0.0;
        for (const auto& light : j["lights"]) {
            for (const char* key : {"dir", "radiance", "solid_angle", "cos_radius", "cos_radius_weighted"})
                ASSERT_TRUE(light.contains(key)) << "a light without " << key << ": " << light.dump();
            ASSERT_EQ(light["dir"].size(), 3u);
            ASSERT_EQ(light["radiance"].size(), 3u);
            const double x = light["dir"][0], y = light["dir"][1], z = light["dir"][2];
            EXPECT_NEAR(std::sqrt(x * x + y * y + z * z), 1.0, 1e-5);
            for (int c = 0; c < 3; ++c) radiance_sum[c] += light["radiance"][c].get<double>();
            const double solid_angle = light["solid_angle"], cos_radius = light["cos_radius"];
            solid_angle_sum += solid_angle;
            EXPECT_NEAR(cos_radius, 1.0 - solid_angle / (2.0 * std::numbers::pi), 1e-5);
            EXPECT_GE(light["cos_radius_weighted"].get<double>(), -1.0);
            EXPECT_LE(light["cos_radius_weighted"].get<double>(), 1.0);
        }
        ASSERT_EQ(j["integral"].size(), 3u);
        for (int c = 0; c < 3; ++c) {
            EXPECT_NEAR(j["integral"][c].get<double>(), integral[c], 1e-5 * integral[c]) << "integral channel " << c;
            EXPECT_NEAR(radiance_sum[c], integral[c], 1e-4 * integral[c]) << "Σ radiance channel " << c;
        }
        EXPECT_NEAR(solid_angle_sum, 4.0 * std::numbers::pi, 1e-4 * 4.0 * std::numbers::pi);
        const Image8 picture = read_png(png_file);
        EXPECT_EQ(picture.width, 1024);
        EXPECT_EQ(picture.height, 512);
    }
}

// --hemisphere upper: the JSON says so, its integral is the upper hemisphere's (rows 0 ..
// H/2 - 1 of the 512), every light lies above the horizon and the cells cover 2 pi. The default is full.
TEST_F(EnvContractCli, UpperHemisphereIsSaidAndIntegrated) {
    const ExrContents exr = read_exr(kCourtyard);
    double integral[3] = {0.0, 0.0, 0.0};
    for (int j = 0; j < exr.image.height / 2; ++j)
        for (int i = 0; i < exr.image.width; ++i)
            for (int c = 0; c < 3; ++c)
                integral[c] += double(std::max(0.0f, exr.image.at(i, j)[c])) *
                               latlong::texel_solid_angle(j, exr.image.width, exr.image.height);
    const fs::path json_file = file("upper.json"), full_file = file("full.json");
    const CommandRun run = decompose("--env " + shell_quoted(kCourtyard) + " --lights 32 --hemisphere upper --json " +
                                     shell_quoted(json_file));
    ASSERT_EQ(run.status, 0) << run.out << run.err;
    EXPECT_NE(run.out.find("upper hemisphere"), std::string::npos) << run.out;
    const nlohmann::json j = nlohmann::json::parse(slurp(json_file));
    EXPECT_EQ(j["hemisphere"], "upper");
    ASSERT_EQ(j["lights"].size(), 32u);
    double radiance_sum[3] = {0.0, 0.0, 0.0}, solid_angle_sum = 0.0;
    for (const auto& light : j["lights"]) {
        EXPECT_GT(light["dir"][1].get<double>(), 0.0) << light.dump();
        for (int c = 0; c < 3; ++c) radiance_sum[c] += light["radiance"][c].get<double>();
        solid_angle_sum += light["solid_angle"].get<double>();
    }
    for (int c = 0; c < 3; ++c) {
        EXPECT_NEAR(j["integral"][c].get<double>(), integral[c], 1e-5 * integral[c]) << "integral channel " << c;
        EXPECT_NEAR(radiance_sum[c], integral[c], 1e-4 * integral[c]) << "Σ radiance channel " << c;
    }
    EXPECT_NEAR(solid_angle_sum, 2.0 * std::numbers::pi, 1e-4 * 2.0 * std::numbers::pi);

    ASSERT_EQ(decompose("--env " + shell_quoted(kCourtyard) + " --lights 32 --json " + shell_quoted(full_file)).status,
              0);
    EXPECT_EQ(nlohmann::json::parse(slurp(full_file))["hemisphere"], "full");
    const CommandRun bad = decompose("--env builtin:constant --lights 4 --hemisphere lower");
    EXPECT_EQ(bad.status, 2) << bad.out << bad.err;
}

TEST_F(EnvContractCli, BadUsageExitsTwoAndWritesNothing) {
    for (const std::string bad : std::initializer_list<const char*>{
             "--lights 0 --method lloyd", "--lights 1000 --method lloyd", "--lights 16 --method bogus"}) {
        const CommandRun run = decompose("--env builtin:constant " + bad + " --json " + shell_quoted(file("out.json")) +
                                         " --png " + shell_quoted(file("out.png")));
        EXPECT_EQ(run.status, 2) << bad << "\n" << run.out << run.err;
        EXPECT_FALSE(run.err.empty()) << bad << ": no message";
        EXPECT_EQ(outputs_left(), 0) << bad << ": an output file was left";
    }
}

// docs/DESIGN.md §6: a clear one-line message naming the file, exit code 3, no partial output.
TEST_F(EnvContractCli, BadInputExitsThreeWithOneLineNamingTheFile) {
    const fs::path missing = file("no_such_map.exr");
    // A truncated copy of a real map.
    const fs::path truncated = file("truncated.exr");
    {
        std::ifstream in(kCourtyard, std::ios::binary);
        std::string bytes((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
        std::ofstream(truncated, std::ios::binary).write(bytes.data(), std::streamsize(bytes.size() / 3));
    }
    for (const fs::path& bad : {missing, truncated}) {
        const CommandRun run = decompose("--env " + shell_quoted(bad) + " --lights 16 --method lloyd --json " +
                                         shell_quoted(file("out.json")) + " --png " + shell_quoted(file("out.png")));
        EXPECT_EQ(run.status, 3) << bad << "\n" << run.out << run.err;
        EXPECT_NE(run.err.find(bad.string()), std::string::npos) << "stderr does not name the file: " << run.err;
        const auto lines = std::count(run.err.begin(), run.err.end(), '\n');
        EXPECT_EQ(lines, 1) << "stderr should be one line: " << run.err;
        EXPECT_FALSE(fs::exists(file("out.json"))) << bad;
        EXPECT_FALSE(fs::exists(file("out.png"))) << bad;
    }
    fs::remove(truncated);
    EXPECT_EQ(outputs_left(), 0);
}

}  // namespace
}  // namespace envshadow
