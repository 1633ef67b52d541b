#pragma once
// Lat-long HDR environment maps (row 0 = zenith, W = 2H), from files or generated (`builtin:`).
#include <filesystem>
#include <string>
#include <vector>

#include <glm/vec3.hpp>

namespace envshadow {

struct EnvironmentMap {
    int width = 0;
    int height = 0;
    std::vector<glm::vec3> texels;  // linear RGB, finite and >= 0; texel (i, j) at j * width + i
    std::string source;             // file path or builtin spec, for messages

    const glm::vec3& at(int i, int j) const { return texels[size_t(j) * size_t(width) + size_t(i)]; }
    glm::vec3& at(int i, int j) { return texels[size_t(j) * size_t(width) + size_t(i)]; }
};

struct EnvironmentLoadOptions {
    bool clamp_invalid = false;  // NaN/Inf texels become 0 instead of an InputError
};

struct EnvironmentLoadReport {
    long long negative_clamped = 0;  // negative components set to 0 (real photographs have ~-0.003)
    long long invalid_clamped = 0;   // NaN/Inf components set to 0 (only with clamp_invalid)
};

// `spec` is a path to an .exr or .hdr file, or a builtin:
//   builtin:constant[:R]                 uniform radiance (default 1): the white-furnace test
//   builtin:sky[:key=value,...]          analytic sky with a sun disc; keys: elevation, azimuth (degrees),
//                                        size (sun angular diameter, degrees), intensity (sun radiance),
//                                        time (hours: moves the sun along its arc), width (map width)
// Throws InputError (naming the file and the reason) for missing, corrupt, wrongly shaped or
// non-finite input.
EnvironmentMap load_environment(const std::string& spec, const EnvironmentLoadOptions& options = {},
                                EnvironmentLoadReport* report = nullptr);

}  // namespace envshadow
