// Shared by the Floyd-Steinberg GPU sampler's stages (engine/render/fs_sampler.h).

#include "latlong.glsl"

vec3 fs_texel_direction(ivec2 texel, ivec2 size) { return latlong_direction((vec2(texel) + 0.5) / vec2(size)); }

// (2 pi / W)(cos theta_top - cos theta_bottom) = (4 pi / W) sin(theta_centre) sin(pi / 2H): a product
// of sines keeps float's precision for thin rows, and taking theta_centre from the nearer pole keeps
// it at the south pole too (sin near pi would lose it).
float fs_texel_solid_angle(int row, ivec2 size) {
    const float from_pole = min(float(row) + 0.5, float(size.y - row) - 0.5);
    return (4.0 * PI / float(size.x)) * sin(PI * from_pole / float(size.y)) * sin(PI / (2.0 * float(size.y)));
}

float fs_luminance(vec3 rgb) { return dot(rgb, vec3(0.2126, 0.7152, 0.0722)); }

// Count words at the head of the count buffer (std430): written by the sampler, read by the light
// pass and by the renderer (light_count is the number of valid entries of the light buffer).
#define FS_COUNTS_MEMBERS                                                                          \
    uint light_count;      /* lights written: min(lights_found, capacity) */                      \
    uint samples;          /* K: the samples those lights carry (multiplicities summed) */        \
    float importance_sum;  /* S, the sum of the importance map (rounded to float) */             \
    uint capacity;         /* entries the sample and light buffers hold */                        \
    uint rows_scanned;     /* importance rows the scan finished: all of them, or it was cut short */ \
    uint lights_found;     /* sample texels the scan found; more than capacity: some were dropped */ \
    uint unused_counts0, unused_counts1;

// A captured sample: texel index (FS_TEXEL_BITS = 21 bits: up to 2048 x 1024) and multiplicity (the
// 11 bits above; engine/render/shader_interface.h).
const int FS_MAX_MULTIPLICITY = (1 << (32 - FS_TEXEL_BITS)) - 1;
uint fs_pack_sample(uint texel, uint multiplicity) { return texel | (multiplicity << FS_TEXEL_BITS); }
uint fs_sample_texel(uint captured) { return captured & ((1u << FS_TEXEL_BITS) - 1u); }
uint fs_sample_multiplicity(uint captured) { return captured >> FS_TEXEL_BITS; }

// One light, the fields of envshadow::Cell (engine/env/cells.h), std430: 48 bytes.
struct FsLight {
    vec3 direction;             // unit, world space
    float solid_angle;          // m 4 pi / K for a light of m of the K samples
    vec3 radiance;              // L~ (RGB), luminance m S / K
    float cos_radius;           // 1 - solid_angle / (2 pi)
    float cos_radius_weighted;  // cap of the solid angle over which the texel's radiance gives L~
    float unused0, unused1, unused2;
};

// The scan's accumulator type: double (default) matches a CPU scan in double; float is faster on GPUs
// with slow doubles and may move a sample by a few texels where the error creeps up slowly.
#ifdef FS_SCAN_FLOAT
#define fs_real float
#else
#define fs_real double
#endif
