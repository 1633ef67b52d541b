#pragma once
// The display transforms for 8-bit output: HDR radiance (after exposure) to display-linear [0, 1],
// before the sRGB encoding. glsl/tonemap.glsl is the GLSL twin (tests/render/tonemap_glsl_test.cpp
// keeps them equal); the operator's name table lives here, once, for the CLI, the viewer and GLSL.
#include <cstddef>
#include <span>
#include <string>
#include <string_view>

#include <glm/vec3.hpp>

#include "core/enum_names.h"

namespace envshadow {

enum class ToneMap {
    aces,     // Narkowicz 2015 fit of the ACES filmic curve, per channel (the default)
    agx,      // Sobotka's AgX base look (Wrensch 2024's minimal Rec. 709 form), no look transform
    neutral,  // Khronos PBR Neutral (KhronosGroup/ToneMapping, PBR_Neutral)
    linear,   // a clamp to [0, 1]
};
// In the enum's order: ToneMap(i) is named kToneMapNames[i].name.
inline constexpr EnumName<ToneMap> kToneMapNames[] = {
    {ToneMap::aces, "aces"}, {ToneMap::agx, "agx"}, {ToneMap::neutral, "neutral"}, {ToneMap::linear, "linear"}};
constexpr std::span<const EnumName<ToneMap>> enum_names(ToneMap) {
    return kToneMapNames;
}
inline constexpr std::size_t kToneMapCount = std::size(kToneMapNames);  // ToneMap's values are 0 .. count - 1
// The define that selects `op` in glsl/tonemap.glsl: "TONEMAP_AGX".
std::string tone_map_define(ToneMap op);

// Display-linear colour in [0, 1] for exposed radiance `x` (finite, any sign: negatives count as 0).
glm::vec3 tone_map(ToneMap op, glm::vec3 x);

float aces_filmic(float x);
glm::vec3 agx(glm::vec3 x);
glm::vec3 pbr_neutral(glm::vec3 x);

}  // namespace envshadow
