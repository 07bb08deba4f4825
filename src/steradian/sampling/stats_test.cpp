#include "steradian/sampling/stats.h"

#include <gtest/gtest.h>

#include <cmath>
#include <numbers>
#include <vector>

namespace sr {
namespace {

TEST(Stats, Chi2SurvivalMatchesClosedForms) {
    for (double x : {0.01, 0.5, 1.0, 2.0, 3.7, 10.0, 25.0, 60.0}) {
        // dof 2: exponential with mean 2.
        EXPECT_NEAR(chi2_sf(x, 2), std::exp(-x / 2), 1e-12 + 1e-10 * std::exp(-x / 2)) << x;
        // dof 1: the square of a standard normal, P[Z^2 >= x] = erfc(sqrt(x/2)).
        EXPECT_NEAR(chi2_sf(x, 1), std::erfc(std::sqrt(x / 2)), 1e-12) << x;
        // dof 4: Erlang(2, 1/2) tail, exp(-x/2) (1 + x/2).
        EXPECT_NEAR(chi2_sf(x, 4), std::exp(-x / 2) * (1 + x / 2), 1e-12) << x;
        // dof 3: erfc(sqrt(x/2)) + sqrt(2x/pi) exp(-x/2).
        EXPECT_NEAR(
            chi2_sf(x, 3),
            std::erfc(std::sqrt(x / 2)) + std::sqrt(2 * x / std::numbers::pi) * std::exp(-x / 2),
            1e-12)
            << x;
    }
    EXPECT_EQ(chi2_sf(0, 5), 1.0);
}

TEST(Stats, Chi2SurvivalMatchesTabulatedQuantiles) {
    // Upper 5% and 1% points of the chi-square distribution (NIST/SEMATECH e-Handbook of
    // Statistical Methods, Sec. 1.3.6.7.4), given to three decimals.
    EXPECT_NEAR(chi2_sf(18.307, 10), 0.05, 1e-4);
    EXPECT_NEAR(chi2_sf(23.209, 10), 0.01, 1e-4);
    EXPECT_NEAR(chi2_sf(124.342, 100), 0.05, 1e-4);
    EXPECT_NEAR(chi2_sf(135.807, 100), 0.01, 1e-4);
}

TEST(Stats, IncompleteGammaHalvesSumToOne) {
    for (double a : {0.5, 1.0, 3.0, 12.5, 200.0}) {
        for (double x : {0.1, 1.0, a, a + 1, 2 * a + 5}) {
            EXPECT_NEAR(gamma_p(a, x) + gamma_q(a, x), 1.0, 1e-12);
        }
    }
    // P(1, x) = 1 - exp(-x).
    EXPECT_NEAR(gamma_p(1, 0.3), -std::expm1(-0.3), 1e-14);
}

TEST(Stats, NormalTails) {
    EXPECT_DOUBLE_EQ(normal_cdf(0), 0.5);
    EXPECT_NEAR(normal_two_sided_p(1.959963984540054), 0.05, 1e-12);
    EXPECT_NEAR(normal_two_sided_p(-2.5758293035489), 0.01, 1e-12);
    EXPECT_NEAR(normal_cdf(1) + normal_cdf(-1), 1.0, 1e-15);
    EXPECT_NEAR(z_test_p(1.0, 0.0, 1.0), 1 - (normal_cdf(1) - normal_cdf(-1)), 1e-12);
    EXPECT_EQ(z_test_p(3.0, 3.0, 0.0), 1.0);
}

TEST(Stats, SidakKeepsFamilyWiseLevel) {
    EXPECT_NEAR(sidak_alpha(0.05, 1), 0.05, 1e-15);
    for (int n : {2, 10, 1000}) {
        double a = sidak_alpha(0.01, n);
        EXPECT_NEAR(1 - std::pow(1 - a, n), 0.01, 1e-12);
        EXPECT_LT(a, 0.01 / n * 1.01);
    }
}

TEST(Stats, Chi2TestPerfectFitAndPooling) {
    std::vector<double> e = {100, 200, 300, 400};
    Chi2Result r = chi2_test(e, e);
    EXPECT_EQ(r.statistic, 0);
    EXPECT_EQ(r.dof, 3);
    EXPECT_EQ(r.p_value, 1);

    // Sparse cells (E < 5) are pooled: 1 + 2 + 3 = 6 forms one cell; dof = 3 cells - 1.
    std::vector<double> es = {1, 2, 3, 50, 50};
    std::vector<double> os = {0, 3, 3, 50, 50};
    r = chi2_test(os, es);
    EXPECT_EQ(r.pooled_cells, 3);
    EXPECT_EQ(r.dof, 2);
    EXPECT_NEAR(r.statistic, 0.0, 1e-12);

    // A leftover pool below the threshold joins the smallest regular cell.
    std::vector<double> el = {1, 10, 20};
    std::vector<double> ol = {1, 10, 20};
    r = chi2_test(ol, el);
    EXPECT_EQ(r.dof, 1);

    // A sample where the density is zero fails outright.
    std::vector<double> ez = {0, 50, 50}, oz = {1, 49, 50};
    r = chi2_test(oz, ez);
    EXPECT_EQ(r.p_value, 0);

    // A gross misfit is rejected.
    std::vector<double> eb = {250, 250, 250, 250}, ob = {400, 200, 200, 200};
    EXPECT_LT(chi2_test(ob, eb).p_value, 1e-10);
}

TEST(Stats, SimpsonIsExactForCubics) {
    auto cubic = [](double x) { return 2 * x * x * x - x + 3; };
    // Integral over [-1, 2]: [x^4/2 - x^2/2 + 3x] = (8 - 2 + 6) - (0.5 - 0.5 - 3) = 15.
    EXPECT_NEAR(simpson_1d(cubic, -1, 2, 2), 15.0, 1e-12);
    EXPECT_NEAR(simpson_2d([](double x, double y) { return x * y; }, 0, 1, 0, 2, 4, 4), 1.0, 1e-12);
}

}  // namespace
}  // namespace sr
