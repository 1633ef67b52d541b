// The pixel a shading sample stands for (docs/DESIGN.md §4.1, §11): its centre's normal and view and their change
// across it. Fragment stage only (screen derivatives).

// With multisampling (u_pixel_footprint) one shading sample stands for the pixel's mean, as the resolve and the
// box-filtered reference take it: where a mirror's reflection changes within the pixel, its lobe is taken over
// the pixel's footprint, from the screen derivatives of the normal and the view at the pixel's centre. With MSAA
// the shading point is the centroid, which moves within the pixel from one pixel to the next.
layout(location = LOC_PIXEL_FOOTPRINT) uniform bool u_pixel_footprint;
// Bit k of component q: the target's sample k lies in the pixel's quarter q (Renderer::sample_quarters_).
layout(location = LOC_SAMPLE_QUARTERS) uniform uvec4 u_sample_quarters;
// The frame's image moved by this many pixels (CameraView::jitter): the footprint is taken about the unmoved
// pixel's centre, which lies this far from the moved one's, so that each frame's lobes are the pixel's own.
layout(location = LOC_FOOTPRINT_SHIFT) uniform vec2 u_footprint_shift;

struct PixelFootprint {
    vec3 normal, view;          // the shading normal and the view at the pixel's centre
    vec3 normal_dx, normal_dy;  // their screen derivatives with u_pixel_footprint, else 0
    vec3 view_dx, view_dy;
    vec3 mirror_dx, mirror_dy;  // the mirror direction's likewise
    // Bit q: the fragment covers a sample in the pixel's quarter q (x = q & 1, y = q >> 1, from the lower left). A
    // lobe taken over the pixel is taken over these quarters: where a silhouette or another surface covers the
    // rest, the resolve gives the rest its own colour.
    uint quarters;
};

// normal: the shading normal at the pixel's centre; normal_at_centre and view_at_centre the interpolated normal
// and the view there, whose screen derivatives (in uniform control flow) span the footprint.
PixelFootprint pixel_footprint(vec3 normal, vec3 normal_at_centre, vec3 view_at_centre) {
    PixelFootprint p;
    p.normal = normal;
    p.view = view_at_centre;
    vec3 r = reflect(-view_at_centre, normal_at_centre);
    vec3 dn_dx = dFdxFine(normal_at_centre), dn_dy = dFdyFine(normal_at_centre);
    vec3 dv_dx = dFdxFine(view_at_centre), dv_dy = dFdyFine(view_at_centre);
    vec3 dr_dx = dFdxFine(r), dr_dy = dFdyFine(r);
    p.normal_dx = u_pixel_footprint ? dn_dx : vec3(0.0);
    p.normal_dy = u_pixel_footprint ? dn_dy : vec3(0.0);
    p.view_dx = u_pixel_footprint ? dv_dx : vec3(0.0);
    p.view_dy = u_pixel_footprint ? dv_dy : vec3(0.0);
    p.mirror_dx = u_pixel_footprint ? dr_dx : vec3(0.0);
    p.mirror_dy = u_pixel_footprint ? dr_dy : vec3(0.0);
    p.normal = normalize(normal + p.normal_dx * u_footprint_shift.x + p.normal_dy * u_footprint_shift.y);
    p.view = normalize(view_at_centre + p.view_dx * u_footprint_shift.x + p.view_dy * u_footprint_shift.y);
    p.quarters = 0u;
    for (int q = 0; q < 4; ++q)
        if ((uint(gl_SampleMaskIn[0]) & u_sample_quarters[q]) != 0u) p.quarters |= 1u << uint(q);
    if (p.quarters == 0u) p.quarters = 15u;
    return p;
}

bool covers_quarter(PixelFootprint p, int q) {
    return (p.quarters & (1u << uint(q))) != 0u;
}

// Whether the fragment covers the quarter that `offset` from the pixel's centre (in pixels) lies in.
bool covers(PixelFootprint p, vec2 offset) {
    offset += u_footprint_shift;
    return covers_quarter(p, (offset.x >= 0.0 ? 1 : 0) + (offset.y >= 0.0 ? 2 : 0));
}

// The normal and the view at `offset` from the pixel's centre (in pixels), carried there by their derivatives.
vec3 normal_at(PixelFootprint p, vec2 offset) {
    return normalize(p.normal + p.normal_dx * offset.x + p.normal_dy * offset.y);
}
vec3 view_at(PixelFootprint p, vec2 offset) {
    return normalize(p.view + p.view_dx * offset.x + p.view_dy * offset.y);
}
