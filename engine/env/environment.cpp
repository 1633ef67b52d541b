// Loading lat-long environment maps: OpenEXR, Radiance .hdr, and maps generated in code (builtin:).
#include "env/environment.h"

#include <stb_image.h>
#include <tbb/parallel_for.h>

#include <array>
#include <charconv>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <numbers>
#include <string_view>

#include "core/error.h"
#include "core/image.h"
#include "env/latlong.h"

namespace envshadow {
namespace {

// Larger finite values count as invalid: a cell's radiance (float) must stay finite.
constexpr float kMaxRadiance = 1e30f;
constexpr int kMaxHeight = kMaxEnvironmentWidth / 2;

void check_shape(const std::string& name, long long width, long long height) {
    if (width < 2 || height < 1 || width > kMaxEnvironmentWidth || height > kMaxHeight)
        throw InputError(name + ": map size " + std::to_string(width) + "x" + std::to_string(height) +
                         " is outside the accepted 2x1.." + std::to_string(kMaxEnvironmentWidth) + "x" +
                         std::to_string(kMaxHeight));
    if (width != 2 * height)
        throw InputError(name + ": map size " + std::to_string(width) + "x" + std::to_string(height) +
                         " is not a lat-long map (width must be twice the height)");
}

// Negative components (real photographs carry small ones) become 0; NaN, infinite and absurdly large
// ones are an error unless the caller asked to clamp them too.
// Row by row in parallel: also the process's first parallel work, so the thread pool starts here
// rather than inside the timed decomposition that follows.
void sanitise(EnvironmentMap& map, const EnvironmentLoadOptions& options, EnvironmentLoadReport& report) {
    std::vector<EnvironmentLoadReport> rows(static_cast<size_t>(map.height));
    tbb::parallel_for(0, map.height, [&](int j) {
        EnvironmentLoadReport& row = rows[size_t(j)];
        for (int i = 0; i < map.width; ++i)
            for (int c = 0; c < 3; ++c) {
                float& v = map.at(i, j)[c];
                if (!std::isfinite(v) || v > kMaxRadiance) {
                    ++row.invalid_clamped;
                    v = 0.0f;
                } else if (v < 0.0f) {
                    ++row.negative_clamped;
                    v = 0.0f;
                }
            }
    });
    for (const EnvironmentLoadReport& row : rows) {
        report.invalid_clamped += row.invalid_clamped;
        report.negative_clamped += row.negative_clamped;
    }
    if (report.invalid_clamped > 0 && !options.clamp_invalid)
        throw InputError(map.source + ": " + std::to_string(report.invalid_clamped) +
                         " texel values are NaN, infinite or above 1e30 (--clamp-invalid sets them to 0)");
}

// The shape is checked as soon as the reader knows the size: a 16384 x 16383 picture is within
// read_exr's limits (4 GiB of pixels) but no map, and must be refused before it is allocated.
EnvironmentMap load_exr(const std::string& path) {
    const ExrContents exr = read_exr(path, [&](int width, int height) { check_shape(path, width, height); });
    EnvironmentMap map;
    map.width = exr.image.width;
    map.height = exr.image.height;
    map.source = path;
    map.texels.resize(exr.image.pixels.size());
    for (size_t t = 0; t < map.texels.size(); ++t) map.texels[t] = glm::vec3(exr.image.pixels[t]);
    return map;
}

// core's checked reader, not stb_image: Debian's stb_image 2.27 loops for ever on a run-length
// scanline cut short (CVE-2021-42715).
EnvironmentMap load_radiance_hdr(const std::string& path) {
    const Image image = read_radiance_hdr(path, [&](int width, int height) { check_shape(path, width, height); });
    EnvironmentMap map;
    map.width = image.width;
    map.height = image.height;
    map.source = path;
    map.texels.resize(image.pixels.size());
    for (size_t t = 0; t < map.texels.size(); ++t) map.texels[t] = glm::vec3(image.pixels[t]);
    return map;
}

EnvironmentMap load_file(const std::string& path) {
    std::error_code ec;  // opening a FIFO would block for ever, a device never end
    if (!std::filesystem::is_regular_file(path, ec)) throw InputError(path + ": file not found or not a regular file");
    std::ifstream in(path, std::ios::binary);
    if (!in) throw InputError(path + ": file not found or not readable");
    std::array<char, 4> magic{};
    in.read(magic.data(), magic.size());
    if (in.gcount() == 4 && (unsigned char)magic[0] == 0x76 && (unsigned char)magic[1] == 0x2f &&
        (unsigned char)magic[2] == 0x31 && (unsigned char)magic[3] == 0x01)
        return load_exr(path);
    if (in.gcount() >= 2 && magic[0] == '#' && magic[1] == '?') return load_radiance_hdr(path);
    throw InputError(path + ": not an OpenEXR or Radiance HDR file");
}

// --- builtin: ------------------------------------------------------------------------------------

double parse_number(const std::string& spec, std::string_view key, std::string_view text) {
    double value = 0.0;
    const auto [end, error] = std::from_chars(text.data(), text.data() + text.size(), value);
    if (error != std::errc() || end != text.data() + text.size() || !std::isfinite(value))
        throw InputError(spec + ": '" + std::string(text) + "' is not a number (" + std::string(key) + ")");
    return value;
}

void check_range(const std::string& spec, std::string_view key, double value, double lo, double hi) {
    if (value < lo || value > hi)
        throw InputError(spec + ": " + std::string(key) + "=" + std::to_string(value) + " is outside " +
                         std::to_string(lo) + ".." + std::to_string(hi));
}

EnvironmentMap blank_map(const std::string& spec, int width) {
    EnvironmentMap map;
    map.width = width;
    map.height = width / 2;
    map.source = spec;
    map.texels.assign(size_t(map.width) * size_t(map.height), glm::vec3(0.0f));
    return map;
}

EnvironmentMap builtin_constant(const std::string& spec, std::string_view arguments) {
    double radiance = 1.0;
    if (!arguments.empty()) radiance = parse_number(spec, "radiance", arguments);
    check_range(spec, "radiance", radiance, 0.0, kMaxRadiance);
    EnvironmentMap map = blank_map(spec, kConstantEnvironmentWidth);
    std::fill(map.texels.begin(), map.texels.end(), glm::vec3(float(radiance)));
    return map;
}

// The key=value list after "builtin:sky:" (the last of a key counts); `width` is the map's.
SkyParameters parse_sky(const std::string& spec, std::string_view arguments, double& width) {
    SkyParameters sky;
    width = 1024;
    while (!arguments.empty()) {
        const size_t comma = arguments.find(',');
        const std::string_view item = arguments.substr(0, comma);
        arguments = comma == std::string_view::npos ? std::string_view() : arguments.substr(comma + 1);
        const size_t equals = item.find('=');
        if (equals == std::string_view::npos) throw InputError(spec + ": '" + std::string(item) + "' is not key=value");
        const std::string_view key = item.substr(0, equals), text = item.substr(equals + 1);
        const double value = parse_number(spec, key, text);
        if (key == "elevation")
            check_range(spec, key, sky.elevation_degrees = value, -90.0, 90.0);
        else if (key == "azimuth")
            sky.azimuth_degrees = value;
        else if (key == "size")
            check_range(spec, key, sky.size_degrees = value, 0.01, 90.0);
        else if (key == "intensity")
            check_range(spec, key, sky.intensity = value, 0.0, 1e12);
        else if (key == "time")
            sky.time_hours = value;
        else if (key == "width")
            check_range(spec, key, width = value, 2.0, kMaxEnvironmentWidth);
        else
            throw InputError(spec + ": unknown key '" + std::string(key) +
                             "' (elevation, azimuth, size, intensity, time, width)");
    }
    if (width != std::floor(width) || int(width) % 2 != 0) throw InputError(spec + ": width must be an even integer");
    return sky;
}

// builtin:sky's arguments: what follows "builtin:sky:", or nothing.
std::string_view sky_arguments(const std::string& spec) {
    constexpr std::string_view prefix = "builtin:sky:";
    return spec.starts_with(prefix) ? std::string_view(spec).substr(prefix.size()) : std::string_view();
}

EnvironmentMap builtin_sky(const std::string& spec, std::string_view arguments) {
    double width = 0.0;
    const SkyParameters sky = parse_sky(spec, arguments, width);
    EnvironmentMap map = blank_map(spec, int(width));
    render_sky(sky, map);
    return map;
}

EnvironmentMap load_builtin(const std::string& spec) {
    const std::string_view rest = std::string_view(spec).substr(std::string_view("builtin:").size());
    const size_t colon = rest.find(':');
    const std::string_view name = rest.substr(0, colon);
    const std::string_view arguments = colon == std::string_view::npos ? std::string_view() : rest.substr(colon + 1);
    if (name == "constant") return builtin_constant(spec, arguments);
    if (name == "sky") return builtin_sky(spec, arguments);
    throw InputError(spec + ": unknown builtin environment (builtin:constant, builtin:sky)");
}

}  // namespace

glm::dvec3 sun_direction(const SkyParameters& sky) {
    constexpr double kDegree = std::numbers::pi / 180.0;
    const double e = sky.elevation_degrees * kDegree, a = sky.azimuth_degrees * kDegree;
    const glm::dvec3 noon(std::cos(e) * std::cos(a), std::sin(e), std::cos(e) * std::sin(a));
    const glm::dvec3 east(-std::sin(a), 0.0, std::cos(a));  // horizontal, 90 degrees of azimuth further
    const double h = (sky.time_hours - 12.0) * 15.0 * kDegree;
    return std::cos(h) * noon + std::sin(h) * east;
}

void render_sky(const SkyParameters& sky, EnvironmentMap& map) {
    const glm::dvec3 sun = sun_direction(sky);
    const double sun_radius = 0.5 * sky.size_degrees * std::numbers::pi / 180.0;
    const double cos_sun = std::cos(sun_radius);
    const glm::dvec3 sun_colour = glm::dvec3(1.0, 0.93, 0.82) * sky.intensity;
    const glm::dvec3 horizon(1.00, 0.97, 0.92), zenith(0.28, 0.48, 0.95);
    // The ground is lit by the sky (irradiance ~ pi x its mean radiance) and the sun above the horizon.
    const double sun_solid_angle = 2.0 * std::numbers::pi * (1.0 - cos_sun);
    const glm::dvec3 irradiance =
        glm::dvec3(0.65 * std::numbers::pi) + sun_colour * sun_solid_angle * std::max(0.0, sun.y);
    const glm::dvec3 ground = glm::dvec3(0.12, 0.10, 0.08) * irradiance / std::numbers::pi;

    auto sky_radiance = [&](const glm::dvec3& d) {
        if (d.y < 0.0) return ground;
        const glm::dvec3 gradient = glm::mix(horizon, zenith, std::pow(d.y, 0.5));
        // A soft aureole brightens the sky towards the sun (above the horizon only).
        const double aureole = sun.y > -0.1 ? 0.6 * std::exp((glm::dot(d, sun) - 1.0) * 8.0) : 0.0;
        return gradient * (1.0 + aureole);
    };
    // Texels near the disc average 8 x 8 sub-samples (uniform in u and cos theta, so each carries equal
    // solid angle): the disc's energy is right at any resolution.
    const double texel_angle = std::numbers::pi / map.height;
    const double near_sun = std::cos(std::min(std::numbers::pi, sun_radius + 2.0 * texel_angle));
    for (int j = 0; j < map.height; ++j)
        for (int i = 0; i < map.width; ++i) {
            const glm::dvec3 d = latlong::texel_direction(i, j, map.width, map.height);
            glm::dvec3 value = sky_radiance(d);
            if (glm::dot(d, sun) >= near_sun) {
                constexpr int kSub = 8;
                const double cos_top = std::cos(std::numbers::pi * j / map.height);
                const double cos_bottom = std::cos(std::numbers::pi * (j + 1) / map.height);
                int covered = 0;
                for (int b = 0; b < kSub; ++b)
                    for (int a = 0; a < kSub; ++a) {
                        const double u = (i + (a + 0.5) / kSub) / map.width;
                        const double cos_theta = cos_top + (cos_bottom - cos_top) * (b + 0.5) / kSub;
                        const glm::dvec3 p = latlong::direction(u, std::acos(cos_theta) / std::numbers::pi);
                        if (p.y >= 0.0 && glm::dot(p, sun) >= cos_sun) ++covered;
                    }
                value += sun_colour * (double(covered) / (kSub * kSub));
            }
            map.at(i, j) = glm::vec3(value);
        }
}

std::string environment_at_time(const std::string& spec, double seconds) {
    if (seconds == 0.0 || (spec != "builtin:sky" && !spec.starts_with("builtin:sky:"))) return spec;
    double width = 0.0;
    const double hours = parse_sky(spec, sky_arguments(spec), width).time_hours + seconds;
    return spec + (spec == "builtin:sky" ? ":" : ",") + "time=" + std::to_string(hours);  // the last key wins
}

EnvironmentMap load_environment(const std::string& spec, const EnvironmentLoadOptions& options,
                                EnvironmentLoadReport* report) {
    EnvironmentMap map = spec.starts_with("builtin:") ? load_builtin(spec) : load_file(spec);
    EnvironmentLoadReport local;
    sanitise(map, options, local);
    if (report) *report = local;
    return map;
}

}  // namespace envshadow
