#include "scene/texture.h"

#include <array>
#include <cmath>

#include <glm/common.hpp>

namespace envshadow {
namespace {

const std::array<float, 256>& srgb_table() {
    static const std::array<float, 256> table = [] {
        std::array<float, 256> t{};
        for (int i = 0; i < 256; ++i) {
            const double c = i / 255.0;
            t[std::size_t(i)] = float(c <= 0.04045 ? c / 12.92 : std::pow((c + 0.055) / 1.055, 2.4));
        }
        return t;
    }();
    return table;
}

// The texel index for integer coordinate i (any integer) under `wrap`, in [0, size).
int wrap_index(long long i, int size, TextureWrap wrap) {
    const long long n = size;
    switch (wrap) {
        case TextureWrap::clamp_to_edge:
            return int(i < 0 ? 0 : i >= n ? n - 1 : i);
        case TextureWrap::mirrored_repeat: {
            const long long period = 2 * n;
            long long k = ((i % period) + period) % period;
            return int(k < n ? k : period - 1 - k);
        }
        case TextureWrap::repeat:
        default:
            return int(((i % n) + n) % n);
    }
}

// Linear RGB (decoded from sRGB where `srgb`) and alpha (linear as stored) of one texel.
glm::vec4 texel(const TextureImage& image, bool srgb, int x, int y) {
    const std::uint8_t* p = &image.rgba[(std::size_t(y) * std::size_t(image.width) + std::size_t(x)) * 4];
    if (!srgb) return glm::vec4(p[0], p[1], p[2], p[3]) / 255.0f;
    const auto& table = srgb_table();
    return {table[p[0]], table[p[1]], table[p[2]], float(p[3]) / 255.0f};
}

// uv beyond this is folded back by whole periods first, so the texel coordinates stay exact in double
// (the wrap modes repeat with period 2 at most).
constexpr double kFoldPeriods = 1e6;

}  // namespace

float srgb8_to_linear(std::uint8_t value) {
    return srgb_table()[value];
}

glm::vec3 sample_linear_rgb(const MaterialTexture& texture, glm::vec2 uv) {
    return glm::vec3(sample_linear_rgba(texture, uv));
}

glm::vec4 sample_linear_rgba(const MaterialTexture& texture, glm::vec2 uv) {
    const TextureImage& image = *texture.image;
    const auto at = [&](int x, int y) { return texel(image, texture.srgb, x, y); };
    double u = uv.x, v = uv.y;
    if (!std::isfinite(u) || !std::isfinite(v)) return at(0, 0);
    if (std::abs(u) > kFoldPeriods) u = std::fmod(u, 2.0);
    if (std::abs(v) > kFoldPeriods) v = std::fmod(v, 2.0);
    const double x = u * image.width - 0.5, y = v * image.height - 0.5;
    if (texture.nearest) {
        const auto xi = static_cast<long long>(std::floor(x + 0.5)), yi = static_cast<long long>(std::floor(y + 0.5));
        return at(wrap_index(xi, image.width, texture.wrap_s), wrap_index(yi, image.height, texture.wrap_t));
    }
    const double x0 = std::floor(x), y0 = std::floor(y);
    const auto fx = float(x - x0), fy = float(y - y0);
    const auto xi = static_cast<long long>(x0), yi = static_cast<long long>(y0);
    const int xa = wrap_index(xi, image.width, texture.wrap_s), xb = wrap_index(xi + 1, image.width, texture.wrap_s);
    const int ya = wrap_index(yi, image.height, texture.wrap_t), yb = wrap_index(yi + 1, image.height, texture.wrap_t);
    // Filtered after decoding, as GL does for sRGB textures.
    const glm::vec4 top = glm::mix(at(xa, ya), at(xb, ya), fx);
    const glm::vec4 bottom = glm::mix(at(xa, yb), at(xb, yb), fx);
    return glm::mix(top, bottom, fy);
}

}  // namespace envshadow
