#pragma once
// Lat-long HDR environment maps (row 0 = zenith, W = 2H), from files or generated (`builtin:`).
#include <filesystem>
#include <glm/vec3.hpp>
#include <string>
#include <vector>

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

// Largest map accepted: 16384 x 8192.
inline constexpr int kMaxEnvironmentWidth = 16384;
inline constexpr int kConstantEnvironmentWidth = 256;  // builtin:constant is 256 x 128

// `spec` is a path to an .exr or .hdr file (recognised by content), or a builtin:
//   builtin:constant[:R]                 uniform radiance (default 1): the white-furnace test
//   builtin:sky[:key=value,...]          analytic sky with a sun disc; keys: elevation, azimuth (degrees),
//                                        size (sun angular diameter, degrees), intensity (sun radiance),
//                                        time (hours: moves the sun along its arc), width (map width)
//                                        e.g. builtin:sky:elevation=20,azimuth=90,time=9.5 (SkyParameters)
// Negative components become 0 (counted in the report). Throws InputError (naming the file and the
// reason) for missing, corrupt, wrongly shaped (W != 2H, larger than 16384 x 8192) or non-finite input
// (NaN, Inf, above 1e30; with clamp_invalid these become 0 instead, counted in the report).
EnvironmentMap load_environment(const std::string& spec, const EnvironmentLoadOptions& options = {},
                                EnvironmentLoadReport* report = nullptr);

// The spec of `spec` after `seconds` of animation: builtin:sky's sun advances one hour per second from
// the spec's time (noon by default), so the environment animates with the scene; every other
// environment is returned unchanged. InputError for a builtin:sky spec that does not parse.
std::string environment_at_time(const std::string& spec, double seconds);

// builtin:sky. Azimuth is the lat-long longitude phi = 2 pi u (0 = +X, 90 = +Z). The sun moves on a
// great circle: it rises at 6 h on the horizon at azimuth - 90, culminates at 12 h at (elevation,
// azimuth) and sets at 18 h at azimuth + 90; below the horizon the ground hides it. With the defaults
// the sun's disc carries about two thirds of the integral of L dw (so shadows are clear) over a
// smooth horizon-to-zenith gradient and a dim ground lit by sky and sun.
struct SkyParameters {
    double elevation_degrees = 35.0;
    double azimuth_degrees = 60.0;
    double size_degrees = 1.5;   // angular diameter of the disc
    double intensity = 25000.0;  // radiance of the disc (times a warm white)
    double time_hours = 12.0;
};
glm::dvec3 sun_direction(const SkyParameters& sky);
// Fills `map` (its width and height set, W = 2H).
void render_sky(const SkyParameters& sky, EnvironmentMap& map);

}  // namespace envshadow
