// Prints the data of Barsi et al.'s Figs. 5 and 6 as CSV for the accuracy document (not a test):
//   brdf_figures fig5   single-sample / exact cap average at psi_c = 0 against r, n = 10, 100, 1000
//   brdf_figures fig6   exact, blended and single-sample averages against psi_c for r = pi/8
// Averages are per unit k_s. "exact" is numerical integration over the cap (tests/brdf/cap_quadrature.h).
#include <cmath>
#include <cstdio>
#include <cstring>
#include <numbers>

#include "brdf/cap_quadrature.h"
#include "env/brdf.h"

namespace {

constexpr double kPi = std::numbers::pi;
constexpr double kShininess[] = {10.0, 100.0, 1000.0};

double exact_average(double cos_psi_c, double cos_r, double n) {
    return envshadow::testing::cap_average_by_rings([n](double c) { return std::pow(std::max(c, 0.0), n); }, cos_psi_c,
                                                    cos_r);
}

void figure5() {
    std::printf("n,r,exact,single,blended,single_over_exact,blended_over_exact\n");
    for (double n : kShininess) {
        for (int k = 1; k <= 100; ++k) {
            const double r = kPi / 2.0 * k / 100.0;
            const float cos_r = float(std::cos(r));
            const double exact = exact_average(1.0, cos_r, n);
            const double single = envshadow::brdf::average_specular_single(1.0f, float(n));
            const double blended = envshadow::brdf::average_specular_blended(1.0f, cos_r, float(n));
            std::printf("%g,%.6f,%.9g,%.9g,%.9g,%.9g,%.9g\n", n, r, exact, single, blended, single / exact,
                        blended / exact);
        }
    }
}

void figure6() {
    const double r = kPi / 8.0;
    const float cos_r = float(std::cos(r));
    std::printf("n,r,psi_c,exact,blended,single\n");
    for (double n : kShininess) {
        for (int k = 0; k <= 160; ++k) {
            const double psi_c = 2.0 * r * k / 160.0;  // the paper plots [0, r]; the rim and beyond show the join
            const float c = float(std::cos(psi_c));
            std::printf("%g,%.6f,%.6f,%.9g,%.9g,%.9g\n", n, r, psi_c, exact_average(c, cos_r, n),
                        double(envshadow::brdf::average_specular_blended(c, cos_r, float(n))),
                        double(envshadow::brdf::average_specular_single(c, float(n))));
        }
    }
}

}  // namespace

int main(int argc, char** argv) {
    if (argc == 2 && std::strcmp(argv[1], "fig5") == 0) {
        figure5();
        return 0;
    }
    if (argc == 2 && std::strcmp(argv[1], "fig6") == 0) {
        figure6();
        return 0;
    }
    std::fprintf(stderr, "usage: brdf_figures fig5|fig6  (CSV on stdout)\n");
    return 2;
}
