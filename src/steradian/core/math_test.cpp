// The polynomial sin, cos and atan2 of math.h against the double-precision libm functions
// (the oracle), on dense grids that include the ends of each range and every quadrant.
#include <gtest/gtest.h>

#include <cmath>

#include "steradian/core/math.h"

namespace sr {
namespace {

TEST(FastTrig, SincosPi4WithinOneTenMillionth) {
    double worst_s = 0, worst_c = 0;
    const int n = 200000;
    for (int i = 0; i <= n; ++i) {
        Float x = Float(-kPiOver4 + 2 * double(kPiOver4) * i / n);
        Float s, c;
        sincos_pi4(x, s, c);
        worst_s = std::max(worst_s, std::abs(double(s) - std::sin(double(x))));
        worst_c = std::max(worst_c, std::abs(double(c) - std::cos(double(x))));
    }
    EXPECT_LT(worst_s, 1e-7);
    EXPECT_LT(worst_c, 1e-7);
}

TEST(FastTrig, SincosOverSeveralTurnsWithinTwoTenMillionths) {
    double worst = 0;
    const int n = 400000;
    for (int i = 0; i <= n; ++i) {
        Float x = Float(-64 + 128.0 * i / n);
        Float s, c;
        fast_sincos(x, s, c);
        worst = std::max({worst, std::abs(double(s) - std::sin(double(x))),
                          std::abs(double(c) - std::cos(double(x)))});
    }
    EXPECT_LT(worst, 2e-7);
    // Exact quadrant points.
    Float s, c;
    fast_sincos(0, s, c);
    EXPECT_EQ(s, 0);
    EXPECT_EQ(c, 1);
    fast_sincos(kPi, s, c);
    EXPECT_NEAR(s, 0, 1e-7);
    EXPECT_NEAR(c, -1, 1e-7);
}

TEST(FastTrig, Atan2RelativeErrorBelowThreeTenMillionthsInEveryOctant) {
    double worst = 0;
    const int n = 720000;
    for (int i = 0; i < n; ++i) {
        double phi = -std::numbers::pi + 2 * std::numbers::pi * (i + 0.5) / n;
        for (double r : {1e-6, 1.0, 3e4}) {
            Float y = Float(r * std::sin(phi)), x = Float(r * std::cos(phi));
            double ref = std::atan2(double(y), double(x));
            if (ref == 0) continue;
            worst = std::max(worst, std::abs(double(fast_atan2(y, x)) - ref) / std::abs(ref));
        }
    }
    EXPECT_LT(worst, 3e-7);
    // Axes and signed zeros as std::atan2.
    EXPECT_EQ(fast_atan2(0, 1), 0);
    EXPECT_NEAR(fast_atan2(1, 0), kPiOver2, 1e-7);
    EXPECT_NEAR(fast_atan2(-1, 0), -kPiOver2, 1e-7);
    EXPECT_NEAR(fast_atan2(0, -1), kPi, 1e-7);
    EXPECT_NEAR(fast_atan2(-0.0f, -1), -kPi, 1e-7);
    EXPECT_EQ(fast_atan2(0, 0), 0);
}

}  // namespace
}  // namespace sr
