#pragma once
/// Small statistics toolbox for tests that prove sampling code right: chi-square and normal
/// tail probabilities, a Pearson chi-square goodness-of-fit test with pooling of sparse cells
/// (as in Mitsuba's chi2 test library), and the Sidak multiple-testing correction.
/// Everything is in double precision.
#include <span>
#include <utility>

namespace sr {

/// Regularized lower incomplete gamma P(a, x) = gamma(a, x) / Gamma(a), a > 0, x >= 0.
double gamma_p(double a, double x);
/// Regularized upper incomplete gamma Q(a, x) = 1 - P(a, x), computed directly (not as
/// 1 - P) so that small tail probabilities keep their relative accuracy.
double gamma_q(double a, double x);

/// Survival function of the chi-square distribution with dof degrees of freedom:
/// P[X >= x] = Q(dof/2, x/2). This is the p-value of a chi-square statistic x.
double chi2_sf(double x, double dof);

/// Standard normal CDF Phi(z).
double normal_cdf(double z);
/// Two-sided p-value of a standard normal statistic: P[|Z| >= |z|] = erfc(|z| / sqrt(2)).
double normal_two_sided_p(double z);
/// Two-sided z-test of an estimated mean against an expected value with the given standard
/// error: the p-value of (mean - expected) / std_error (1 if both differences vanish).
double z_test_p(double mean, double expected, double std_error);

/// Per-test significance level that keeps the family-wise error rate at alpha over
/// num_tests independent tests (Sidak 1967): 1 - (1 - alpha)^(1 / num_tests).
double sidak_alpha(double alpha, int num_tests);

struct Chi2Result {
    double statistic = 0;  ///< Pearson's sum (O - E)^2 / E over the pooled cells
    int dof = 0;           ///< number of cells after pooling, minus one
    double p_value = 1;    ///< chi2_sf(statistic, dof); 0 if a sample fell where E == 0
    int pooled_cells = 0;  ///< how many sparse cells were pooled
};

/// Pearson chi-square test of observed counts against expected counts (same total). Cells
/// with an expected count below min_expected are pooled, smallest first, into merged cells
/// of at least min_expected (a left-over remainder is added to the smallest regular cell).
/// A cell with E == 0 but O > 0 makes the test fail outright (p = 0): samples were generated
/// where the density claims there are none.
Chi2Result chi2_test(std::span<const double> observed, std::span<const double> expected,
                     double min_expected = 5);

/// Composite Simpson rule for the integral of f over [a, b] with n intervals (n rounded up to
/// an even number). Exact for cubics; error O(n^-4) for smooth f.
template <typename F>
double simpson_1d(F&& f, double a, double b, int n) {
    n = n < 2 ? 2 : n + (n & 1);
    double h = (b - a) / n;
    double sum = f(a) + f(b);
    for (int i = 1; i < n; ++i) sum += (i & 1 ? 4 : 2) * f(a + i * h);
    return sum * h / 3;
}

/// Tensor-product composite Simpson rule for the integral of f(x, y) over
/// [x0, x1] x [y0, y1] with nx by ny intervals (e.g. a pdf over a chi-square cell, with the
/// cell's Jacobian included in f).
template <typename F>
double simpson_2d(F&& f, double x0, double x1, double y0, double y1, int nx, int ny) {
    return simpson_1d(
        [&](double y) { return simpson_1d([&](double x) { return f(x, y); }, x0, x1, nx); }, y0, y1,
        ny);
}

}  // namespace sr
