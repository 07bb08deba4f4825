#include "steradian/film/filter.h"

#include <gtest/gtest.h>

#include <cmath>
#include <numbers>
#include <string>
#include <vector>

#include "steradian/sampling/rng.h"
#include "steradian/sampling/stats.h"

namespace sr {
namespace {

constexpr double kPiD = std::numbers::pi;

// ---- closed forms of the filters (pbrt-v4's definitions) ------------------------------------

double gauss(double x, double sigma) {
    return std::exp(-x * x / (2 * sigma * sigma)) / std::sqrt(2 * kPiD * sigma * sigma);
}

/// The 1D filter along one axis: box 1, triangle r - |x|, gaussian g(x) - g(r); 0 for |x| > r.
double f1(FilterType type, double x, double r, double sigma) {
    if (std::abs(x) > r) return 0;
    switch (type) {
        case FilterType::Box: return 1;
        case FilterType::Triangle: return r - std::abs(x);
        case FilterType::Gaussian: return std::max(0.0, gauss(x, sigma) - gauss(r, sigma));
    }
    return 0;
}

/// Antiderivative of the 1D filter on [-r, r] (so that the integral over [a, b] is
/// F(b) - F(a)): box x; triangle r x - x |x| / 2; gaussian erf(x / (sigma sqrt 2)) / 2 - g(r) x.
double antiderivative(FilterType type, double x, double r, double sigma) {
    x = std::clamp(x, -r, r);
    switch (type) {
        case FilterType::Box: return x;
        case FilterType::Triangle: return r * x - x * std::abs(x) / 2;
        case FilterType::Gaussian:
            return 0.5 * std::erf(x / (sigma * std::sqrt(2.0))) - gauss(r, sigma) * x;
    }
    return 0;
}

double integral_1d(FilterType type, double r, double sigma) {
    return antiderivative(type, r, r, sigma) - antiderivative(type, -r, r, sigma);
}

struct Case {
    FilterType type;
    Vec2 radius;
    Float sigma;
    const char* name;
};

// pbrt-v4's defaults, plus anisotropic radii.
const Case kCases[] = {
    {FilterType::Box, {0.5f, 0.5f}, 0.5f, "box default"},
    {FilterType::Box, {1.5f, 0.75f}, 0.5f, "box anisotropic"},
    {FilterType::Triangle, {2, 2}, 0.5f, "triangle default"},
    {FilterType::Triangle, {0.5f, 1.25f}, 0.5f, "triangle anisotropic"},
    {FilterType::Gaussian, {1.5f, 1.5f}, 0.5f, "gaussian default"},
    {FilterType::Gaussian, {1.0f, 2.5f}, 0.7f, "gaussian anisotropic"},
};
constexpr int kNumChi2Tests = 6;  // one per case
const double kAlpha = sidak_alpha(0.01, kNumChi2Tests);

// ---- evaluate ---------------------------------------------------------------------------------

TEST(Filter, EvaluateMatchesClosedForms) {
    Pcg32 rng(1, 42);
    for (const Case& c : kCases) {
        Filter f(c.type, c.radius, c.sigma);
        EXPECT_EQ(f.type(), c.type);
        EXPECT_EQ(f.radius().x, c.radius.x);
        for (int k = 0; k < 2000; ++k) {
            // Points over 1.2 times the support, so the zero outside is covered too.
            double x = (2 * rng.next_float() - 1) * 1.2 * c.radius.x;
            double y = (2 * rng.next_float() - 1) * 1.2 * c.radius.y;
            double expected = f1(c.type, x, c.radius.x, c.sigma) * f1(c.type, y, c.radius.y, c.sigma);
            EXPECT_NEAR(f.evaluate(Vec2(Float(x), Float(y))), expected, 1e-5 * (1 + expected))
                << c.name << " at (" << x << ", " << y << ")";
        }
    }
}

TEST(Filter, EvaluateAtKnownPoints) {
    Filter box(FilterType::Box, {0.5f, 0.5f});
    EXPECT_EQ(box.evaluate({0.49f, -0.49f}), 1);
    EXPECT_EQ(box.evaluate({0.51f, 0}), 0);
    Filter tri(FilterType::Triangle, {2, 2});
    EXPECT_FLOAT_EQ(tri.evaluate({0, 0}), 4);      // r^2
    EXPECT_FLOAT_EQ(tri.evaluate({1, -0.5f}), 1.5f);  // (2 - 1)(2 - 0.5)
    EXPECT_EQ(tri.evaluate({2.5f, 0}), 0);
    Filter g(FilterType::Gaussian, {1.5f, 1.5f}, 0.5f);
    // Reaches zero at the radius (the value there is subtracted) and peaks at the centre with
    // (1 / sqrt(2 pi sigma^2) - g(r))^2.
    EXPECT_NEAR(g.evaluate({1.5f, 0}), 0, 1e-6);
    double peak = gauss(0, 0.5) - gauss(1.5, 0.5);
    EXPECT_NEAR(g.evaluate({0, 0}), peak * peak, 1e-5);
}

// ---- sample -----------------------------------------------------------------------------------

TEST(Filter, StratifiedSamplesStayWithinTheRadius) {
    for (const Case& c : kCases) {
        Filter f(c.type, c.radius, c.sigma);
        const int n = 128;
        Pcg32 rng(2, 7);
        for (int j = 0; j <= n; ++j) {
            for (int i = 0; i <= n; ++i) {
                // Jittered strata, plus the closed upper ends u = 1 - eps.
                Float ux = i < n ? (i + rng.next_float()) / n : kOneMinusEpsilon;
                Float uy = j < n ? (j + rng.next_float()) / n : kOneMinusEpsilon;
                if (i == 0 && j == 0) ux = uy = 0;
                FilterSample s = f.sample({ux, uy});
                ASSERT_LE(std::abs(s.offset.x), c.radius.x * (1 + 1e-6f)) << c.name;
                ASSERT_LE(std::abs(s.offset.y), c.radius.y * (1 + 1e-6f)) << c.name;
                ASSERT_TRUE(std::isfinite(s.weight)) << c.name;
            }
        }
    }
}

TEST(Filter, WeightIsTheFilterIntegral) {
    // Filter importance sampling: a sample with density p = f / integral(f) has weight
    // f / p = integral(f). The film divides by the weight sum, so the constant cancels, but it
    // must be constant (else the estimate is not the filtered image): exactly for box and
    // triangle, within 1% for the tabulated gaussian.
    for (const Case& c : kCases) {
        Filter f(c.type, c.radius, c.sigma);
        double integral =
            integral_1d(c.type, c.radius.x, c.sigma) * integral_1d(c.type, c.radius.y, c.sigma);
        double tol = c.type == FilterType::Gaussian ? 1e-2 : 1e-5;
        Pcg32 rng(3, 11);
        double wmin = 1e30, wmax = -1e30;
        for (int k = 0; k < 20000; ++k) {
            FilterSample s = f.sample({rng.next_float(), rng.next_float()});
            if (f.evaluate(s.offset) == 0) continue;  // the measure-zero rim
            wmin = std::min(wmin, double(s.weight));
            wmax = std::max(wmax, double(s.weight));
        }
        EXPECT_NEAR(wmin / integral, 1, tol) << c.name << ": integral " << integral;
        EXPECT_NEAR(wmax / integral, 1, tol) << c.name << ": integral " << integral;
    }
}

TEST(Filter, ClosedFormIntegralsOfTheDefaults) {
    // Box 0.5: area 1; triangle 2: (r^2)^2 = 16; gaussian 1.5, sigma 0.5:
    // (erf(1.5 / (0.5 sqrt 2)) - 2 * 1.5 * g(1.5))^2 (a sanity check of the helpers above
    // against independently known numbers: erf(3 / sqrt 2) = 0.99730020).
    EXPECT_NEAR(integral_1d(FilterType::Box, 0.5, 0.5), 1, 1e-15);
    EXPECT_NEAR(integral_1d(FilterType::Triangle, 2, 0.5), 4, 1e-15);
    EXPECT_NEAR(integral_1d(FilterType::Gaussian, 1.5, 0.5),
                0.99730020 - 3 * 0.7978845608 * std::exp(-4.5), 1e-7);
}

/// Chi-square test of sampled offsets against the filter integrated over the cells of a
/// 21 x 21 grid on [-rx, rx] x [-ry, ry] (the filters are separable, so each cell's mass is a
/// product of closed-form 1D integrals).
TEST(Filter, SampleDistributionMatchesTheFilterShape) {
    const int nc = 21;
    const int n_samples = 400000;
    for (const Case& c : kCases) {
        Filter f(c.type, c.radius, c.sigma);
        double ix = integral_1d(c.type, c.radius.x, c.sigma);
        double iy = integral_1d(c.type, c.radius.y, c.sigma);
        std::vector<double> mx(nc), my(nc);
        for (int i = 0; i < nc; ++i) {
            double ax = -c.radius.x + 2.0 * c.radius.x * i / nc;
            double bx = -c.radius.x + 2.0 * c.radius.x * (i + 1) / nc;
            mx[i] = (antiderivative(c.type, bx, c.radius.x, c.sigma) -
                     antiderivative(c.type, ax, c.radius.x, c.sigma)) / ix;
            double ay = -c.radius.y + 2.0 * c.radius.y * i / nc;
            double by = -c.radius.y + 2.0 * c.radius.y * (i + 1) / nc;
            my[i] = (antiderivative(c.type, by, c.radius.y, c.sigma) -
                     antiderivative(c.type, ay, c.radius.y, c.sigma)) / iy;
        }
        std::vector<double> observed(nc * nc, 0.0), expected(nc * nc, 0.0);
        for (int j = 0; j < nc; ++j)
            for (int i = 0; i < nc; ++i) expected[j * nc + i] = mx[i] * my[j] * n_samples;
        Pcg32 rng(4, 1000 + uint64_t(c.type));
        for (int k = 0; k < n_samples; ++k) {
            FilterSample s = f.sample({rng.next_float(), rng.next_float()});
            int i = int(std::floor((s.offset.x + c.radius.x) / (2 * c.radius.x) * nc));
            int j = int(std::floor((s.offset.y + c.radius.y) / (2 * c.radius.y) * nc));
            i = std::clamp(i, 0, nc - 1);  // an offset of exactly +r
            j = std::clamp(j, 0, nc - 1);
            observed[j * nc + i] += 1;
        }
        Chi2Result r = chi2_test(observed, expected);
        EXPECT_GT(r.p_value, kAlpha) << c.name << ": chi2 = " << r.statistic << ", dof " << r.dof;
    }
}

TEST(Filter, ChiSquareDetectsAWrongShape) {
    // The same test must reject a box-distributed sample set against the triangle's shape
    // (guards against a chi-square harness that cannot fail).
    const int nc = 21, n_samples = 400000;
    Filter box(FilterType::Box, {2, 2});
    std::vector<double> m(nc);
    for (int i = 0; i < nc; ++i)
        m[i] = (antiderivative(FilterType::Triangle, -2 + 4.0 * (i + 1) / nc, 2, 0.5) -
                antiderivative(FilterType::Triangle, -2 + 4.0 * i / nc, 2, 0.5)) / 4;
    std::vector<double> observed(nc * nc, 0.0), expected(nc * nc, 0.0);
    for (int j = 0; j < nc; ++j)
        for (int i = 0; i < nc; ++i) expected[j * nc + i] = m[i] * m[j] * n_samples;
    Pcg32 rng(4, 5);
    for (int k = 0; k < n_samples; ++k) {
        FilterSample s = box.sample({rng.next_float(), rng.next_float()});
        int i = std::clamp(int(std::floor((s.offset.x + 2) / 4 * nc)), 0, nc - 1);
        int j = std::clamp(int(std::floor((s.offset.y + 2) / 4 * nc)), 0, nc - 1);
        observed[j * nc + i] += 1;
    }
    EXPECT_LT(chi2_test(observed, expected).p_value, 1e-12);
}

TEST(Filter, BoxAndTriangleSamplesFollowTheInverseCdf) {
    // Box: x = lerp(u, -r, r). Triangle: the tent's CDF is F(x) = (r + x)^2 / (2 r^2) for
    // x < 0, so u = 1/8 (F = 1/8 at x = -r/2) maps to -r/2 and u = 1/2 to 0.
    Filter box(FilterType::Box, {0.5f, 1.5f});
    FilterSample b = box.sample({0.25f, 0.75f});
    EXPECT_NEAR(b.offset.x, -0.25, 1e-6);
    EXPECT_NEAR(b.offset.y, 0.75, 1e-6);
    Filter tri(FilterType::Triangle, {2, 2});
    FilterSample t = tri.sample({0.125f, 0.5f});
    EXPECT_NEAR(t.offset.x, -1, 1e-6);
    EXPECT_NEAR(t.offset.y, 0, 1e-6);
    t = tri.sample({0.875f, 0.0f});
    EXPECT_NEAR(t.offset.x, 1, 1e-6);
    EXPECT_NEAR(t.offset.y, -2, 1e-6);
}

}  // namespace
}  // namespace sr
