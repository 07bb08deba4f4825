// PiecewiseLinear2D: the bilinear interpolant is exact for bilinear functions; the density's
// samples follow it (chi-square against cell integrals computed independently, exact for a
// bilinear function on each patch); invert() undoes sample(); densities at a parameter between
// tabulated values are the linear blend of the neighbouring slices' normalised densities (and
// are sampled as such); bad tables are sr::Errors.
#include "steradian/sampling/piecewise_linear_2d.h"

#include <gtest/gtest.h>

#include <vector>

#include "steradian/core/error.h"
#include "steradian/sampling/rng.h"
#include "steradian/sampling/stats.h"

namespace sr {
namespace {

const double kAlpha = sidak_alpha(0.01, 2);

/// Integral over the unit square of the bilinear interpolant of v (nx x ny, x fastest):
/// per patch the mean of its four corners times its area.
double bilinear_integral(const std::vector<float>& v, int nx, int ny) {
    double sum = 0;
    for (int y = 0; y + 1 < ny; ++y)
        for (int x = 0; x + 1 < nx; ++x)
            sum += 0.25 * (v[y * nx + x] + v[y * nx + x + 1] + v[(y + 1) * nx + x] +
                           v[(y + 1) * nx + x + 1]);
    return sum / ((nx - 1) * (ny - 1));
}

/// The bilinear interpolant of v at (px, py), written out independently of the class.
double bilinear(const std::vector<float>& v, int nx, int ny, double px, double py) {
    double x = px * (nx - 1), y = py * (ny - 1);
    int i = std::min(int(x), nx - 2), j = std::min(int(y), ny - 2);
    double s = x - i, t = y - j;
    return (1 - t) * ((1 - s) * v[j * nx + i] + s * v[j * nx + i + 1]) +
           t * ((1 - s) * v[(j + 1) * nx + i] + s * v[(j + 1) * nx + i + 1]);
}

/// Chi-square of `n` samples of `draw` against density `dens` on a histogram of `sub` bins
/// per patch and axis (each bin inside one patch, where Simpson's rule is exact).
template <typename Draw, typename Dens>
Chi2Result histogram_chi2(Draw&& draw, Dens&& dens, int nx, int ny, int sub, int n) {
    const int bx = (nx - 1) * sub, by = (ny - 1) * sub;
    std::vector<double> observed(size_t(bx * by), 0), expected(size_t(bx * by));
    for (int k = 0; k < n; ++k) {
        Point2 p = draw(k);
        int i = std::min(int(p.x * bx), bx - 1), j = std::min(int(p.y * by), by - 1);
        observed[size_t(j * bx + i)] += 1;
    }
    for (int j = 0; j < by; ++j)
        for (int i = 0; i < bx; ++i)
            expected[size_t(j * bx + i)] = n * simpson_2d(dens, double(i) / bx, double(i + 1) / bx,
                                                          double(j) / by, double(j + 1) / by, 2, 2);
    return chi2_test(observed, expected);
}

// A bumpy table with a zero row, a zero column and an isolated zero.
const std::vector<float> kTable = {0, 1, 2,    0.5f, 3, 0, 0, 0, 0, 0,
                                   4, 0, 1.5f, 2,    6, 1, 2, 3, 0, 0.2f};
constexpr int kNx = 5, kNy = 4;

TEST(PiecewiseLinear2D, InterpolantIsExactForBilinearFunctions) {
    // f = 1 + 2 x - 3 y + 5 x y is reproduced exactly by bilinear interpolation.
    const int nx = 4, ny = 6;
    auto f = [](double x, double y) { return 1 + 2 * x - 3 * y + 5 * x * y; };
    std::vector<float> v;
    for (int y = 0; y < ny; ++y)
        for (int x = 0; x < nx; ++x) v.push_back(float(f(x / 3.0, y / 5.0)));
    PiecewiseLinear2D t(v, nx, ny, {}, false);
    Pcg32 rng(7);
    for (int k = 0; k < 1000; ++k) {
        Point2 p{rng.next_float(), rng.next_float()};
        EXPECT_NEAR(t.evaluate(p), f(p.x, p.y), 1e-5) << p.x << " " << p.y;
    }
}

TEST(PiecewiseLinear2D, DensityIsNormalisedAndSampledChi2) {
    PiecewiseLinear2D t(kTable, kNx, kNy, {}, true);
    const double integral = bilinear_integral(kTable, kNx, kNy);
    auto dens = [&](double x, double y) { return bilinear(kTable, kNx, kNy, x, y) / integral; };
    Pcg32 rng(11);
    for (int k = 0; k < 200; ++k) {
        Point2 p{rng.next_float(), rng.next_float()};
        EXPECT_NEAR(t.evaluate(p), dens(p.x, p.y), 1e-5);
    }
    Chi2Result r = histogram_chi2(
        [&](int) {
            PiecewiseLinear2D::Sample s = t.sample({rng.next_float(), rng.next_float()});
            EXPECT_NEAR(s.pdf, dens(s.p.x, s.p.y), 1e-4 * (1 + s.pdf));
            return s.p;
        },
        dens, kNx, kNy, 3, 400000);
    EXPECT_GT(r.p_value, kAlpha) << "chi2 " << r.statistic << " dof " << r.dof;
}

TEST(PiecewiseLinear2D, InvertUndoesSample) {
    PiecewiseLinear2D t(kTable, kNx, kNy, {}, true);
    Pcg32 rng(13);
    for (int k = 0; k < 20000; ++k) {
        Point2 u{rng.next_float(), rng.next_float()};
        PiecewiseLinear2D::Sample s = t.sample(u);
        PiecewiseLinear2D::Sample back = t.invert(s.p);
        ASSERT_NEAR(back.p.x, u.x, 2e-4) << u.x << " " << u.y;
        ASSERT_NEAR(back.p.y, u.y, 2e-4) << u.x << " " << u.y;
        ASSERT_NEAR(back.pdf, s.pdf, 1e-4 * (1 + s.pdf));
    }
}

TEST(PiecewiseLinear2D, ParametersBlendNormalisedSlices) {
    // Two slices at parameter values 0 and 2 (the second a different shape and scale); at
    // 0.5 the density is 3/4 of the first normalised slice plus 1/4 of the second.
    const int nx = 3, ny = 3;
    std::vector<float> a = {1, 2, 0, 0, 1, 3, 2, 2, 1}, b = {9, 0, 0, 0, 0, 0, 0, 0, 30};
    std::vector<float> data = a;
    data.insert(data.end(), b.begin(), b.end());
    std::vector<std::vector<float>> params = {{0, 2}};
    PiecewiseLinear2D t(data, nx, ny, params, true);
    double ia = bilinear_integral(a, nx, ny), ib = bilinear_integral(b, nx, ny);
    auto dens = [&](double x, double y) {
        return 0.75 * bilinear(a, nx, ny, x, y) / ia + 0.25 * bilinear(b, nx, ny, x, y) / ib;
    };
    const Float p = 0.5f;
    Pcg32 rng(17);
    for (int k = 0; k < 100; ++k) {
        Point2 q{rng.next_float(), rng.next_float()};
        EXPECT_NEAR(t.evaluate(q, &p), dens(q.x, q.y), 1e-5);
    }
    Chi2Result r = histogram_chi2(
        [&](int) {
            return t.sample({rng.next_float(), rng.next_float()}, &p).p;
        },
        dens, nx, ny, 4, 400000);
    EXPECT_GT(r.p_value, kAlpha) << "chi2 " << r.statistic << " dof " << r.dof;
    // Outside the tabulated range the nearest slice stands.
    const Float below = -1, above = 5;
    Point2 q{0.3f, 0.6f};
    EXPECT_NEAR(t.evaluate(q, &below), bilinear(a, nx, ny, q.x, q.y) / ia, 1e-5);
    EXPECT_NEAR(t.evaluate(q, &above), bilinear(b, nx, ny, q.x, q.y) / ib, 1e-5);
}

TEST(PiecewiseLinear2D, BadTablesAreErrors) {
    std::vector<float> four = {1, 1, 1, 1};
    EXPECT_THROW(PiecewiseLinear2D(four, 1, 4, {}, false), Error);
    EXPECT_THROW(PiecewiseLinear2D(four, 2, 3, {}, false), Error);  // size mismatch
    std::vector<float> nan = {1, std::nanf(""), 1, 1};
    EXPECT_THROW(PiecewiseLinear2D(nan, 2, 2, {}, false), Error);
    std::vector<float> zero = {0, -1, 0, 0};
    EXPECT_THROW(PiecewiseLinear2D(zero, 2, 2, {}, true), Error);  // no mass
    EXPECT_NO_THROW(PiecewiseLinear2D(zero, 2, 2, {}, false));     // an interpolant may be 0
    std::vector<float> two(8, 1.0f);
    std::vector<std::vector<float>> decreasing = {{1, 0}};
    EXPECT_THROW(PiecewiseLinear2D(two, 2, 2, decreasing, true), Error);
}

}  // namespace
}  // namespace sr
