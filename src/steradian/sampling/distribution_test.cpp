#include "steradian/sampling/distribution.h"

#include <gtest/gtest.h>

#include <cmath>
#include <numeric>
#include <vector>

#include "steradian/core/error.h"
#include "steradian/sampling/rng.h"
#include "steradian/sampling/stats.h"

namespace sr {
namespace {

const double kAlpha = sidak_alpha(0.01, 10);

/// Normalized weights, computed independently of the classes under test.
std::vector<double> normalized(const std::vector<Float>& w) {
    double sum = 0;
    for (Float x : w) sum += x;
    std::vector<double> p;
    for (Float x : w) p.push_back(sum > 0 ? x / sum : 1.0 / double(w.size()));
    return p;
}

std::vector<Float> test_weights() {
    // Includes leading, interior and trailing zeros and a wide dynamic range.
    return {0, 1, 3, 0, 0.5f, 10, 2, 0, 7, 0.01f, 4, 0};
}

TEST(Distribution1D, DiscreteSamplingMatchesPmf) {
    std::vector<Float> w = test_weights();
    Distribution1D d(w);
    std::vector<double> p = normalized(w);
    const int n = 300000;
    std::vector<double> observed(w.size(), 0.0), expected(w.size());
    for (std::size_t i = 0; i < w.size(); ++i) {
        expected[i] = p[i] * n;
        EXPECT_NEAR(d.pmf(int(i)), p[i], 1e-6);
    }
    Pcg32 rng(1);
    for (int s = 0; s < n; ++s) {
        Float pmf;
        int i = d.sample_discrete(rng.next_float(), &pmf);
        ASSERT_GE(i, 0);
        ASSERT_LT(i, int(w.size()));
        ASSERT_GT(w[std::size_t(i)], 0) << "sampled a zero-weight bin";
        EXPECT_EQ(pmf, d.pmf(i));
        observed[std::size_t(i)] += 1;
    }
    EXPECT_GT(chi2_test(observed, expected).p_value, kAlpha);
}

TEST(Distribution1D, RemappedVariateIsUniform) {
    std::vector<Float> w = test_weights();
    Distribution1D d(w);
    Pcg32 rng(2);
    const int n = 200000, bins = 20;
    std::vector<double> observed(bins, 0.0), expected(bins, double(n) / bins);
    for (int s = 0; s < n; ++s) {
        Float ur;
        d.sample_discrete(rng.next_float(), nullptr, &ur);
        ASSERT_GE(ur, 0);
        ASSERT_LT(ur, 1);
        observed[std::size_t(ur * bins)] += 1;
    }
    EXPECT_GT(chi2_test(observed, expected).p_value, kAlpha);
}

TEST(Distribution1D, ContinuousSamplingOnRange) {
    std::vector<Float> w = test_weights();
    const Float lo = -2, hi = 4;
    Distribution1D d(w, lo, hi);
    std::vector<double> p = normalized(w);
    double width = (hi - lo) / double(w.size());
    // Integral of the step function: sum * bin width.
    double sum = std::accumulate(w.begin(), w.end(), 0.0);
    EXPECT_NEAR(d.integral(), sum * width, 1e-5);
    // The pdf integrates to 1 (midpoint rule, exact for a step function with aligned cells).
    double total = 0;
    const int fine = 50;
    for (std::size_t i = 0; i < w.size() * fine; ++i) {
        total += d.pdf(Float(lo + (double(i) + 0.5) * width / fine)) * width / fine;
    }
    EXPECT_NEAR(total, 1.0, 1e-5);

    // Chi-square with two cells per bin: inside a bin the density is flat.
    const int n = 300000;
    std::vector<double> observed(2 * w.size(), 0.0), expected(2 * w.size());
    for (std::size_t i = 0; i < 2 * w.size(); ++i) expected[i] = p[i / 2] / 2 * n;
    Pcg32 rng(3);
    for (int s = 0; s < n; ++s) {
        Float pdf;
        int offset;
        Float x = d.sample_continuous(rng.next_float(), &pdf, &offset);
        ASSERT_GE(x, lo);
        ASSERT_LT(x, hi);
        EXPECT_EQ(pdf, d.pdf(x));
        EXPECT_GT(pdf, 0);
        auto cell = std::size_t(std::floor((x - lo) / (width / 2)));
        EXPECT_EQ(std::size_t(offset), cell / 2);
        observed[std::min(cell, observed.size() - 1)] += 1;
    }
    EXPECT_GT(chi2_test(observed, expected).p_value, kAlpha);
    EXPECT_EQ(d.pdf(lo - 1), 0);
    EXPECT_EQ(d.pdf(hi + 1), 0);
}

// The bin chosen for u is the CDF's inverse: the largest bin whose CDF value (a prefix sum
// in double, rounded to float) is <= u, zero-width bins skipped, found here by a linear scan
// and there through the guide table.
TEST(Distribution1D, ChosenBinIsTheInverseCdf) {
    Pcg32 rng(11);
    for (int n : {1, 2, 7, 64, 1000}) {
        std::vector<Float> f(static_cast<size_t>(n));
        for (int i = 0; i < n; ++i) {
            const Float r = rng.next_float();
            f[size_t(i)] = r < 0.3f ? 0 : r < 0.35f ? 1000 * r : r;  // zeros and spikes
        }
        Distribution1D d(f);
        std::vector<Float> cdf(size_t(n) + 1, 0);
        double sum = 0;
        for (Float v : f) sum += double(v);
        double acc = 0;
        for (int i = 0; i < n; ++i)  // (all zero: uniform, as documented)
            cdf[size_t(i) + 1] =
                sum > 0 ? Float((acc += double(f[size_t(i)])) / sum) : Float(double(i + 1) / n);
        cdf[size_t(n)] = 1;
        for (int k = 0; k < 20000; ++k) {
            // Every multiple of 1/n (the guide's cut points) and random u.
            const Float u = k <= n ? Float(double(k) / n) * 0.999999f : rng.next_float();
            int expect = 0;
            for (int i = 0; i < n; ++i)
                if (cdf[size_t(i)] <= u) expect = i;
            ASSERT_EQ(d.sample_discrete(u), expect) << "n " << n << " u " << u;
        }
    }
}

TEST(Distribution1D, InvertRoundTrip) {
    std::vector<Float> w = test_weights();
    Distribution1D d(w, 1, 3);
    Pcg32 rng(4);
    for (int i = 0; i < 10000; ++i) {
        Float u = rng.next_float();
        Float x = d.sample_continuous(u);
        auto v = d.invert(x);
        ASSERT_TRUE(v.has_value());
        EXPECT_NEAR(*v, u, 1e-4);
    }
    EXPECT_FALSE(d.invert(0.5f).has_value());
    EXPECT_FALSE(d.invert(3.5f).has_value());
}

TEST(Distribution1D, AllZeroFallsBackToUniform) {
    std::vector<Float> w(5, 0.0f);
    Distribution1D d(w, 0, 2);
    EXPECT_EQ(d.integral(), 0);
    for (int i = 0; i < 5; ++i) EXPECT_FLOAT_EQ(d.pmf(i), 0.2f);
    EXPECT_FLOAT_EQ(d.pdf(1.3f), 0.5f);
    Pcg32 rng(5);
    const int n = 50000;
    std::vector<double> observed(5, 0.0), expected(5, n / 5.0);
    for (int s = 0; s < n; ++s) {
        Float pdf;
        Float x = d.sample_continuous(rng.next_float(), &pdf);
        EXPECT_FLOAT_EQ(pdf, 0.5f);
        observed[std::size_t(x / 2 * 5)] += 1;
    }
    EXPECT_GT(chi2_test(observed, expected).p_value, kAlpha);
}

TEST(Distribution1D, RejectsInvalidInput) {
    std::vector<Float> empty;
    EXPECT_THROW(Distribution1D{empty}, Error);
    std::vector<Float> nan = {1, std::nanf(""), 2};
    EXPECT_THROW(Distribution1D{nan}, Error);
    std::vector<Float> inf = {1, kInfinity};
    EXPECT_THROW(Distribution1D{inf}, Error);
    std::vector<Float> ok = {1, 2};
    EXPECT_THROW(Distribution1D(ok, 1, 1), Error);
}

TEST(AliasTable, SamplingMatchesPmf) {
    Pcg32 rng(6);
    std::vector<Float> w(100);
    for (std::size_t i = 0; i < w.size(); ++i) {
        // Heavy-tailed weights with some zeros.
        w[i] = i % 7 == 3 ? 0.0f : std::pow(rng.next_float(), 4.0f) * 100;
    }
    AliasTable table(w);
    std::vector<double> p = normalized(w);
    ASSERT_EQ(table.size(), w.size());
    const int n = 1000000;
    std::vector<double> observed(w.size(), 0.0), expected(w.size());
    for (std::size_t i = 0; i < w.size(); ++i) {
        expected[i] = p[i] * n;
        EXPECT_NEAR(table.pmf(int(i)), p[i], 1e-6);
    }
    for (int s = 0; s < n; ++s) {
        Float pmf;
        int i = table.sample(rng.next_float(), &pmf);
        ASSERT_GE(i, 0);
        ASSERT_LT(i, int(w.size()));
        ASSERT_GT(w[std::size_t(i)], 0) << "sampled a zero-weight entry";
        EXPECT_EQ(pmf, table.pmf(i));
        observed[std::size_t(i)] += 1;
    }
    EXPECT_GT(chi2_test(observed, expected).p_value, kAlpha);
}

TEST(AliasTable, RemappedVariateIsUniformGivenTheChoice) {
    std::vector<Float> w = {1, 5, 0.5f, 3};
    AliasTable table(w);
    Pcg32 rng(7);
    const int n = 400000, bins = 10;
    // Conditional on the returned index, u_remapped must still be U(0,1).
    std::vector<std::vector<double>> observed(w.size(), std::vector<double>(bins, 0.0));
    std::vector<int> count(w.size(), 0);
    for (int s = 0; s < n; ++s) {
        Float ur;
        int i = table.sample(rng.next_float(), nullptr, &ur);
        ASSERT_GE(ur, 0);
        ASSERT_LT(ur, 1);
        observed[std::size_t(i)][std::size_t(ur * bins)] += 1;
        ++count[std::size_t(i)];
    }
    for (std::size_t i = 0; i < w.size(); ++i) {
        std::vector<double> expected(bins, count[i] / double(bins));
        EXPECT_GT(chi2_test(observed[i], expected).p_value, kAlpha / 4) << "index " << i;
    }
}

TEST(AliasTable, EdgeCases) {
    std::vector<Float> one = {3};
    AliasTable single(one);
    EXPECT_EQ(single.sample(0.7f), 0);
    EXPECT_EQ(single.pmf(0), 1.0f);

    std::vector<Float> zeros(4, 0.0f);
    AliasTable uniform(zeros);
    for (int i = 0; i < 4; ++i) EXPECT_FLOAT_EQ(uniform.pmf(i), 0.25f);

    std::vector<Float> negative = {1, -1};
    EXPECT_THROW(AliasTable{negative}, Error);
    std::vector<Float> empty;
    EXPECT_THROW(AliasTable{empty}, Error);
}

TEST(Distribution2D, SamplingMatchesFunction) {
    const int nu = 8, nv = 6;
    std::vector<Float> f(nu * nv);
    for (int v = 0; v < nv; ++v) {
        for (int u = 0; u < nu; ++u) {
            // A smooth bump with one all-zero row and one zero cell.
            f[std::size_t(v * nu + u)] =
                v == 2 ? 0.0f
                       : 1 + std::sin(Float(u) * 0.7f) * std::cos(Float(v) * 0.4f) + 0.1f * u;
        }
    }
    f[5 * nu + 3] = 0;
    const Point2 lo{-1, 2}, hi{3, 5};
    Distribution2D d(f, nu, nv, lo, hi);
    std::vector<double> p = normalized(f);
    double cell_area = double(hi.x - lo.x) * (hi.y - lo.y) / (nu * nv);
    double sum = std::accumulate(f.begin(), f.end(), 0.0);
    EXPECT_NEAR(d.integral(), sum * cell_area, 1e-4);

    // pdf integrates to 1 (constant per cell: evaluate at cell centres).
    double total = 0;
    for (int v = 0; v < nv; ++v) {
        for (int u = 0; u < nu; ++u) {
            Point2 c{lo.x + (u + 0.5f) * (hi.x - lo.x) / nu,
                     lo.y + (v + 0.5f) * (hi.y - lo.y) / nv};
            total += d.pdf(c) * cell_area;
            EXPECT_NEAR(d.pdf(c), p[std::size_t(v * nu + u)] / cell_area, 1e-5);
        }
    }
    EXPECT_NEAR(total, 1.0, 1e-5);

    const int n = 400000;
    std::vector<double> observed(f.size(), 0.0), expected(f.size());
    for (std::size_t i = 0; i < f.size(); ++i) expected[i] = p[i] * n;
    Pcg32 rng(8);
    for (int s = 0; s < n; ++s) {
        Float pdf;
        Point2 x = d.sample({rng.next_float(), rng.next_float()}, &pdf);
        ASSERT_GE(x.x, lo.x);
        ASSERT_LT(x.x, hi.x);
        ASSERT_GE(x.y, lo.y);
        ASSERT_LT(x.y, hi.y);
        EXPECT_FLOAT_EQ(pdf, d.pdf(x));
        auto iu = std::size_t((x.x - lo.x) / (hi.x - lo.x) * nu);
        auto iv = std::size_t((x.y - lo.y) / (hi.y - lo.y) * nv);
        ASSERT_GT(f[iv * nu + iu], 0) << "sampled a zero cell";
        observed[iv * nu + iu] += 1;
    }
    EXPECT_GT(chi2_test(observed, expected).p_value, kAlpha);
    EXPECT_EQ(d.pdf({lo.x - 1, lo.y}), 0);
}

TEST(Distribution2D, InvertRoundTripAndZeroFallback) {
    std::vector<Float> f = {1, 2, 3, 4, 0, 6};
    Distribution2D d(f, 3, 2);
    Pcg32 rng(9);
    for (int i = 0; i < 10000; ++i) {
        Point2 u{rng.next_float(), rng.next_float()};
        Point2 x = d.sample(u);
        auto v = d.invert(x);
        ASSERT_TRUE(v.has_value());
        EXPECT_NEAR(v->x, u.x, 1e-4);
        EXPECT_NEAR(v->y, u.y, 1e-4);
    }
    EXPECT_FALSE(d.invert({1.5f, 0.5f}).has_value());

    std::vector<Float> zeros(12, 0.0f);
    Distribution2D z(zeros, 4, 3, {0, 0}, {2, 2});
    EXPECT_EQ(z.integral(), 0);
    Float pdf;
    z.sample({0.3f, 0.8f}, &pdf);
    EXPECT_FLOAT_EQ(pdf, 0.25f);  // uniform over an area of 4
    EXPECT_FLOAT_EQ(z.pdf({1, 1}), 0.25f);
    EXPECT_THROW(Distribution2D(f, 4, 2), Error);
}

}  // namespace
}  // namespace sr
