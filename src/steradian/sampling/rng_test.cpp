#include "steradian/sampling/rng.h"

#include <gtest/gtest.h>

#include <bit>
#include <cmath>
#include <vector>

#include "steradian/sampling/stats.h"

namespace sr {
namespace {

// Significance level per statistical test in this file (tests are deterministic: fixed seeds).
constexpr double kAlpha = 1e-3;

TEST(Pcg32, MatchesReferenceImplementation) {
    // pcg32-demo of the reference C implementation (pcg-random.org, pcg-c-basic):
    // pcg32_srandom_r(&rng, 42u, 54u) then six pcg32_random_r calls ("Round 1").
    Pcg32 rng(/*seq_index=*/54, /*seed=*/42);
    const uint32_t expected[] = {0xa15c02b7u, 0x7b47f409u, 0xba1d3330u,
                                 0x83d2f293u, 0xbfa4784bu, 0xcbed606eu};
    for (uint32_t e : expected) EXPECT_EQ(rng.next_u32(), e);
}

TEST(Pcg32, DeterministicForFixedSeed) {
    Pcg32 a(7, 11), b(7, 11);
    for (int i = 0; i < 1000; ++i) ASSERT_EQ(a.next_u32(), b.next_u32());
    Pcg32 c(7), d(7);
    for (int i = 0; i < 100; ++i) ASSERT_EQ(c.next_float(), d.next_float());
}

TEST(Pcg32, StreamsDiffer) {
    Pcg32 a(1, 99), b(2, 99);
    int equal = 0;
    for (int i = 0; i < 1000; ++i) equal += a.next_u32() == b.next_u32();
    EXPECT_LT(equal, 3);
}

TEST(Pcg32, AdvanceEqualsRepeatedSteps) {
    for (int64_t n :
         {int64_t(0), int64_t(1), int64_t(2), int64_t(17), int64_t(1000), int64_t(65537)}) {
        Pcg32 stepped(3, 5), jumped(3, 5);
        for (int64_t i = 0; i < n; ++i) stepped.next_u32();
        jumped.advance(n);
        EXPECT_EQ(stepped, jumped) << "n = " << n;
        EXPECT_EQ(stepped.next_u32(), jumped.next_u32());
    }
}

TEST(Pcg32, AdvanceBackwardsReturns) {
    Pcg32 rng(12, 34);
    Pcg32 start = rng;
    std::vector<uint32_t> first;
    for (int i = 0; i < 100; ++i) first.push_back(rng.next_u32());
    rng.advance(-100);
    EXPECT_EQ(rng, start);
    for (int i = 0; i < 100; ++i) ASSERT_EQ(rng.next_u32(), first[std::size_t(i)]);

    // Large jumps compose: +k then -k is the identity, +a +b equals +(a+b).
    Pcg32 a = start, b = start;
    a.advance(int64_t(1) << 40);
    a.advance(-(int64_t(1) << 40));
    EXPECT_EQ(a, start);
    a.advance(123456789);
    a.advance(987654321);
    b.advance(123456789 + 987654321);
    EXPECT_EQ(a, b);
}

TEST(Pcg32, DistanceInvertsAdvance) {
    Pcg32 a(9, 9);
    for (int64_t d : {int64_t(0), int64_t(1), int64_t(255), int64_t(-1), int64_t(-4096),
                      int64_t(1) << 50, -(int64_t(1) << 33) + 7}) {
        Pcg32 b = a;
        b.advance(d);
        EXPECT_EQ(b - a, d);
        EXPECT_EQ(a - b, -d);
    }
    Pcg32 c = a;
    for (int i = 0; i < 37; ++i) c.next_u32();
    EXPECT_EQ(c - a, 37);
}

TEST(Pcg32, BoundedIntegersAreUniform) {
    // Chi-square over the `bound` values; expected count N / bound each.
    Pcg32 rng(2024, 1);
    for (uint32_t bound : {2u, 3u, 7u, 10u, 100u, 1000u}) {
        const int n = 200000;
        std::vector<double> observed(bound, 0.0), expected(bound, double(n) / bound);
        for (int i = 0; i < n; ++i) {
            uint32_t v = rng.next_u32(bound);
            ASSERT_LT(v, bound);
            observed[v] += 1;
        }
        Chi2Result r = chi2_test(observed, expected);
        EXPECT_GT(r.p_value, kAlpha) << "bound " << bound << " chi2 " << r.statistic;
    }
}

TEST(Pcg32, BoundedIntegersUnbiasedForHugeBound) {
    // bound = 3 * 2^30: plain `next_u32() % bound` would put [0, 2^30) at twice the probability
    // of [2^30, 2^31) and [2^31, 3 * 2^30). The three thirds must be equally likely.
    Pcg32 rng(77, 3);
    const uint32_t bound = 3u << 30;
    const int n = 300000;
    std::vector<double> observed(3, 0.0), expected(3, n / 3.0);
    for (int i = 0; i < n; ++i) {
        uint32_t v = rng.next_u32(bound);
        ASSERT_LT(v, bound);
        observed[v >> 30] += 1;
    }
    EXPECT_GT(chi2_test(observed, expected).p_value, kAlpha);
}

TEST(Pcg32, FloatsAreUniformInHalfOpenUnitInterval) {
    Pcg32 rng(5, 6);
    const int n = 400000, bins = 100;
    std::vector<double> observed(bins, 0.0), expected(bins, double(n) / bins);
    double sum = 0;
    for (int i = 0; i < n; ++i) {
        Float u = rng.next_float();
        ASSERT_GE(u, 0);
        ASSERT_LT(u, 1);
        sum += u;
        observed[std::size_t(u * bins)] += 1;
    }
    EXPECT_GT(chi2_test(observed, expected).p_value, kAlpha);
    // Mean 1/2 and variance 1/12 for U(0,1).
    EXPECT_GT(z_test_p(sum / n, 0.5, std::sqrt(1.0 / 12 / n)), kAlpha);

    double dsum = 0;
    for (int i = 0; i < n; ++i) {
        double u = rng.next_double();
        ASSERT_GE(u, 0);
        ASSERT_LT(u, 1);
        dsum += u;
    }
    EXPECT_GT(z_test_p(dsum / n, 0.5, std::sqrt(1.0 / 12 / n)), kAlpha);
}

TEST(UnitFloat, NeverOneAndPreservesDyadicIntervals) {
    EXPECT_EQ(u32_to_unit_float(0), 0.0f);
    EXPECT_EQ(u32_to_unit_float(0xffffffffu), kOneMinusEpsilon);
    EXPECT_LT(u32_to_unit_float(0xffffffffu), 1.0f);
    // Exact for values with at most 24 significant bits.
    EXPECT_EQ(u32_to_unit_float(1u), 0x1p-32f);
    EXPECT_EQ(u32_to_unit_float(0x80000000u), 0.5f);
    // v = k 2^(32-j) - 1 is the last integer of dyadic interval k-1 at level j: its float must
    // stay strictly below k 2^-j (rounding to nearest would give k 2^-j).
    for (int j = 1; j <= 24; ++j) {
        for (uint32_t k : {1u, 2u, 3u, 5u}) {
            uint64_t v = (uint64_t(k) << (32 - j)) - 1;
            if (v > 0xffffffffu) continue;
            Float f = u32_to_unit_float(uint32_t(v));
            EXPECT_LT(double(f), double(k) * std::ldexp(1.0, -j)) << "j " << j << " k " << k;
            EXPECT_GE(double(f), double(k - 1) * std::ldexp(1.0, -j));
        }
    }
    // Monotone.
    Pcg32 rng(1, 2);
    for (int i = 0; i < 10000; ++i) {
        uint32_t a = rng.next_u32(), b = rng.next_u32();
        if (a > b) std::swap(a, b);
        ASSERT_LE(u32_to_unit_float(a), u32_to_unit_float(b));
    }
}

TEST(UnitFloat, TruncatesToTwentyFourSignificantBits) {
    // The definition: mask v below its 24 most significant set bits, then convert (exactly).
    auto reference = [](uint32_t v) {
        int width = 32 - std::countl_zero(v);
        int drop = width > 24 ? width - 24 : 0;
        return float(v & ~((uint32_t(1) << drop) - 1)) * 0x1p-32f;
    };
    std::vector<uint32_t> values = {0u,          1u,          2u,          0xffffffu,   0x1000000u,
                                    0x1000001u,  0x1ffffffu,  0x7fffffffu, 0x80000000u, 0x80000001u,
                                    0xfffffeffu, 0xffffff00u, 0xffffffffu};
    for (int k = 0; k < 32; ++k) {
        values.push_back(uint32_t(1) << k);
        values.push_back((uint32_t(1) << k) - 1);
        values.push_back(~uint32_t(0) >> k);
    }
    Pcg32 rng(3, 5);
    for (int i = 0; i < 200000; ++i) values.push_back(rng.next_u32() >> (i % 32));
    for (uint32_t v : values) ASSERT_EQ(u32_to_unit_float(v), reference(v)) << std::hex << v;
}

}  // namespace
}  // namespace sr
