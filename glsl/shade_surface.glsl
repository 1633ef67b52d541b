// The surface point a fragment of shade.frag shades, and its material (the paper's modified Phong BRDF:
// k_d, k_s and the shininess n, Barsi et al. §2.3; or glTF's, METALLIC_ROUGHNESS). Fragment stage only (screen
// derivatives, gl_FrontFacing).
#include "pixel_footprint.glsl"
#if defined(METALLIC_ROUGHNESS)
#include "shade_metallic_roughness.glsl"
#endif
// ALPHA_BLEND's premultiplied_footprint, and ALPHA_TEST's cut (an include is expanded once, before any #if).
#include "alpha_mask.glsl"

layout(location = LOC_EYE) uniform vec3 u_eye;
layout(location = LOC_K_D) uniform vec3 u_k_d;  // rho_d / pi
// The base-colour texture (linear: an sRGB texture), white without one; it scales k_d at each pixel.
layout(binding = UNIT_BASE_COLOR) uniform sampler2D u_base_color;
layout(location = LOC_K_S) uniform float u_k_s;  // rho_s (n + 2) / (2 pi)
layout(location = LOC_SHININESS) uniform float u_shininess;
// Emitted radiance, times the emission texture (linear: sRGB; white without one): seen, lighting nothing.
layout(location = LOC_EMISSION) uniform vec3 u_emission;
layout(binding = UNIT_EMISSION_TEXTURE) uniform sampler2D u_emission_texture;
// glTF's occlusion: its texture's R (linear; white without one), blended towards 1 by (1 - strength).
layout(location = LOC_OCCLUSION_STRENGTH) uniform float u_occlusion_strength;
layout(binding = UNIT_OCCLUSION_TEXTURE) uniform sampler2D u_occlusion_texture;
// glTF's normal map (linear) and its scale; 0 without one (a scale of 0 leaves the normal as it is).
layout(location = LOC_NORMAL_SCALE) uniform float u_normal_scale;
layout(binding = UNIT_NORMAL_TEXTURE) uniform sampler2D u_normal_texture;

struct Surface {
    vec3 position;      // x, in world space
    vec3 normal;        // the shading normal n (shading_normal)
    vec3 plane_normal;  // the triangle's plane (either side): the surface the shadow atlas holds
    bool curved;        // the interpolated normal turns across the pixel: a smooth-shaded curved surface
    vec3 mirror;        // r: the direction to the viewer reflected about n
    vec3 base_color;    // the base-colour texture at this pixel (ALPHA_BLEND: where the surface is)
    vec3 k_d;           // u_k_d times base_color
    vec2 texcoord;
    vec3 view;          // towards the eye
    PixelFootprint pixel;  // the pixel this sample stands for (pixel_footprint.glsl)
#if defined(ALPHA_BLEND)
    float alpha;        // how much of the pixel's footprint the blended surface covers
#endif
#if defined(METALLIC_ROUGHNESS)
    GltfPixel gltf;     // glTF's BRDF at this pixel
#endif
};

vec3 emitted_radiance(Surface s) {
    return u_emission * texture(u_emission_texture, s.texcoord).rgb;
}

// What the reflected radiance is multiplied by (docs/SCENES.md "Occlusion"): glTF's
// 1 + strength (occlusion - 1); not the emission.
float occlusion(Surface s) {
    return 1.0 + u_occlusion_strength * (texture(u_occlusion_texture, s.texcoord).r - 1.0);
}

// The normal map's direction at texcoord in the frame of the interpolated normal n and tangent (w: the
// handedness), glTF 2.0 §3.9.3: normalize(T x s + B y s + N z), (x, y, z) = 2 texel - 1, B = w cross(N, T)
// with T made orthogonal to N (docs/SCENES.md "Normal maps"). n unchanged without a map or a tangent.
vec3 normal_mapped(vec3 n, vec4 tangent, vec2 texcoord) {
    vec3 texel = texture(u_normal_texture, texcoord).xyz;  // before any branch: its mip level needs derivatives
    vec3 t = tangent.xyz - n * dot(n, tangent.xyz);
    if (u_normal_scale == 0.0 || !(dot(t, t) > 0.0)) return n;
    t = normalize(t);
    vec3 b = (tangent.w < 0.0 ? -1.0 : 1.0) * cross(n, t);
    vec3 m = (2.0 * texel - 1.0) * vec3(u_normal_scale, u_normal_scale, 1.0);
    vec3 mapped = m.x * t + m.y * b + m.z * n;
    return dot(mapped, mapped) > 0.0 ? normalize(mapped) : n;
}

// Where the mirror direction of `view` about n dips below t = min(0.9 view.ng, 0.01) over the triangle's plane
// (ng, on the viewer's side), n turned towards ng, in the plane of the two, until that direction's height is t:
// the shading normal adaptation of Iray (Keller et al. 2017) and Cycles, which a normal map's slopes facing
// away from the viewer need. In closed form, without a loop (env/shading_normal.h derives it; its C++ twin).
vec3 mirror_above_surface(vec3 n, vec3 ng, vec3 view) {
    float vz = dot(view, ng);
    float threshold = min(0.9 * vz, 0.01);
    vec3 x = n - dot(n, ng) * ng;
    if (2.0 * dot(n, view) * dot(n, ng) - vz >= threshold || !(dot(x, x) > 0.0)) return n;
    x = normalize(x);
    float vx = dot(view, x);
    float a = 0.5 * (atan(vx, vz) + acos(clamp(threshold / length(vec2(vz, vx)), -1.0, 1.0)));
    return cos(a) * ng + sin(a) * x;
}

// Shading normal at p (docs/DESIGN.md §5.4): interpolated, then normal-mapped. The side comes from the
// triangle: seen from behind (an open mesh), the normal is turned round; it may still face away from the
// viewer near a silhouette, and is then bent towards the viewer in the plane of n and v until n.v is about
// kFacingEpsilon (turning it round instead would point it into the surface: a black rim); last, a mapped
// normal's mirror direction is kept above the triangle's plane (viewer_plane: its normal on the viewer's
// side, or 0 for a triangle seen edge on). The reference (engine/reference/reference.cpp) does the same.
const float kFacingEpsilon = 0.01;
vec3 shading_normal(vec3 interpolated, vec4 tangent, vec2 texcoord, vec3 view, vec3 viewer_plane) {
    vec3 n = normal_mapped(interpolated, tangent, texcoord);
    bool mapped = n != interpolated;
    if (!gl_FrontFacing) n = -n;
    float facing = dot(n, view);
    if (facing < kFacingEpsilon) n = normalize(n + (kFacingEpsilon - facing) * view);
    return mapped && dot(viewer_plane, viewer_plane) > 0.0 ? mirror_above_surface(n, viewer_plane, view) : n;
}

// The surface at the fragment's interpolated world position, normal, tangent and texture coordinates;
// position_at_centre is the position interpolated at the pixel centre (not centroid: it may lie beyond
// the triangle's edge, on its plane).
Surface surface(vec3 position, vec3 position_at_centre, vec3 interpolated_normal, vec3 normal_at_centre, vec4 tangent,
                vec2 texcoord) {
    Surface s;
    s.texcoord = texcoord;
#if defined(ALPHA_BLEND)
    vec4 texel = premultiplied_footprint(u_base_color, texcoord);
    s.base_color = texel.a > 0.0 ? texel.rgb / texel.a : texture(u_base_color, texcoord).rgb;
    s.alpha = clamp(u_base_alpha * texel.a, 0.0, 1.0);
#else
    s.base_color = texture(u_base_color, texcoord).rgb;
#endif
    s.k_d = u_k_d * s.base_color;
    vec3 view = normalize(u_eye - position);
    // The plane of the triangle, from the pixel-centre position's screen derivatives (helper invocations
    // interpolate the same triangle): the surface the atlas holds, which the interpolated normal only
    // approximates. Centroid positions would not do: a 2x2 quad's lie at different sub-pixel offsets.
    // A triangle seen edge on has none: its shading normal stands in.
    vec3 across = cross(dFdx(position_at_centre), dFdy(position_at_centre));
    bool has_plane = dot(across, across) > 0.0;
    vec3 plane = has_plane ? normalize(across) : vec3(0.0);
    s.normal = shading_normal(normalize(interpolated_normal), tangent, texcoord, view,
                              dot(plane, view) < 0.0 ? -plane : plane);
    s.plane_normal = has_plane ? plane : s.normal;
    vec3 turn = abs(dFdx(normal_at_centre)) + abs(dFdy(normal_at_centre));  // 0 on a flat face, to rounding
    s.curved = max(turn.x, max(turn.y, turn.z)) > 1e-5;
    // The shaded point is the centroid position put onto that plane: with MSAA the centroid sample lies
    // inside the triangle, but the position interpolated there need not lie on the triangle's plane
    // (llvmpipe's does not), and a point below it is shadowed by its own triangle. At one sample per
    // pixel both positions are the pixel centre's.
    s.position = has_plane ? position - s.plane_normal * dot(position - position_at_centre, s.plane_normal)
                           : position;
    s.mirror = reflect(-view, s.normal);
    s.view = view;
    // The shading normal moved from the centroid to the pixel's centre by the interpolated normal's change.
    vec3 centre_normal = normalize(normal_at_centre);
    s.pixel = pixel_footprint(normalize(s.normal + centre_normal - normalize(interpolated_normal)), centre_normal,
                              normalize(u_eye - position_at_centre));
#if defined(METALLIC_ROUGHNESS)
    s.gltf = gltf_pixel(s.base_color, texcoord, dot(s.normal, view), s.pixel);
#endif
    return s;
}
