// glTF's alpha MASK (docs/DESIGN.md §5.12): the surface is cut out where u_base_alpha times the base-colour
// texture's alpha is below u_alpha_cutoff (0 for surfaces without a mask: nothing is cut).
layout(location = LOC_BASE_ALPHA) uniform float u_base_alpha;
layout(location = LOC_ALPHA_CUTOFF) uniform float u_alpha_cutoff;

bool cut_out(float texture_alpha) {
    return u_base_alpha * texture_alpha < u_alpha_cutoff;
}
