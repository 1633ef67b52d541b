#version 450 core
// Floyd-Steinberg importance sampling in a geometry shader (Szirmay-Kalos, Szécsi, Penzov, Environment
// Mapping with Floyd-Steinberg Halftoning, §1.3.1, Listing 1.1): one invocation scans the importance
// map in serpentine rows with threshold S / (2M); a texel whose error-diffused importance exceeds the
// threshold becomes a sample and gives back S / M. The error
// goes to the next texel, the texel below and the one below the next (u_weights; Listing 1.1 uses
// 3/8, 3/8, 1/4), carried in registers (carry_pixel, carry_diagonal) and in one array for the next
// row, and, as in the listing, carries on across row ends along the serpentine path.
//
// With FS_MERGE, a texel whose error exceeds the threshold by more than S / M takes as many samples as
// thresholds it crosses (multi-level error diffusion) and emits them once, with their multiplicity: a
// sun holding 30 S / M becomes one light of 30 samples instead of spilling one sample per texel into
// a streak along its row. Without it, one sample per texel, as in the listing.
//
// Texels are visited in unrolled runs of FS_SCAN_RUN where the width allows (the listing works in runs of
// 4): llvmpipe ends any shader after 65535 loop iterations in all, which a loop per texel would pass
// at 256 x 256.
//
// Each sample is emitted as one uint (texel index | multiplicity << 21) for transform feedback: one component per
// vertex keeps GL_MAX_GEOMETRY_TOTAL_OUTPUT_COMPONENTS from limiting the vertices per invocation below
// GL_MAX_GEOMETRY_OUTPUT_VERTICES. When the capacity exceeds what one invocation may emit, several
// points are drawn; every invocation runs the same scan and emits only its slice of the sample
// ordinals, so the captured stream is the full sample sequence in scan order.
//
// Defines: FS_IMPORTANCE_WIDTH (the map's width), FS_MAX_VERTICES (per invocation), FS_MERGE,
// FS_ADAPTIVE (the CPU method's rules instead of the listing's), FS_SCAN_FLOAT (fs_common.glsl).
#include "fs_common.glsl"

#if FS_SCAN_RUN != 16
#error "FS_SCAN_RUN: main() unrolls runs of exactly 16 texels (four FS_VISIT4)"
#endif

layout(points) in;
layout(points, max_vertices = FS_MAX_VERTICES) out;

layout(binding = UNIT_IMPORTANCE) uniform sampler2D u_importance;  // r32f, FS_IMPORTANCE_WIDTH x height
layout(std430, binding = BINDING_FS_ROW_SUMS) readonly buffer FsRowSums { double row_sum[]; };
layout(std430, binding = BINDING_FS_COUNTS) writeonly buffer FsCounts { FS_COUNTS_MEMBERS };

layout(location = LOC_EXPECTED_SAMPLES) uniform int u_expected_samples;  // M
layout(location = LOC_CAPACITY) uniform int u_capacity;                  // samples the capture buffer holds
layout(location = LOC_WEIGHTS) uniform dvec3 u_weights;                  // error to: next texel, below, below the next
layout(location = LOC_SCAN_ROWS) uniform int u_scan_rows;                  // rows scanned: all, or those above the horizon

out uint fs_texel;  // fs_pack_sample(j * width + i, multiplicity)

fs_real threshold;
int found;         // sample texels so far, in scan order: the lights
int kept_samples;  // samples (multiplicities summed) in the lights that fit the capacity
int slice_begin, slice_end;
int importance_height;
fs_real carry_row[FS_IMPORTANCE_WIDTH];  // error for the next row, by column (the listing's cRow)
fs_real carry_pixel, carry_diagonal;
fs_real weight_next, weight_below, weight_below_next;

void emit_sample(int column, int row, int multiplicity) {
    if (found >= slice_begin && found < slice_end) {
        fs_texel = fs_pack_sample(uint(row * FS_IMPORTANCE_WIDTH + column), uint(multiplicity));
        EmitVertex();
    }
    if (found < u_capacity) kept_samples += multiplicity;
    ++found;
}

#ifndef FS_ADAPTIVE
// Listing 1.1: fixed weights, and the carries run on across row ends along the serpentine path.
void visit(int column, int row) {
    const fs_real importance = fs_real(texelFetch(u_importance, ivec2(column, row), 0).r);
    fs_real modified = importance + carry_row[column] + carry_pixel;
    if (modified > threshold) {
#ifdef FS_MERGE
        // The quotient is positive, so int() is floor() (and avoids llvmpipe's double floor, which gave 0 here).
        const int multiplicity = min(int((modified - threshold) / (2.0 * threshold)) + 1, FS_MAX_MULTIPLICITY);
#else
        const int multiplicity = 1;
#endif
        emit_sample(column, row, multiplicity);
        modified -= 2.0 * threshold * fs_real(multiplicity);
    }
    carry_row[column] = modified * weight_below + carry_diagonal;
    carry_pixel = modified * weight_next;
    carry_diagonal = modified * weight_below_next;
}
#else
// The CPU method fs (engine/env sites_floyd_steinberg), for the same samples from both: blocks of B x B
// texels (the importance map's texels here); the share passed along the row adapts to the block,
// clamp(1 - I / (S/M), 3/8, 15/16), the rest 3 : 2 below and below-next; the next texel's share stops
// at the row's end (it goes below), the diagonal wraps around the seam, nothing carries across rows,
// and in the last row everything goes along the row.
const fs_real kMaxAlong = 15.0 / 16.0;
fs_real carry_below_next;  // this texel's share for the texel below the next one, added when that is visited

void visit(int column, int row) {
    const bool forward = (row & 1) == 0;
    const int first_column = forward ? 0 : FS_IMPORTANCE_WIDTH - 1;
    const bool last_in_row = column == (forward ? FS_IMPORTANCE_WIDTH - 1 : 0);
    const fs_real block = fs_real(texelFetch(u_importance, ivec2(column, row), 0).r);
    fs_real error = block + carry_row[column] + carry_pixel;
    carry_pixel = 0.0;
    if (error > threshold) {
        emit_sample(column, row, 1);
        error -= 2.0 * threshold;
    }
    if (row == importance_height - 1) {
        if (!last_in_row) carry_pixel = error;
        return;
    }
    const fs_real along = clamp(1.0 - block / (2.0 * threshold), 0.375, kMaxAlong);
    const fs_real below = (1.0 - along) * 0.6, diagonal = (1.0 - along) * 0.4;
    if (!last_in_row) {
        carry_pixel = along * error;
        carry_row[column] = below * error + carry_below_next;
        carry_below_next = diagonal * error;
    } else {
        carry_row[column] = (along + below) * error + carry_below_next;
        carry_row[first_column] += diagonal * error;  // across the seam
        carry_below_next = 0.0;
    }
}
#endif

#define FS_VISIT4(k)                         \
    visit(first + (k) * step, row);          \
    visit(first + ((k) + 1) * step, row);    \
    visit(first + ((k) + 2) * step, row);    \
    visit(first + ((k) + 3) * step, row);

void main() {
    const int height = u_scan_rows;
    importance_height = height;
    double sum = 0.0;  // S, from the importance pass's row sums (Listing 1.1 sums every texel here)
    for (int row = 0; row < height; ++row) sum += row_sum[row];
    threshold = fs_real(sum / (2.0 * double(u_expected_samples)));
    weight_next = fs_real(u_weights.x);
    weight_below = fs_real(u_weights.y);
    weight_below_next = fs_real(u_weights.z);

    slice_begin = gl_PrimitiveIDIn * FS_MAX_VERTICES;
    slice_end = min(slice_begin + FS_MAX_VERTICES, u_capacity);
    found = 0;
    kept_samples = 0;
    for (int i = 0; i < FS_IMPORTANCE_WIDTH; ++i) carry_row[i] = 0.0;
    carry_pixel = 0.0;
    carry_diagonal = 0.0;
#ifdef FS_ADAPTIVE
    carry_below_next = 0.0;
#endif

    int rows_done = 0;
    for (int row = 0; row < height; ++row) {
        const bool forward = (row & 1) == 0;
        const int step = forward ? 1 : -1;
#if FS_IMPORTANCE_WIDTH % FS_SCAN_RUN == 0
        for (int run = 0; run < FS_IMPORTANCE_WIDTH; run += FS_SCAN_RUN) {
            const int first = forward ? run : FS_IMPORTANCE_WIDTH - 1 - run;
            FS_VISIT4(0) FS_VISIT4(4) FS_VISIT4(8) FS_VISIT4(12)
        }
#else  // a narrow map (few texels: far from the loop limit)
        for (int n = 0; n < FS_IMPORTANCE_WIDTH; ++n) visit(forward ? n : FS_IMPORTANCE_WIDTH - 1 - n, row);
#endif
        rows_done = row + 1;
    }

    if (gl_PrimitiveIDIn == 0) {
        light_count = uint(min(found, u_capacity));
        lights_found = uint(found);
        samples = uint(kept_samples);
        importance_sum = float(sum);
        capacity = uint(u_capacity);
        rows_scanned = uint(rows_done);
    }
}
