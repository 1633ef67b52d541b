// Exposure, a tone map and the sRGB transfer function: the GLSL twin of engine/core/tonemap.cpp and
// image.cpp's tonemap_to_srgb8 (tests/render/tonemap_glsl_test.cpp keeps them equal). The operator
// is one of the defines core's tone_map_define names (TONEMAP_AGX, ...); none is ACES, the default.
vec3 aces_filmic(vec3 x) {
    const float a = 2.51, b = 0.03, c = 2.43, d = 0.59, e = 0.14;
    return clamp((x * (a * x + b)) / (x * (c * x + d) + e), 0.0, 1.0);
}

// Sobotka's AgX as in Wrensch 2024, "Minimal AgX implementation" (see core's agx()).
vec3 agx(vec3 x) {
    const mat3 inset = mat3(0.842479062253094, 0.0423282422610123, 0.0423756549057051,   //
                            0.0784335999999992, 0.878468636469772, 0.0784336,            //
                            0.0792237451477643, 0.0791661274605434, 0.879142973793104);
    const mat3 outset = mat3(1.19687900512017, -0.0528968517574562, -0.0529716355144438,  //
                             -0.0980208811401368, 1.15190312990417, -0.0980434501171241,  //
                             -0.0990297440797205, -0.0989611768448433, 1.15107367264116);
    const float min_ev = -12.47393, max_ev = 4.026069;
    vec3 v = inset * max(x, vec3(0.0));
    v = clamp(log2(max(v, vec3(1e-10))), min_ev, max_ev);
    v = (v - min_ev) / (max_ev - min_ev);
    vec3 v2 = v * v, v4 = v2 * v2;
    v = 15.5 * v4 * v2 - 40.14 * v4 * v + 31.96 * v4 - 6.868 * v2 * v + 0.4298 * v2 + 0.1191 * v - 0.00232;
    v = outset * v;
    return clamp(pow(max(v, vec3(0.0)), vec3(2.2)), 0.0, 1.0);
}

// Khronos PBR Neutral (KhronosGroup/ToneMapping, PBR_Neutral).
vec3 pbr_neutral(vec3 color) {
    const float start_compression = 0.8 - 0.04, desaturation = 0.15;
    color = max(color, vec3(0.0));
    float x = min(color.r, min(color.g, color.b));
    float offset = x < 0.08 ? x - 6.25 * x * x : 0.04;
    color -= offset;
    float peak = max(color.r, max(color.g, color.b));
    if (peak < start_compression) return clamp(color, 0.0, 1.0);
    const float d = 1.0 - start_compression;
    float new_peak = 1.0 - d * d / (peak + d - start_compression);
    color *= new_peak / peak;
    float g = 1.0 - 1.0 / (desaturation * (peak - new_peak) + 1.0);
    return clamp(mix(color, vec3(new_peak), g), 0.0, 1.0);
}

vec3 tone_map(vec3 x) {
#if defined(TONEMAP_AGX)
    return agx(x);
#elif defined(TONEMAP_NEUTRAL)
    return pbr_neutral(x);
#elif defined(TONEMAP_LINEAR)
    return clamp(x, 0.0, 1.0);
#else
    return aces_filmic(x);
#endif
}

vec3 srgb_encode(vec3 linear) {
    linear = clamp(linear, 0.0, 1.0);
    return mix(12.92 * linear, 1.055 * pow(linear, vec3(1.0 / 2.4)) - 0.055, step(vec3(0.0031308), linear));
}

vec3 tonemap(vec3 radiance, float exposure_scale) { return srgb_encode(tone_map(radiance * exposure_scale)); }
