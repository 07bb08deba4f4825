// ThinDielectricLobe: the slab's total reflectance against the closed form of the incoherent
// multiple-reflection series (at normal incidence R' = 2R / (1 + R)), lossless sampling
// (albedo exactly 1), mirror and straight-through directions, the reflection probability,
// symmetry of the two sides, and the index-matched case.
#include "steradian/bsdf/thin_dielectric.h"

#include <gtest/gtest.h>

#include <cmath>

#include "stat/lobe_util.h"
#include "steradian/bsdf/fresnel.h"

namespace sr {
namespace {

using testing::direction_deg;

constexpr TransportMode kModes[] = {TransportMode::Radiance, TransportMode::Importance};

TEST(ThinDielectric, NormalIncidenceClosedForm) {
    for (double eta : {1.33, 1.5, 2.4}) {
        double r = std::pow((eta - 1) / (eta + 1), 2);
        ThinDielectricLobe lobe{Float(eta)};
        // Sum over paths with 2k + 1 internal passes: R + T^2 R (1 + R^2 + R^4 + ...).
        EXPECT_NEAR(lobe.split(1).r, 2 * r / (1 + r), 1e-6) << eta;
        EXPECT_NEAR(lobe.split(1).r + lobe.split(1).t, 1, 1e-7);
    }
    // Glass: 4 % per surface, 7.7 % for the pane.
    EXPECT_NEAR(ThinDielectricLobe{1.5f}.split(1).r, 0.08 / 1.04, 1e-6);
}

TEST(ThinDielectric, SeriesAtOblique) {
    // The closed form against an explicit sum of the series with the single-interface
    // reflectance at every angle.
    ThinDielectricLobe lobe{1.5f};
    for (double t : {10.0, 40.0, 70.0, 85.0}) {
        double r = fr_dielectric(Float(std::cos(t * 3.141592653589793 / 180)), 1.5f);
        double tr = 1 - r, sum = r, path = tr * tr * r;
        for (int k = 0; k < 200; ++k, path *= r * r) sum += path;
        EXPECT_NEAR(lobe.split(Float(std::cos(t * 3.141592653589793 / 180))).r, sum, 2e-6) << t;
    }
    EXPECT_EQ(lobe.split(0).r, 1);  // grazing: everything is reflected
}

TEST(ThinDielectric, LosslessAndDirections) {
    for (Float eta : {1.5f, 1.33f}) {
        ThinDielectricLobe lobe{eta};
        EXPECT_EQ(lobe.flags(), kLobeReflection | kLobeTransmission | kLobeSpecular);
        for (double t : {0.0, 30.0, 60.0, 89.0, 120.0, 170.0}) {
            Vec3 wo = direction_deg(t, 0.8);
            for (TransportMode mode : kModes) {
                testing::Albedo a = testing::directional_albedo(lobe, wo, mode, 20000);
                EXPECT_NEAR(a.mean[0], 1, 1e-5) << eta << " " << t;
            }
            Float r = lobe.split(wo.z).r;
            Pcg32 rng(uint64_t(t) + 3);
            int reflected = 0;
            const int n = 20000;
            for (int k = 0; k < n; ++k) {
                std::optional<BsdfSample> s =
                    lobe.sample(wo, rng.next_float(), {0.5f, 0.5f}, TransportMode::Radiance);
                ASSERT_TRUE(s);
                EXPECT_TRUE(s->is_specular());
                EXPECT_EQ(s->eta, 1);
                if (s->is_reflection()) {
                    ++reflected;
                    EXPECT_EQ(s->wi, Vec3(-wo.x, -wo.y, wo.z));
                    EXPECT_FLOAT_EQ(s->pdf_sa, r);
                } else {
                    EXPECT_EQ(s->wi, -wo);  // straight through: the refractions cancel
                    EXPECT_FLOAT_EQ(s->pdf_sa, 1 - r);
                }
                EXPECT_TRUE(lobe.f(wo, s->wi, TransportMode::Radiance).is_zero());
                EXPECT_EQ(lobe.pdf(wo, s->wi, TransportMode::Radiance), 0);
            }
            double se = std::sqrt(std::max(double(r) * (1 - r), 1e-12) / n);
            EXPECT_NEAR(double(reflected) / n, r, 5 * se + 1e-9) << eta << " " << t;
            // The slab looks the same from both sides.
            EXPECT_EQ(lobe.split(wo.z).r, lobe.split(-wo.z).r);
        }
    }
}

TEST(ThinDielectric, IndexMatchedIsInvisible) {
    ThinDielectricLobe lobe{1};
    EXPECT_EQ(lobe.flags(), kLobeTransmission | kLobeSpecular);
    Vec3 wo = direction_deg(35);
    std::optional<BsdfSample> s = lobe.sample(wo, 0, {0.5f, 0.5f}, TransportMode::Radiance);
    ASSERT_TRUE(s);
    EXPECT_TRUE(s->is_transmission());
    EXPECT_EQ(s->wi, -wo);
    EXPECT_NEAR(s->f[0] * std::abs(s->wi.z) / s->pdf_sa, 1, 1e-6);
}

}  // namespace
}  // namespace sr
