// Convolution of the environment with axially symmetric lobes through spherical harmonics (docs/DESIGN.md §4.1).
// With Y_lm = P_lm(cos theta) e^{i m phi} orthonormal, the map's coefficients are the exact texel sums
//   c_lm = sum over texels of L dw P_lm(cos theta) e^{-i m phi}
// (so the result is the direct numerical integral of the texels, the twin tests' truth, up to the
// truncation of the lobe's expansion), and by Funk-Hecke any lobe K(r . w) gives
//   integral of L K(r . w) dw = sum_lm Lambda_l c_lm Y_lm(r),  Lambda_l = 2 pi integral K(t) P_l(t) dt.
#include "env/lobe_convolution.h"

#include <tbb/enumerable_thread_specific.h>
#include <tbb/parallel_for.h>

#include <algorithm>
#include <bit>
#include <cmath>
#include <complex>
#include <cstdint>
#include <numbers>
#include <utility>

#include "env/fft.h"
#include "env/latlong.h"
#include "env/legendre.h"
#include "env/level_storage.h"
#include "env/row_block.h"

namespace envshadow::prefiltering {

namespace {

using Complex = std::complex<double>;
constexpr double kPi = std::numbers::pi;

// The map at kMaxGridWidth x kMaxGridWidth / 2: wider maps box-halved (weighted by texel solid angle),
// narrower ones (builtin:constant, small skies) repeated texel by texel, so that the sharpest lobe's band
// fits the source's (a band cut short would overshoot).
EnvironmentMap resampled(const EnvironmentMap& map) {
    if (map.width < kMaxGridWidth) {
        EnvironmentMap larger;
        larger.width = kMaxGridWidth;
        larger.height = kMaxGridWidth / 2;
        larger.texels.resize(std::size_t(larger.width) * std::size_t(larger.height));
        tbb::parallel_for(0, larger.height, [&](int j) {
            const int source_row = std::min(int(std::int64_t(j) * map.height / larger.height), map.height - 1);
            for (int i = 0; i < larger.width; ++i)
                larger.at(i, j) =
                    map.at(std::min(int(std::int64_t(i) * map.width / larger.width), map.width - 1), source_row);
        });
        return larger;
    }
    EnvironmentMap current = map;
    while (current.width > kMaxGridWidth && current.width % 2 == 0 && current.height % 2 == 0) {
        EnvironmentMap half;
        half.width = current.width / 2;
        half.height = current.height / 2;
        half.texels.resize(std::size_t(half.width) * std::size_t(half.height));
        tbb::parallel_for(0, half.height, [&](int j) {
            const double w0 = latlong::texel_solid_angle(2 * j, current.width, current.height);
            const double w1 = latlong::texel_solid_angle(2 * j + 1, current.width, current.height);
            for (int i = 0; i < half.width; ++i) {
                const glm::dvec3 top = glm::dvec3(current.at(2 * i, 2 * j)) + glm::dvec3(current.at(2 * i + 1, 2 * j));
                const glm::dvec3 bottom =
                    glm::dvec3(current.at(2 * i, 2 * j + 1)) + glm::dvec3(current.at(2 * i + 1, 2 * j + 1));
                half.at(i, j) = glm::vec3((top * w0 + bottom * w1) / (2.0 * (w0 + w1)));
            }
        });
        current = std::move(half);
    }
    return current;
}

}  // namespace

std::vector<LobeGrid> convolve_with_lobes(const EnvironmentMap& full_map, Hemisphere hemisphere,
                                          const std::vector<LobePlan>& lobe_plans) {
    // A 1024-wide map is used as it is (no copy: 6 MB of page faults).
    const EnvironmentMap resampled_map = full_map.width == kMaxGridWidth ? EnvironmentMap{} : resampled(full_map);
    const EnvironmentMap& map = full_map.width == kMaxGridWidth ? full_map : resampled_map;
    const int w = map.width, h = map.height;
    const int source_band = std::max(w / 2 - 1, 1);

    std::vector<LobeGrid> grids(lobe_plans.size());
    std::vector<LobePlan> plans = lobe_plans;
    int lmax = 0;
    for (std::size_t k = 0; k < plans.size(); ++k) {
        grids[k].width = plans[k].width;
        grids[k].height = plans[k].width / 2;
        plans[k].band = std::min({plans[k].band, plans[k].width / 2 - 1, source_band});
        lmax = std::max(lmax, plans[k].band);
    }
    const LegendreRecurrence recurrence(lmax);
    const int bands = lmax + 1;

    // The levels of one grid size share the rows' Legendre recurrences (up to the group's largest band), so
    // they are synthesised together.
    struct Group {
        std::size_t first, end;
        int width, height, band, north, blocks;
        FftTables fft;
        std::vector<double> shift_re, shift_im;  // e^{i pi m / W}: the columns' half texel
    };
    std::vector<Group> groups;
    std::size_t row_doubles = std::size_t(3 * 2) * std::size_t(w) * kBlock;  // the analysis' three transforms
    for (std::size_t first = 0; first < grids.size();) {
        std::size_t end = first + 1;
        while (end < grids.size() && grids[end].width == grids[first].width) ++end;
        const int width = grids[first].width, height = grids[first].height;
        int band = 0;
        for (std::size_t k = first; k < end; ++k) band = std::max(band, plans[k].band);
        // Rows j and H - 1 - j mirror each other: the northern half's recurrences give both.
        const int north = (height + 1) / 2;
        Group& group = groups.emplace_back(
            Group{first, end, width, height, band, north, (north + kBlock - 1) / kBlock, FftTables(width), {}, {}});
        for (int m = 0; m <= band; ++m) {
            const Complex shift = std::polar(1.0, kPi * m / width);
            group.shift_re.push_back(shift.real());
            group.shift_im.push_back(shift.imag());
        }
        row_doubles = std::max(row_doubles, (end - first) * 3 * 2 * std::size_t(width) * kBlock);
        first = end;
    }

    // Row pairs: the northern row r and its mirror h - 1 - r. P_lm(-x) = (-1)^{l+m} P_lm(x), so a pair enters the
    // coefficients through the sum of its rows' spectra (even l - m) and their difference (odd l - m), and the
    // recurrences run over the northern rows only.
    const int pairs = (h + 1) / 2;
    const int blocks = (pairs + kBlock - 1) / kBlock;

    // Per-thread scratch, reused by every stage: complex rows laid out [..][index][lane] and the recurrences.
    struct ThreadScratch {
        Scratch<double> rows, pmm, legendre, p1, p2;
    };
    tbb::enumerable_thread_specific<ThreadScratch> thread_scratch;
    auto local_scratch = [&]() -> ThreadScratch& {
        ThreadScratch& local = thread_scratch.local();
        if (!local.rows) {
            local.rows = scratch<double>(row_doubles);
            local.pmm = scratch<double>(std::size_t(bands) * kBlock);
            local.legendre = scratch<double>(std::size_t(bands) * kBlock);
            local.p1 = scratch<double>(std::size_t(blocks) * kBlock);
            local.p2 = scratch<double>(std::size_t(blocks) * kBlock);
        }
        return local;
    };

    // Row spectra of L dw: F_j(m) = dw_j sum_i L_ij e^{-i m phi_i}, phi_i = 2 pi (i + 0.5) / W, of each pair's
    // rows, as the even and odd spectra F_north +- F_south; 6 doubles (re, im of r, g, b) per pair, order and
    // parity: spectra[block][m][parity][q][lane]; one parity when no southern row is visible (the upper
    // hemisphere: both are F_north). Padding lanes are zero. With the P_mm of the northern rows:
    // block_pmm[block][m][lane].
    bool southern_rows = false;
    for (int r = 0; r < pairs; ++r)
        southern_rows =
            southern_rows || (h - 1 - r != r && hemisphere_texel_solid_angle(h - 1 - r, w, h, hemisphere) > 0.0);
    const int parities = southern_rows ? 2 : 1;
    Scratch<double> spectra =
        scratch<double>(std::size_t(blocks) * std::size_t(bands) * std::size_t(parities) * 6 * kBlock);
    Scratch<double> block_x = scratch<double>(std::size_t(blocks) * kBlock);
    Scratch<double> block_pmm = scratch<double>(std::size_t(blocks) * std::size_t(bands) * kBlock);
    std::vector<double> source_shift_re(static_cast<std::size_t>(bands)), source_shift_im(source_shift_re.size());
    for (int m = 0; m < bands; ++m) {  // e^{-i pi m / W}: phi_i's half texel
        const Complex shift = std::polar(1.0, -kPi * m / w);
        source_shift_re[std::size_t(m)] = shift.real(), source_shift_im[std::size_t(m)] = shift.imag();
    }
    const bool power_of_two = std::has_single_bit(unsigned(w));
    const FftTables source_fft(power_of_two ? w : 1);
    tbb::parallel_for(0, blocks, [&](int block) {
        ThreadScratch& local = local_scratch();
        alignas(64) double north_weight[kBlock], south_weight[kBlock], s[kBlock];
        int north_row[kBlock], south_row[kBlock];
        for (int b = 0; b < kBlock; ++b) {
            const int r = block * kBlock + b;
            double x = 0.0;
            north_weight[b] = south_weight[b] = s[b] = 0.0;
            north_row[b] = south_row[b] = 0;
            if (r < pairs) {
                north_row[b] = r, south_row[b] = h - 1 - r;
                north_weight[b] = hemisphere_texel_solid_angle(r, w, h, hemisphere);
                if (south_row[b] != r) south_weight[b] = hemisphere_texel_solid_angle(h - 1 - r, w, h, hemisphere);
                x = std::cos(kPi * (r + 0.5) / h);
                s[b] = std::sin(kPi * (r + 0.5) / h);
            }
            block_x[std::size_t(block) * kBlock + std::size_t(b)] = x;
        }
        sectoral(recurrence, s, lmax, &block_pmm[std::size_t(block) * std::size_t(bands) * kBlock]);

        // Three complex transforms of two real rows each: north red + i green, south red + i green, north blue +
        // i south blue. Z = X + i Y with X, Y real rows' spectra (X_{-m} = conj X_m) gives X_m = (Z_m + conj
        // Z_{-m}) / 2, Y_m = (Z_m - conj Z_{-m}) / 2i.
        const std::size_t row_size = std::size_t(w) * kBlock;
        double* z = local.rows.get();
        auto re_of = [&](int t) { return z + std::size_t(2 * t) * row_size; };
        auto im_of = [&](int t) { return z + std::size_t(2 * t + 1) * row_size; };
        if (power_of_two) {
            for (int i = 0; i < w; ++i)
                for (int b = 0; b < kBlock; ++b) {
                    // Rows outside the hemisphere (weight 0) read as zero, whatever they hold.
                    const glm::vec3 north = north_weight[b] > 0.0 ? map.at(i, north_row[b]) : glm::vec3(0.0f);
                    const glm::vec3 south = south_weight[b] > 0.0 ? map.at(i, south_row[b]) : glm::vec3(0.0f);
                    const std::size_t at = std::size_t(i) * kBlock + std::size_t(b);
                    re_of(0)[at] = north.r, im_of(0)[at] = north.g;
                    re_of(1)[at] = south.r, im_of(1)[at] = south.g;
                    re_of(2)[at] = north.b, im_of(2)[at] = south.b;
                }
            for (int t = 0; t < 3; ++t)
                if (t != 1 || southern_rows) block_fft(source_fft, re_of(t), im_of(t), -1.0);  // zeros stay zeros
        } else {  // a direct transform of the orders needed, m < bands (and their mirrors -m)
            std::vector<double> cos_table(static_cast<std::size_t>(w)), sin_table(cos_table.size());
            for (int i = 0; i < w; ++i)
                cos_table[std::size_t(i)] = std::cos(2.0 * kPi * i / w),
                sin_table[std::size_t(i)] = std::sin(2.0 * kPi * i / w);
            for (int m = 0; m < bands; ++m)
                for (int b = 0; b < kBlock; ++b) {
                    double sums[3][2][2] = {};  // [transform][re/im of sum L e^{-i m phi}][real row X or Y]
                    for (int i = 0; i < w; ++i) {
                        const std::size_t turn = std::size_t(std::int64_t(m) * i % w);
                        const double c = cos_table[turn], si = -sin_table[turn];
                        const glm::vec3 north = north_weight[b] > 0.0 ? map.at(i, north_row[b]) : glm::vec3(0.0f);
                        const glm::vec3 south = south_weight[b] > 0.0 ? map.at(i, south_row[b]) : glm::vec3(0.0f);
                        const double xs[3] = {north.r, south.r, north.b}, ys[3] = {north.g, south.g, south.b};
                        for (int t = 0; t < 3; ++t) {
                            sums[t][0][0] += xs[t] * c, sums[t][1][0] += xs[t] * si;
                            sums[t][0][1] += ys[t] * c, sums[t][1][1] += ys[t] * si;
                        }
                    }
                    // Stored as the transform of X + i Y would be, at m and -m.
                    const std::size_t p = std::size_t(m) * kBlock + std::size_t(b);
                    const std::size_t q = std::size_t((w - m) % w) * kBlock + std::size_t(b);
                    for (int t = 0; t < 3; ++t) {
                        re_of(t)[p] = sums[t][0][0] - sums[t][1][1], im_of(t)[p] = sums[t][1][0] + sums[t][0][1];
                        re_of(t)[q] = sums[t][0][0] + sums[t][1][1], im_of(t)[q] = sums[t][0][1] - sums[t][1][0];
                    }
                }
        }
        auto slot = [&](int m) {  // of Z_m: the FFT's output is bit-reversed, the direct transform's natural
            return std::size_t(power_of_two ? source_fft.reversed[std::size_t(m)] : m) * kBlock;
        };
        for (int m = 0; m < bands; ++m) {
            const std::size_t p = slot(m), q = slot((w - m) % w);
            const double shift_re = source_shift_re[std::size_t(m)], shift_im = source_shift_im[std::size_t(m)];
            double* even =
                &spectra[((std::size_t(block) * std::size_t(bands) + std::size_t(m)) * std::size_t(parities)) * 6 *
                         kBlock];
            double* odd = even + std::size_t(parities - 1) * 6 * kBlock;  // the same when one parity
            for (int c = 0; c < 3; ++c) {
                // The transform and the half of it that holds channel c of the north (X) and south (Y) rows.
                const int north_t = c < 2 ? 0 : 2, south_t = c < 2 ? 1 : 2;
                const bool north_imag = c == 1, south_imag = c != 0;
                for (int b = 0; b < kBlock; ++b) {
                    auto unpack = [&](int t, bool imag, double& value_re, double& value_im) {
                        const double zpr = re_of(t)[p + std::size_t(b)], zpi = im_of(t)[p + std::size_t(b)];
                        const double zqr = re_of(t)[q + std::size_t(b)], zqi = im_of(t)[q + std::size_t(b)];
                        value_re = imag ? 0.5 * (zpi + zqi) : 0.5 * (zpr + zqr);
                        value_im = imag ? 0.5 * (zqr - zpr) : 0.5 * (zpi - zqi);
                    };
                    double nr, ni, sr, si;
                    unpack(north_t, north_imag, nr, ni);
                    unpack(south_t, south_imag, sr, si);
                    nr *= north_weight[b], ni *= north_weight[b], sr *= south_weight[b], si *= south_weight[b];
                    const double er = nr + sr, ei = ni + si, or_ = nr - sr, oi = ni - si;
                    even[(2 * c) * kBlock + b] = er * shift_re - ei * shift_im;
                    even[(2 * c + 1) * kBlock + b] = er * shift_im + ei * shift_re;
                    odd[(2 * c) * kBlock + b] = or_ * shift_re - oi * shift_im;
                    odd[(2 * c + 1) * kBlock + b] = or_ * shift_im + oi * shift_re;
                }
            }
        }
    });

    // c_lm = sum over pairs of P_lm(cos theta) (F_north +- F_south)(m), one task per order m; 6 doubles per
    // coefficient, by order: coefficients[recurrence.offset(m) * 6 + (l - m) * 6 + q].
    Scratch<double> coefficients = scratch<double>(recurrence.offset(bands) * 6);
    tbb::parallel_for(0, bands, [&](int m) {
        ThreadScratch& local = local_scratch();
        order_coefficients(recurrence, m, blocks, bands, parities, spectra.get(), block_x.get(), block_pmm.get(),
                           local.p1.get(), local.p2.get(), &coefficients[recurrence.offset(m) * 6]);
    });

    // Each level: G_m(theta) = sum_l Lambda_l c_lm P_lm(cos theta), then each row by an inverse FFT of
    // G_0 + 2 sum_{m > 0} G_m e^{i m phi}. One task per group and block of kBlock northern rows, whose
    // recurrences give its southern mirrors too, from the sums over even and odd l - m.
    struct Task {
        int group, block;
    };
    std::vector<Task> tasks;
    for (std::size_t g = 0; g < groups.size(); ++g) {
        for (std::size_t k = groups[g].first; k < groups[g].end; ++k)
            grids[k].texels.resize(std::size_t(groups[g].width) * std::size_t(groups[g].height));
        for (int block = 0; block < groups[g].blocks; ++block) tasks.push_back({int(g), block});
    }
    std::reverse(tasks.begin(), tasks.end());  // the widest grids first
    tbb::parallel_for(0, int(tasks.size()), [&](int t) {
        const Group& group = groups[std::size_t(tasks[std::size_t(t)].group)];
        const int block = tasks[std::size_t(t)].block, width = group.width, height = group.height;
        const int levels = int(group.end - group.first);
        ThreadScratch& local = local_scratch();
        alignas(64) double x[kBlock], s[kBlock];
        for (int b = 0; b < kBlock; ++b) {
            const int j = std::min(block * kBlock + b, group.north - 1);
            const double theta = kPi * j / (height - 1);  // rows from pole to pole (prefilter.h)
            x[b] = std::cos(theta);
            s[b] = std::sin(theta);
        }
        double* pmm = local.pmm.get();
        sectoral(recurrence, s, group.band, pmm);
        const int last_order = last_nonzero_order(pmm, group.band);

        // Per level and channel one complex row per lane: the northern row in the real part, the southern one in
        // the imaginary part (two real rows through one transform, as in the analysis).
        // [level][channel][re/im][i][lane].
        const std::size_t row_size = std::size_t(width) * kBlock;
        double* rows = local.rows.get();
        auto row_re = [&](int g, int c) { return rows + std::size_t((g * 3 + c) * 2) * row_size; };
        for (int g = 0; g < levels; ++g) {  // orders above the level's band (or underflowed) are zero
            const int zero_from = std::min(plans[group.first + std::size_t(g)].band, last_order) + 1;
            for (int c = 0; c < 3; ++c) {
                double* re = row_re(g, c);
                std::fill(re + std::size_t(zero_from) * kBlock, re + std::size_t(width - zero_from + 1) * kBlock, 0.0);
                std::fill(re + row_size + std::size_t(zero_from) * kBlock,
                          re + row_size + std::size_t(width - zero_from + 1) * kBlock, 0.0);
            }
        }
        double* legendre = local.legendre.get();
        for (int m = 0; m <= last_order; ++m) {
            order_legendre(recurrence, x, &pmm[std::size_t(m) * kBlock], m, group.band, legendre);
            const double* c_m = &coefficients[recurrence.offset(m) * 6];
            for (int g = 0; g < levels; ++g) {
                const LobePlan& plan = plans[group.first + std::size_t(g)];
                if (m > plan.band) continue;
                alignas(64) double sums[2][6][kBlock];
                degree_sums(legendre, c_m, plan.factors.data() + m, m, plan.band, sums);
                // North X = (even + odd) e^{i pi m / W}, south Y = (even - odd) e^{i pi m / W}; the row
                // X_0 + 2 Re sum_{m > 0} X_m e^{i m phi} (X_0 real) is the transform of X_m at m and conj X_m
                // at W - m. Packed with Y: Z_m = X_m + i Y_m, Z_{W-m} = conj X_m + i conj Y_m.
                const double shift_re = group.shift_re[std::size_t(m)], shift_im = group.shift_im[std::size_t(m)];
                const std::size_t at_m = std::size_t(m) * kBlock, at_mirror = std::size_t(width - m) * kBlock;
                for (int c = 0; c < 3; ++c) {
                    double* re = row_re(g, c);
                    double* im = re + row_size;
                    for (int b = 0; b < kBlock; ++b) {
                        const double er = sums[0][2 * c][b], ei = sums[0][2 * c + 1][b];
                        const double or_ = sums[1][2 * c][b], oi = sums[1][2 * c + 1][b];
                        const double nr = er + or_, ni = ei + oi, sr = er - or_, si = ei - oi;
                        const double xr = nr * shift_re - ni * shift_im, xi = nr * shift_im + ni * shift_re;
                        const double yr = sr * shift_re - si * shift_im, yi = sr * shift_im + si * shift_re;
                        if (m == 0) {
                            re[b] = xr;
                            im[b] = yr;
                        } else {
                            re[at_m + std::size_t(b)] = xr - yi;
                            im[at_m + std::size_t(b)] = xi + yr;
                            re[at_mirror + std::size_t(b)] = xr + yi;
                            im[at_mirror + std::size_t(b)] = yr - xi;
                        }
                    }
                }
            }
        }
        for (int g = 0; g < levels; ++g) {
            for (int c = 0; c < 3; ++c) block_fft(group.fft, row_re(g, c), row_re(g, c) + row_size, 1.0);
            LobeGrid& level = grids[group.first + std::size_t(g)];
            const double* re[3] = {row_re(g, 0), row_re(g, 1), row_re(g, 2)};
            const int rows_here = std::min(kBlock, group.north - block * kBlock);
            glm::vec3* north_texels[kBlock];
            glm::vec3* south_texels[kBlock];  // null for a middle row, its own mirror
            for (int b = 0; b < rows_here; ++b) {
                const int north_row = block * kBlock + b, south_row = height - 1 - north_row;
                north_texels[b] = &level.texels[std::size_t(north_row) * std::size_t(width)];
                south_texels[b] =
                    south_row != north_row ? &level.texels[std::size_t(south_row) * std::size_t(width)] : nullptr;
            }
            for (int i = 0; i < width; ++i) {  // the transforms' output is bit-reversed
                const std::size_t at = std::size_t(group.fft.reversed[std::size_t(i)]) * kBlock;
                auto texel = [&](std::size_t from) {  // the truncated expansion may ring a little below zero
                    return glm::vec3(float(std::max(re[0][from], 0.0)), float(std::max(re[1][from], 0.0)),
                                     float(std::max(re[2][from], 0.0)));
                };
                for (int b = 0; b < rows_here; ++b) {
                    north_texels[b][i] = texel(at + std::size_t(b));
                    if (south_texels[b]) south_texels[b][i] = texel(at + std::size_t(b) + row_size);
                }
            }
        }
    });
    return grids;
}

glm::vec3 sample_grid(int width, int height, const glm::vec3* texels, const glm::dvec3& direction) {
    const glm::dvec2 uv = latlong::uv(direction);
    const double x = uv.x * width - 0.5, y = uv.y * (height - 1);
    const double fx = std::floor(x), fy = std::floor(y);
    const double ax = x - fx, ay = y - fy;
    const int i0 = (int(fx) % width + width) % width, i1 = (i0 + 1) % width;
    const int j0 = int(fy), j1 = std::min(j0 + 1, height - 1);
    auto at = [&](int i, int j) { return glm::dvec3(texels[std::size_t(j) * std::size_t(width) + std::size_t(i)]); };
    const glm::dvec3 top = at(i0, j0) * (1.0 - ax) + at(i1, j0) * ax;
    const glm::dvec3 bottom = at(i0, j1) * (1.0 - ax) + at(i1, j1) * ax;
    return glm::vec3(top * (1.0 - ay) + bottom * ay);
}

}  // namespace envshadow::prefiltering
