#include "core/tonemap.h"

#include <algorithm>
#include <array>
#include <cctype>
#include <cmath>

#include <glm/common.hpp>
#include <glm/exponential.hpp>
#include <glm/mat3x3.hpp>

#include "core/error.h"

namespace envshadow {

std::string tone_map_define(ToneMap op) {
    std::string define = "TONEMAP_";
    for (char c : to_string(op)) define += char(std::toupper(static_cast<unsigned char>(c)));
    return define;
}

float aces_filmic(float x) {
    // Narkowicz 2015, "ACES Filmic Tone Mapping Curve".
    constexpr float a = 2.51f, b = 0.03f, c = 2.43f, d = 0.59f, e = 0.14f;
    return std::clamp((x * (a * x + b)) / (x * (c * x + d) + e), 0.0f, 1.0f);
}

glm::vec3 agx(glm::vec3 x) {
    // Sobotka's AgX (github.com/sobotka/AgX) as in Wrensch 2024, "Minimal AgX implementation": the
    // inset matrix, log2 encoding over [-12.47393, 4.026069] EV (middle grey 0.18 -10 / +6.5 stops),
    // the 6th-order polynomial fit of the default contrast sigmoid, the outset matrix and the 2.2
    // display decoding. glm matrices are column-major, as GLSL's mat3 (the same numbers, the same order).
    const glm::mat3 inset(0.842479062253094f, 0.0423282422610123f, 0.0423756549057051f,  //
                          0.0784335999999992f, 0.878468636469772f, 0.0784336f,           //
                          0.0792237451477643f, 0.0791661274605434f, 0.879142973793104f);
    const glm::mat3 outset(1.19687900512017f, -0.0528968517574562f, -0.0529716355144438f,  //
                           -0.0980208811401368f, 1.15190312990417f, -0.0980434501171241f,  //
                           -0.0990297440797205f, -0.0989611768448433f, 1.15107367264116f);
    constexpr float min_ev = -12.47393f, max_ev = 4.026069f;
    glm::vec3 v = inset * glm::max(x, glm::vec3(0.0f));
    v = glm::clamp(glm::log2(glm::max(v, glm::vec3(1e-10f))), min_ev, max_ev);
    v = (v - min_ev) / (max_ev - min_ev);
    const glm::vec3 v2 = v * v, v4 = v2 * v2;
    v = 15.5f * v4 * v2 - 40.14f * v4 * v + 31.96f * v4 - 6.868f * v2 * v + 0.4298f * v2 + 0.1191f * v - 0.00232f;
    v = outset * v;
    return glm::clamp(glm::pow(glm::max(v, glm::vec3(0.0f)), glm::vec3(2.2f)), 0.0f, 1.0f);
}

glm::vec3 pbr_neutral(glm::vec3 color) {
    // Khronos PBR Neutral (KhronosGroup/ToneMapping, PBR_Neutral/README.md's specification).
    constexpr float start_compression = 0.8f - 0.04f, desaturation = 0.15f;
    color = glm::max(color, glm::vec3(0.0f));
    const float x = std::min(color.r, std::min(color.g, color.b));
    const float offset = x < 0.08f ? x - 6.25f * x * x : 0.04f;
    color -= offset;
    const float peak = std::max(color.r, std::max(color.g, color.b));
    if (peak < start_compression) return glm::clamp(color, 0.0f, 1.0f);
    constexpr float d = 1.0f - start_compression;
    const float new_peak = 1.0f - d * d / (peak + d - start_compression);
    color *= new_peak / peak;
    const float g = 1.0f - 1.0f / (desaturation * (peak - new_peak) + 1.0f);
    return glm::clamp(glm::mix(color, glm::vec3(new_peak), g), 0.0f, 1.0f);
}

glm::vec3 tone_map(ToneMap op, glm::vec3 x) {
    switch (op) {
        case ToneMap::aces:
            return {aces_filmic(x.r), aces_filmic(x.g), aces_filmic(x.b)};
        case ToneMap::agx:
            return agx(x);
        case ToneMap::neutral:
            return pbr_neutral(x);
        case ToneMap::linear:
            return glm::clamp(x, 0.0f, 1.0f);
    }
    return glm::clamp(x, 0.0f, 1.0f);
}

}  // namespace envshadow
