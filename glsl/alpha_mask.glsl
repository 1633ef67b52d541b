// glTF's alpha MASK (docs/DESIGN.md §5.12): the surface is cut out where its alpha, u_base_alpha times the
// base-colour texture's alpha, is below u_alpha_cutoff (0 for surfaces without a mask: nothing is cut).
layout(location = LOC_BASE_ALPHA) uniform float u_base_alpha;
layout(location = LOC_ALPHA_CUTOFF) uniform float u_alpha_cutoff;

// The alpha at uv (the base-colour texture filtered as for shading).
float mask_alpha(sampler2D base_color, vec2 uv) {
    return u_base_alpha * texture(base_color, uv).a;
}

bool cut_out(float alpha) {
    return alpha < u_alpha_cutoff;
}

// A blended surface's base-colour texel over the pixel's footprint, its colour premultiplied by its alpha (so
// that the glass's colour does not bleed into a thin opaque frame, nor the frame's into the glass): along the
// footprint's longer axis in texels, up to 8 taps, each a trilinear lookup of half the shorter axis's width
// (anisotropic filtering in the shader: the hardware's isotropic level would blur a thin part's alpha across
// the longer axis's width; and a bilinear tap spans two texels of its level, so half the width makes each
// tap's kernel about as wide as its share of the pixel, as the resolve's box). The reference's footprint_mean
// weighs its taps alike.
vec4 premultiplied_footprint(sampler2D base_color, vec2 uv) {
    vec2 size = vec2(textureSize(base_color, 0));
    vec2 dx = dFdx(uv), dy = dFdy(uv);
    float lx = length(dx * size), ly = length(dy * size);
    vec2 major = lx >= ly ? dx : dy, minor = lx >= ly ? dy : dx;
    int taps = int(clamp(ceil(max(lx, ly) / max(min(lx, ly), 1e-6)), 1.0, 8.0));
    vec2 step_major = major / float(taps);
    vec4 sum = vec4(0.0);
    for (int k = 0; k < taps; ++k) {
        vec4 t = textureGrad(base_color, uv + major * ((float(k) + 0.5) / float(taps) - 0.5), 0.5 * step_major,
                             0.5 * minor);
        sum += vec4(t.rgb * t.a, t.a);
    }
    return sum / float(taps);
}

// With alpha to coverage (MSAA): the alpha sharpened to a pixel's width about the cutoff, so that the
// samples covered follow the cut edge within the pixel (Golus 2017).
float coverage_alpha(float alpha) {
    return (alpha - u_alpha_cutoff) / max(fwidth(alpha), 1e-4) + 0.5;
}
