// HairLobe (material "hair", Chiang et al. 2016 with d'Eon et al. 2011's longitudinal lobes):
// white furnace (with sigma_a = 0 the integral of f |cos| over the sphere is 1, estimated
// both by uniform sphere sampling and by the lobe's own sampling), the sampling pdf
// integrates to 1, chi-square of sample() against pdf(), consistency of sample() with f()
// and pdf(), absorption only removes energy, the symmetry of the scattering function where
// the model is reciprocal, and sigma_a from a reflectance against the published relation.
#include "steradian/bsdf/hair.h"

#include <gtest/gtest.h>

#include <cstdio>
#include <limits>

#include "stat/chi2.h"
#include "stat/lobe_util.h"
#include "steradian/sampling/stats.h"
#include "steradian/sampling/warp.h"

namespace sr {
namespace {

using testing::direction_deg;

constexpr double kZ = 4;  // tolerance in standard errors

struct Case {
    Float beta_m, beta_n, h, alpha;
};
const Case kCases[] = {
    {0.3f, 0.3f, 0.0f, 2}, {0.1f, 0.2f, 0.5f, 2}, {0.6f, 0.8f, -0.8f, 5}, {0.25f, 0.05f, 0.95f, 0},
};
// wo (polar angle from the shading normal, azimuth 0.3 from the fibre's axis x): angles
// theta_o from the fibre's normal plane of 73, 33, 29 and 2 degrees.
const double kThetas[] = {90, 35, 150, 178};

HairLobe lobe_of(const Case& c, Float sigma_a = 0) {
    return HairLobe(c.h, 1.55f, SampledSpectrum(sigma_a), c.beta_m, c.beta_n, c.alpha);
}

/// Mean and standard error of g(w) 4 pi over n directions uniform on the sphere: the
/// integral of g over the sphere.
template <typename G>
std::pair<double, double> sphere_integral(G&& g, int n, uint64_t seed) {
    Pcg32 rng(seed);
    double sum = 0, sum2 = 0;
    for (int i = 0; i < n; ++i) {
        const Vec3 w = sample_uniform_sphere(Point2(rng.next_float(), rng.next_float()));
        const double v = g(w) * 4 * 3.141592653589793;
        sum += v;
        sum2 += v * v;
    }
    const double m = sum / n;
    return {m, std::sqrt(std::max(sum2 / n - m * m, 0.0) / n)};
}

TEST(Hair, WhiteFurnaceByUniformSphereSampling) {
    for (const Case& c : kCases) {
        const HairLobe lobe = lobe_of(c);
        for (double t : kThetas) {
            const Vec3 wo = direction_deg(t);
            auto [m, se] = sphere_integral(
                [&](Vec3 wi) {
                    return double(lobe.f(wo, wi, TransportMode::Radiance)[0]) * std::abs(wi.z);
                },
                400000, uint64_t(t * 10 + c.h * 100 + 3));
            EXPECT_LT(std::abs(m - 1), kZ * se)
                << "beta_m " << c.beta_m << " beta_n " << c.beta_n << " h " << c.h << " theta "
                << t << ": " << m << " +- " << se;
        }
    }
}

TEST(Hair, WhiteFurnaceByImportanceSampling) {
    for (const Case& c : kCases) {
        const HairLobe lobe = lobe_of(c);
        for (double t : kThetas) {
            const testing::Albedo a =
                testing::directional_albedo(lobe, direction_deg(t), TransportMode::Radiance, 200000);
            // The sampling weights f |cos| / pdf are nearly constant (the lobes are sampled
            // in proportion to their Ap): the standard error is tiny, and the float
            // evaluation of the normalised lobes (I0 series, exponentials) is the limit.
            EXPECT_LT(std::abs(a.mean[0] - 1), kZ * a.std_error[0] + 2e-5)
                << "beta_m " << c.beta_m << " beta_n " << c.beta_n << " h " << c.h << " theta "
                << t << ": " << a.mean[0] << " +- " << a.std_error[0];
        }
    }
}

TEST(Hair, AbsorptionRemovesEnergy) {
    // With sigma_a > 0 the albedo is below 1, and lower for a larger sigma_a.
    const Case c = kCases[0];
    double last = 1;
    for (Float sa : {0.1f, 0.5f, 2.f, 8.f}) {
        const testing::Albedo a = testing::directional_albedo(lobe_of(c, sa), direction_deg(60),
                                                              TransportMode::Radiance, 100000);
        EXPECT_LT(a.mean[0] + kZ * a.std_error[0], last) << "sigma_a " << sa;
        last = a.mean[0];
    }
    // sigma_a -> infinity leaves the surface reflection R alone: its Fresnel factor at the
    // fibre's normal incidence, ((eta - 1) / (eta + 1))^2 for h = 0 and wo across the fibre
    // (wo.x = 0).
    const testing::Albedo r = testing::directional_albedo(lobe_of(c, 1e4f), Vec3(0, 0.6f, 0.8f),
                                                          TransportMode::Radiance, 100000);
    EXPECT_NEAR(r.mean[0], sqr((1.55 - 1) / (1.55 + 1)), kZ * r.std_error[0] + 2e-5);
}

TEST(Hair, PdfIntegratesToOne) {
    for (const Case& c : kCases) {
        const HairLobe lobe = lobe_of(c, 0.4f);
        for (double t : kThetas) {
            const Vec3 wo = direction_deg(t);
            auto [m, se] = sphere_integral(
                [&](Vec3 wi) { return double(lobe.pdf(wo, wi, TransportMode::Radiance)); }, 400000,
                uint64_t(t * 7 + c.h * 100 + 11));
            EXPECT_LT(std::abs(m - 1), kZ * se) << "h " << c.h << " theta " << t << ": " << m;
        }
    }
}

TEST(Hair, SamplingMatchesPdfChi2) {
    const int tests = int(std::size(kCases) * std::size(kThetas));
    const double alpha = sidak_alpha(0.01, tests);
    for (const Case& c : kCases) {
        const HairLobe lobe = lobe_of(c, 0.4f);
        for (double t : kThetas) {
            testing::SphereChi2Config cfg;
            cfg.sample_count = 300000;
            cfg.seed = uint64_t(t * 1000 + c.h * 100 + c.beta_m * 10);
            const testing::SphereChi2Outcome r =
                testing::lobe_chi2(lobe, direction_deg(t), TransportMode::Radiance, cfg);
            std::printf("[chi2] hair beta (%g, %g) h %g theta_o %g: %s\n", c.beta_m, c.beta_n,
                        c.h, t, r.summary().c_str());
            EXPECT_GT(r.chi2.p_value, alpha) << "h " << c.h << " theta " << t << "\n" << r.tables();
            EXPECT_NEAR(r.pdf_mass, 1, 1e-3);
        }
    }
}

TEST(Hair, SampleAgreesWithFAndPdf) {
    for (const Case& c : kCases) {
        const HairLobe lobe = lobe_of(c, 0.4f);
        for (double t : kThetas) {
            const testing::ConsistencyResult r = testing::check_sample_consistency(
                lobe, direction_deg(t), TransportMode::Radiance, 20000);
            EXPECT_GT(r.samples, 19000);
            // sample() evaluates at the wi it built from its angles; f() and pdf() recover the
            // angles from wi (atan2, asin): relative rounding of the sharp lobes.
            EXPECT_LT(r.max_rel_f, 2e-3) << r.worst;
            EXPECT_LT(r.max_rel_pdf, 2e-3) << r.worst;
        }
    }
}

TEST(Hair, ScatteringIsSymmetricWhereTheModelIsReciprocal) {
    // The model's scattering function S = f |cos theta_z i| is symmetric in (wo, wi) when the
    // attenuations are (they depend on theta_o: equal for |theta_i| = |theta_o|), the lobes are
    // untilted (alpha = 0) and the azimuthal lobes are even (h = 0: gamma_o = gamma_t = 0).
    const HairLobe lobe(0, 1.55f, SampledSpectrum(0.3f), 0.3f, 0.4f, 0);
    Pcg32 rng(5);
    for (int i = 0; i < 200; ++i) {
        const Float st = 2 * rng.next_float() - 1, ct = std::sqrt(1 - st * st);
        const Float po = 2 * kPi * rng.next_float(), pi = 2 * kPi * rng.next_float();
        const Float si = rng.next_float() < 0.5f ? st : -st;
        const Vec3 wo(st, ct * std::cos(po), ct * std::sin(po));
        const Vec3 wi(si, ct * std::cos(pi), ct * std::sin(pi));
        const Float a = lobe.f(wo, wi, TransportMode::Radiance)[0] * std::abs(wi.z);
        const Float b = lobe.f(wi, wo, TransportMode::Radiance)[0] * std::abs(wo.z);
        EXPECT_NEAR(a, b, 1e-4f * std::max(a, b) + 1e-7f) << i;
    }
}

TEST(Hair, SigmaAFromReflectanceIsThePublishedRelation) {
    // Chiang et al. 2016, eq. 9: sigma_a = (ln C / (5.969 - 0.215 beta_n + 2.532 beta_n^2 -
    // 10.73 beta_n^3 + 5.574 beta_n^4 + 0.245 beta_n^5))^2, in double precision here.
    for (double bn : {0.05, 0.3, 0.7, 1.0}) {
        const double den = 5.969 - 0.215 * bn + 2.532 * bn * bn - 10.73 * std::pow(bn, 3) +
                           5.574 * std::pow(bn, 4) + 0.245 * std::pow(bn, 5);
        SampledSpectrum c;
        const double cs[4] = {1.0, 0.8, 0.3, 0.02};
        for (int i = 0; i < 4; ++i) c[i] = Float(cs[i]);
        const SampledSpectrum s = HairLobe::sigma_a_from_reflectance(c, Float(bn));
        for (int i = 0; i < 4; ++i)
            EXPECT_NEAR(s[i], sqr(std::log(cs[i]) / den), 1e-5 * (1 + sqr(std::log(cs[i]) / den)));
        EXPECT_EQ(s[0], 0) << "a white fibre does not absorb";
    }
    // pbrt-v4's melanin absorption (HairBxDF::SigmaAFromConcentration) is linear in the
    // concentrations.
    const auto a = HairLobe::sigma_a_from_concentration(1.3f, 0.5f);
    EXPECT_NEAR(a[0], 1.3 * 0.419 + 0.5 * 0.187, 1e-6);
    EXPECT_NEAR(a[2], 1.3 * 1.37 + 0.5 * 1.05, 1e-6);
}

}  // namespace
}  // namespace sr
