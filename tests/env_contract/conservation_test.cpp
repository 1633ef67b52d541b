// On the eight blender-data maps and the builtins, every method at every N of
// {1, 16, 64, 128, 256} conserves the integral and the sphere, and every cell is what docs/DESIGN.md §3 says
// (contract_helpers.h: expect_cells_contract). One test per map and method, the five N inside it.
#include <cctype>
#include <ostream>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "contract_helpers.h"

namespace envshadow::contract {
namespace {

struct MapAndMethod {
    std::string spec;
    Method method;
};
// Readable ctest names: "courtyard.exr lloyd" rather than the bytes of the tuple.
void PrintTo(const MapAndMethod& c, std::ostream* out) {
    *out << c.spec.substr(c.spec.rfind('/') + 1) << " " << to_string(c.method);
}

// The eight maps and the two builtins with every method; two more skies (the sun's disc straddling the
// u = 0/1 seam, and covering the zenith's tiny texels) with every method but CCVT, which takes seconds
// per sky (seam_test.cpp covers its seam on the blender maps).
std::vector<MapAndMethod> conservation_cases() {
    std::vector<std::string> specs;
    for (const char* name : kBlenderMaps) specs.push_back(blender_map(name));
    specs.push_back("builtin:constant");
    specs.push_back("builtin:sky");
    std::vector<MapAndMethod> cases;
    for (const std::string& spec : specs)
        for (Method method : kAllMethods) cases.push_back({spec, method});
    for (const char* spec : {"builtin:sky:azimuth=0,elevation=20", "builtin:sky:elevation=89.5,size=3"})
        for (Method method : kAllMethods)
            if (method != Method::ccvt) cases.push_back({spec, method});
    return cases;
}

class EnvContractConservation : public ::testing::TestWithParam<MapAndMethod> {};

TEST_P(EnvContractConservation, EveryNConservesAndCellsMatchTheirTexels) {
    const auto& [spec, method] = GetParam();
    const EnvironmentMap& map = cached_map(spec);
    for (int lights : kIssueCounts) {
        const Decomposition d = decompose(map, {.method = method, .lights = lights, .seed = 7});
        const std::string context = describe(spec, method, lights);
        EXPECT_EQ(d.method, method) << context;
        EXPECT_TRUE(count_as_promised(method, lights, d.cells.size()))
            << context << ": " << d.cells.size()
            << " cells (lloyd, ccvt, random: N; mediancut: 2^floor(log2 N); fs: N or N - 1)";
        EXPECT_LE(std::abs(long(d.cells.size()) - lights), method == Method::mediancut ? lights : 2)
            << context << ": the issue allows N ± 2 for fs";
        EXPECT_FALSE(d.uniform_importance) << context << ": the map is not black";
        expect_cells_contract(map, d, context);
    }
}

std::string map_and_method_name(const ::testing::TestParamInfo<MapAndMethod>& info) {
    std::string spec = info.param.spec;
    if (const auto slash = spec.rfind('/'); slash != std::string::npos) spec = spec.substr(slash + 1);
    std::string name;
    for (char c : spec) name += std::isalnum(static_cast<unsigned char>(c)) ? c : '_';
    return name + "_" + std::string(to_string(info.param.method));
}

INSTANTIATE_TEST_SUITE_P(MapsAndMethods, EnvContractConservation, ::testing::ValuesIn(conservation_cases()),
                         map_and_method_name);

// White furnace: a uniform sphere of radiance R carries 4πR in every channel, whatever the cutting.
TEST(EnvContractWhiteFurnace, ConstantMapSumsToFourPiPerChannel) {
    for (const auto& [spec, radiance] :
         {std::pair<std::string, double>{"builtin:constant", 1.0}, {"builtin:constant:2.5", 2.5}}) {
        const EnvironmentMap& map = cached_map(spec);
        for (Method method : kAllMethods)
            for (int lights : kIssueCounts) {
                const Decomposition d = decompose(map, {.method = method, .lights = lights});
                glm::dvec3 sum(0.0);
                for (const Cell& cell : d.cells) sum += glm::dvec3(cell.radiance);
                for (int c = 0; c < 3; ++c)
                    EXPECT_NEAR(sum[c], kFourPi * radiance, 1e-4 * kFourPi * radiance)
                        << describe(spec, method, lights) << " channel " << c;
            }
    }
}

}  // namespace
}  // namespace envshadow::contract
