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

// With alpha to coverage (MSAA): the alpha sharpened to a pixel's width about the cutoff, so that the
// samples covered follow the cut edge within the pixel (Golus 2017).
float coverage_alpha(float alpha) {
    return (alpha - u_alpha_cutoff) / max(fwidth(alpha), 1e-4) + 0.5;
}
