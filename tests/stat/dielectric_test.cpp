// DielectricLobe: chi-square of rough sampling against pdf() (eta 1.5 and 1/1.5, isotropic and
// anisotropic roughness, incident directions from above and below, normal to grazing),
// consistency of sample() with f() and pdf() in both transport modes, reciprocity of the
// reflection part and the eta^2 relation of the refraction part (Veach 1997, Ch. 5), energy
// (smooth: albedo exactly 1; rough single scattering: <= 1), and the smooth interface's
// Fresnel split, Snell directions, total internal reflection and eta = 1 pass-through.
#include "steradian/bsdf/dielectric.h"

#include <gtest/gtest.h>

#include <cstdio>

#include "stat/chi2.h"
#include "stat/lobe_util.h"
#include "steradian/bsdf/fresnel.h"
#include "steradian/sampling/stats.h"
#include "steradian/sampling/warp.h"

namespace sr {
namespace {

using testing::direction_deg;

const TrowbridgeReitz kRough[] = {{0.05f, 0.05f}, {0.2f, 0.2f}, {1.0f, 1.0f}, {0.05f, 0.4f}};
const Float kEtas[] = {1.5f, 1 / 1.5f};
const double kThetas[] = {0, 45, 87, 140};  // 140: wo below the surface (inside for eta 1.5)

constexpr int kNumChi2Tests = int(std::size(kRough) * std::size(kEtas) * std::size(kThetas));

constexpr TransportMode kModes[] = {TransportMode::Radiance, TransportMode::Importance};

TEST(Dielectric, RoughSamplingMatchesPdfChi2) {
    const double alpha = sidak_alpha(0.01, kNumChi2Tests);
    double p_min = 1, p_max = 0;
    uint64_t seed = 100;
    for (const TrowbridgeReitz& mf : kRough) {
        for (Float eta : kEtas) {
            DielectricLobe lobe{eta, mf};
            for (double t : kThetas) {
                Vec3 wo = direction_deg(t);
                testing::SphereChi2Config cfg;
                cfg.seed = ++seed;
                testing::SphereChi2Outcome r =
                    testing::lobe_chi2(lobe, wo, TransportMode::Radiance, cfg);
                std::printf("[chi2] dielectric eta %.4g alpha (%g, %g) theta_o %g: %s\n", eta,
                            mf.alpha_x, mf.alpha_y, t, r.summary().c_str());
                p_min = std::min(p_min, r.chi2.p_value);
                p_max = std::max(p_max, r.chi2.p_value);
                EXPECT_GT(r.chi2.p_value, alpha) << "eta " << eta << ", alpha (" << mf.alpha_x
                                                 << ", " << mf.alpha_y << "), theta_o " << t << "\n"
                                                 << r.tables();
            }
        }
    }
    std::printf("[chi2] dielectric: %d tests, p in [%.3g, %.3g], per-test alpha %.3g\n",
                kNumChi2Tests, p_min, p_max, alpha);
}

TEST(Dielectric, RoughSampleAgreesWithFAndPdf) {
    for (const TrowbridgeReitz& mf : kRough) {
        for (Float eta : kEtas) {
            DielectricLobe lobe{eta, mf};
            for (double t : kThetas) {
                for (TransportMode mode : kModes) {
                    testing::ConsistencyResult c =
                        testing::check_sample_consistency(lobe, direction_deg(t), mode, 20000);
                    EXPECT_GT(c.samples, 5000);
                    EXPECT_LT(c.max_rel_f, 1e-3) << eta << " " << mf.alpha_x << " " << mf.alpha_y
                                                 << " " << t << ": " << c.worst;
                    EXPECT_LT(c.max_rel_pdf, 1e-3) << eta << " " << mf.alpha_x << " " << mf.alpha_y
                                                   << " " << t << ": " << c.worst;
                }
            }
        }
    }
}

TEST(Dielectric, Reciprocity) {
    Pcg32 rng(21);
    int reflections = 0, refractions = 0;
    for (const TrowbridgeReitz& mf : kRough) {
        for (Float eta : kEtas) {
            DielectricLobe lobe{eta, mf};
            // Index of refraction on w's side: 1 above, eta below.
            auto n = [&](Vec3 w) { return w.z > 0 ? Float(1) : eta; };
            for (int k = 0; k < 4000; ++k) {
                Vec3 wo = sample_uniform_sphere({rng.next_float(), rng.next_float()});
                Vec3 wi = sample_uniform_sphere({rng.next_float(), rng.next_float()});
                Float f_oi = lobe.f(wo, wi, TransportMode::Radiance)[0];
                Float f_io = lobe.f(wi, wo, TransportMode::Radiance)[0];
                // Relative 1e-4, with a floor of 1e-7 / sr for the tails where a microfacet is
                // grazed (cosines ~ 1e-4 carry float errors of ~ 1e-3 relative).
                if (same_hemisphere(wo, wi)) {
                    // Helmholtz reciprocity of the BRDF part.
                    EXPECT_TRUE(testing::near_rel(f_oi, f_io, 1e-4, 1e-7)) << f_oi << " " << f_io;
                    reflections += f_oi > 0;
                    continue;
                }
                // BTDF: f(wo, wi) / n_o^2 = f(wi, wo) / n_i^2 (radiance form), and the
                // Importance-mode BSDF is the adjoint f*(wo, wi) = f(wi, wo).
                EXPECT_TRUE(testing::near_rel(f_oi / sqr(n(wo)), f_io / sqr(n(wi)), 1e-4, 1e-7))
                    << f_oi << " " << f_io;
                Float f_imp = lobe.f(wo, wi, TransportMode::Importance)[0];
                EXPECT_TRUE(testing::near_rel(f_imp, f_io, 1e-4, 1e-7)) << f_imp << " " << f_io;
                refractions += f_oi > 0;
            }
        }
    }
    // The checks above were not vacuous.
    EXPECT_GT(reflections, 10000);
    EXPECT_GT(refractions, 2000);
}

TEST(Dielectric, SmoothIsLossless) {
    for (Float eta : {1.5f, 1 / 1.5f, 1.33f}) {
        DielectricLobe lobe{eta, {}};
        for (double t : {0.0, 30.0, 60.0, 85.0, 100.0, 135.0, 170.0}) {
            for (TransportMode mode : kModes) {
                testing::Albedo a =
                    testing::directional_albedo(lobe, direction_deg(t), mode, 20000);
                for (int i = 0; i < kSpectrumSamples; ++i)
                    EXPECT_NEAR(a.mean[i], 1, 1e-5) << eta << " " << t;
            }
        }
    }
}

TEST(Dielectric, RoughAlbedoAtMostOne) {
    for (const TrowbridgeReitz& mf : kRough) {
        for (Float eta : kEtas) {
            DielectricLobe lobe{eta, mf};
            for (double t : {0.0, 45.0, 87.0, 140.0, 175.0}) {
                for (TransportMode mode : kModes) {
                    testing::Albedo a =
                        testing::directional_albedo(lobe, direction_deg(t), mode, 50000);
                    EXPECT_LE(a.mean[0], 1 + 4 * a.std_error[0] + 1e-6)
                        << eta << " " << mf.alpha_x << " " << mf.alpha_y << " " << t;
                    EXPECT_GT(a.mean[0], 0.3);
                }
            }
        }
    }
    // Nearly smooth at normal incidence: hardly any masking, almost lossless.
    for (Float eta : kEtas) {
        DielectricLobe lobe{eta, {0.05f, 0.05f}};
        testing::Albedo a =
            testing::directional_albedo(lobe, Vec3(0, 0, 1), TransportMode::Importance, 50000);
        EXPECT_GT(a.mean[0], 0.99) << eta;
    }
}

TEST(Dielectric, SmoothFresnelSplitAndDirections) {
    for (Float eta : {1.5f, 1 / 1.5f}) {
        DielectricLobe lobe{eta, {}};
        EXPECT_EQ(lobe.flags(), kLobeReflection | kLobeTransmission | kLobeSpecular);
        for (double t : {0.0, 25.0, 50.0, 80.0, 110.0, 150.0}) {
            Vec3 wo = direction_deg(t, 1.3);
            Float r = fr_dielectric(wo.z, eta);
            int reflected = 0;
            const int n = 20000;
            Pcg32 rng(uint64_t(t) + 7);
            for (int k = 0; k < n; ++k) {
                for (TransportMode mode : kModes) {
                    Float uc = rng.next_float();
                    std::optional<BsdfSample> s = lobe.sample(wo, uc, {0.5f, 0.5f}, mode);
                    ASSERT_TRUE(s);
                    ASSERT_TRUE(s->is_specular());
                    EXPECT_TRUE(lobe.f(wo, s->wi, mode).is_zero());
                    EXPECT_EQ(lobe.pdf(wo, s->wi, mode), 0);
                    Float weight = s->f[0] * std::abs(s->wi.z) / s->pdf_sa;
                    if (s->is_reflection()) {
                        reflected += mode == TransportMode::Radiance;
                        EXPECT_FLOAT_EQ(s->pdf_sa, r);
                        EXPECT_NEAR(s->wi.x, -wo.x, 1e-7);
                        EXPECT_NEAR(s->wi.y, -wo.y, 1e-7);
                        EXPECT_EQ(s->wi.z, wo.z);
                        EXPECT_NEAR(weight, 1, 1e-6);
                        EXPECT_EQ(s->eta, 1);
                        continue;
                    }
                    ASSERT_TRUE(s->is_transmission());
                    EXPECT_FLOAT_EQ(s->pdf_sa, 1 - r);
                    EXPECT_LT(s->wi.z * wo.z, 0);
                    // Snell: n_o sin_o = n_i sin_i, with etap = n_i / n_o.
                    Float etap = wo.z > 0 ? eta : 1 / eta;
                    EXPECT_FLOAT_EQ(s->eta, etap);
                    EXPECT_NEAR(sin_theta(wo), etap * sin_theta(s->wi), 1e-5);
                    // Radiance is scaled by (n_o / n_i)^2; importance is not.
                    Float expected = mode == TransportMode::Radiance ? 1 / sqr(etap) : 1;
                    EXPECT_NEAR(weight, expected, 1e-5);
                }
            }
            // The reflection probability is R (binomial z-test).
            double frac = double(reflected) / n;
            double se = std::sqrt(std::max(double(r) * (1 - r), 1e-12) / n);
            EXPECT_NEAR(frac, r, 5 * se + 1e-9) << eta << " " << t;
        }
    }
}

TEST(Dielectric, TotalInternalReflection) {
    // Inside glass (below the surface for eta = 1.5) beyond the critical angle of 41.8 deg:
    // every sample reflects with weight 1, rough or smooth (rough: per microfacet).
    DielectricLobe smooth{1.5f, {}};
    Vec3 wo = direction_deg(180 - 50);
    for (Float uc : {0.0f, 0.5f, 0.999f}) {
        std::optional<BsdfSample> s = smooth.sample(wo, uc, {0.3f, 0.3f}, TransportMode::Radiance);
        ASSERT_TRUE(s);
        EXPECT_TRUE(s->is_reflection());
        EXPECT_EQ(s->pdf_sa, 1);
        EXPECT_NEAR(s->f[0] * std::abs(s->wi.z), 1, 1e-6);
    }
    // The same from above with eta = 1/1.5 (an interface whose far side is the rarer medium).
    DielectricLobe flipped{1 / 1.5f, {}};
    std::optional<BsdfSample> s =
        flipped.sample(direction_deg(50), 0.99f, {0.3f, 0.3f}, TransportMode::Radiance);
    ASSERT_TRUE(s);
    EXPECT_TRUE(s->is_reflection());
}

TEST(Dielectric, IndexMatchedPassesThrough) {
    for (TrowbridgeReitz mf : {TrowbridgeReitz{}, TrowbridgeReitz{0.5f, 0.5f}}) {
        DielectricLobe lobe{1, mf};
        EXPECT_EQ(lobe.flags(), kLobeTransmission | kLobeSpecular);
        for (double t : {0.0, 40.0, 89.0, 120.0}) {
            Vec3 wo = direction_deg(t, 2.0);
            for (TransportMode mode : kModes) {
                std::optional<BsdfSample> s = lobe.sample(wo, 0.01f, {0.2f, 0.9f}, mode);
                ASSERT_TRUE(s);
                EXPECT_TRUE(s->is_specular() && s->is_transmission());
                EXPECT_EQ(s->wi, -wo);
                EXPECT_EQ(s->eta, 1);
                EXPECT_NEAR(s->f[0] * std::abs(s->wi.z) / s->pdf_sa, 1, 1e-6);
                EXPECT_TRUE(lobe.f(wo, -wo, mode).is_zero());
                EXPECT_EQ(lobe.pdf(wo, -wo, mode), 0);
            }
        }
    }
}

TEST(Dielectric, RoughFlagsAndGrazing) {
    DielectricLobe lobe{1.5f, {0.3f, 0.3f}};
    EXPECT_EQ(lobe.flags(), kLobeReflection | kLobeTransmission | kLobeGlossy);
    EXPECT_FALSE(lobe.sample(Vec3(1, 0, 0), 0.5f, {0.5f, 0.5f}, TransportMode::Radiance));
    EXPECT_TRUE(lobe.f(Vec3(1, 0, 0), Vec3(0, 0, 1), TransportMode::Radiance).is_zero());
    EXPECT_EQ(lobe.pdf(Vec3(0, 0, 1), Vec3(1, 0, 0), TransportMode::Radiance), 0);
}

}  // namespace
}  // namespace sr
