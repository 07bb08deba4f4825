// Trowbridge-Reitz (GGX) distribution: normalisation of D over projected area, normalisation
// of the visible-normal distribution (equivalently, Smith's G1 is the one that makes the
// projected areas agree, Heitz 2014 Eq. 43), G1 closed forms, and a chi-square test of
// visible-normal sampling (Heitz 2018) against D(w, wm).
#include "steradian/bsdf/microfacet.h"

#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>

#include "stat/chi2.h"
#include "stat/lobe_util.h"
#include "steradian/sampling/stats.h"

namespace sr {
namespace {

using testing::direction_deg;

constexpr double kPiD = 3.141592653589793;

const TrowbridgeReitz kDistributions[] = {
    {0.05f, 0.05f}, {0.2f, 0.2f}, {0.5f, 0.5f}, {1.0f, 1.0f}, {0.05f, 0.4f}, {0.6f, 0.15f},
};

/// Integral over the upper hemisphere of g(wm) dwm by adaptive cubature over 6 x 12 cells.
template <typename G>
double hemisphere_integral(G&& g) {
    double sum = 0;
    const int nt = 6, np = 12;
    for (int i = 0; i < nt; ++i)
        for (int j = 0; j < np; ++j)
            sum += testing::sphere_cell_integral(g, i * kPiD / 2 / nt, (i + 1) * kPiD / 2 / nt,
                                                 -kPiD + j * 2 * kPiD / np,
                                                 -kPiD + (j + 1) * 2 * kPiD / np, 1e-8);
    return sum;
}

TEST(Microfacet, DIntegratesToOneOverProjectedArea) {
    for (const TrowbridgeReitz& mf : kDistributions) {
        double integral = hemisphere_integral([&](Vec3 wm) { return mf.D(wm) * wm.z; });
        EXPECT_NEAR(integral, 1.0, 1e-5) << "alpha " << mf.alpha_x << ", " << mf.alpha_y;
    }
}

TEST(Microfacet, VisibleNormalPdfIntegratesToOne) {
    // Equivalent to Heitz 2014, Eq. 43: cos(theta_o) = integral of G1(wo) <wo, wm> D(wm) dwm,
    // i.e. the Smith G1 makes the visible projected microfacet area equal the macro one.
    const double thetas[] = {0, 30, 60, 80, 89, 120, 175};
    for (const TrowbridgeReitz& mf : kDistributions) {
        for (double t : thetas) {
            Vec3 w = direction_deg(t, 0.7);
            double integral = hemisphere_integral([&](Vec3 wm) { return mf.pdf(w, wm); });
            EXPECT_NEAR(integral, 1.0, 1e-5)
                << "alpha " << mf.alpha_x << ", " << mf.alpha_y << ", theta " << t;
        }
    }
}

TEST(Microfacet, SmithG1ClosedForms) {
    for (const TrowbridgeReitz& mf : kDistributions) {
        // Normal incidence: no microfacet is masked.
        EXPECT_EQ(mf.lambda(Vec3(0, 0, 1)), 0);
        EXPECT_EQ(mf.G1(Vec3(0, 0, 1)), 1);
        EXPECT_EQ(mf.G1(Vec3(0, 0, -1)), 1);
        // Grazing: everything is masked.
        EXPECT_EQ(mf.G1(Vec3(1, 0, 0)), 0);
        // G <= min(G1(wo), G1(wi)) (height correlation only helps).
        Vec3 wo = direction_deg(50, 0.2), wi = direction_deg(70, 2.0);
        EXPECT_LE(mf.G(wo, wi), std::min(mf.G1(wo), mf.G1(wi)));
        EXPECT_GE(mf.G(wo, wi), mf.G1(wo) * mf.G1(wi) - 1e-6f);
    }
    // Isotropic: G1 = 2 / (1 + sqrt(1 + alpha^2 tan^2 theta)) (Walter et al. 2007, Eq. 34).
    for (double alpha : {0.1, 0.5, 1.0}) {
        TrowbridgeReitz mf{Float(alpha), Float(alpha)};
        for (double t : {10.0, 45.0, 75.0, 88.0}) {
            double tan_t = std::tan(t * kPiD / 180);
            double expected = 2 / (1 + std::sqrt(1 + alpha * alpha * tan_t * tan_t));
            EXPECT_NEAR(mf.G1(direction_deg(t, 1.1)), expected, 1e-5) << alpha << " " << t;
        }
    }
    // Anisotropic: along x only alpha_x matters, along y only alpha_y.
    TrowbridgeReitz aniso{0.1f, 0.8f};
    TrowbridgeReitz along_x{0.1f, 0.1f}, along_y{0.8f, 0.8f};
    Vec3 wx = direction_deg(60, 0), wy = direction_deg(60, kPiD / 2);
    EXPECT_NEAR(aniso.G1(wx), along_x.G1(wx), 1e-6);
    EXPECT_NEAR(aniso.G1(wy), along_y.G1(wy), 1e-5);
}

TEST(Microfacet, RoughnessMapping) {
    EXPECT_FLOAT_EQ(TrowbridgeReitz::roughness_to_alpha(0.25f), 0.5f);
    EXPECT_FLOAT_EQ(TrowbridgeReitz::roughness_to_alpha(1), 1);
    EXPECT_TRUE((TrowbridgeReitz{0, 0}.effectively_smooth()));
    EXPECT_TRUE((TrowbridgeReitz{9e-4f, 5e-4f}.effectively_smooth()));
    EXPECT_FALSE((TrowbridgeReitz{1e-3f, 1e-4f}.effectively_smooth()));
    // Isotropic D at the pole: 1 / (pi alpha^2).
    EXPECT_FLOAT_EQ((TrowbridgeReitz{0.3f, 0.3f}.D(Vec3(0, 0, 1))), 1 / (kPi * 0.09f));
    EXPECT_EQ((TrowbridgeReitz{0.3f, 0.3f}.D(Vec3(0, 0, -1))), 0);
}

// ---- chi-square of sample_wm ----------------------------------------------------------------

struct VndfCase {
    TrowbridgeReitz mf;
    double theta_deg;
};
const VndfCase kVndfCases[] = {
    {{0.05f, 0.05f}, 0}, {{0.05f, 0.05f}, 60}, {{0.2f, 0.2f}, 30},  {{0.5f, 0.5f}, 85},
    {{1.0f, 1.0f}, 45},  {{1.0f, 1.0f}, 150},  {{0.05f, 0.4f}, 70}, {{0.6f, 0.15f}, 89},
};
constexpr int kNumChi2Tests = int(std::size(kVndfCases));

TEST(Microfacet, VisibleNormalSamplingChi2) {
    const double alpha = sidak_alpha(0.01, kNumChi2Tests);
    for (const VndfCase& c : kVndfCases) {
        Vec3 w = direction_deg(c.theta_deg, 0.4);
        testing::SphereChi2Outcome r = testing::sphere_chi2(
            [&](Pcg32& rng) -> std::optional<Vec3> {
                Point2 u{rng.next_float(), rng.next_float()};
                return c.mf.sample_wm(w, u);
            },
            [&](Vec3 wm) { return c.mf.pdf(w, wm); });
        std::printf("[chi2] vndf alpha (%g, %g) theta_o %g: %s\n", c.mf.alpha_x, c.mf.alpha_y,
                    c.theta_deg, r.summary().c_str());
        EXPECT_GT(r.chi2.p_value, alpha) << r.tables();
    }
}

}  // namespace
}  // namespace sr
