// Exposure, the ACES filmic curve (Narkowicz 2015) and the sRGB transfer function: the GLSL twin of
// engine/core/image.cpp's tonemap_to_srgb8 (tests/render/display_test.cpp keeps them equal).
vec3 aces_filmic(vec3 x) {
    const float a = 2.51, b = 0.03, c = 2.43, d = 0.59, e = 0.14;
    return clamp((x * (a * x + b)) / (x * (c * x + d) + e), 0.0, 1.0);
}

vec3 srgb_encode(vec3 linear) {
    linear = clamp(linear, 0.0, 1.0);
    return mix(12.92 * linear, 1.055 * pow(linear, vec3(1.0 / 2.4)) - 0.055, step(vec3(0.0031308), linear));
}

vec3 tonemap(vec3 radiance, float exposure_scale) { return srgb_encode(aces_filmic(radiance * exposure_scale)); }
