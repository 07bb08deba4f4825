// PhongLobe (materials "phong" and "modifiedphong"): chi-square of sample() against pdf() over
// exponents from 0 to 1000, both sampling schemes, incident directions from normal to grazing
// and from below; consistency of sample() with f() and pdf(); Helmholtz reciprocity; the
// directional albedo <= 1 at every incidence when kd + ks = 1 (Monte Carlo and cubature), its
// closed form kd + ks at normal incidence, the Lambert part exactly kd, its maximum at normal
// incidence, and the absorption probability of the Lafortune-Willems scheme.
#include "steradian/bsdf/phong.h"

#include <gtest/gtest.h>

#include <cstdio>
#include <limits>

#include "stat/chi2.h"
#include "stat/lobe_util.h"
#include "stat/reflection_util.h"
#include "steradian/sampling/stats.h"

namespace sr {
namespace {

using testing::direction_deg;

constexpr double kZ = 4;  // tolerance in standard errors (two-sided p ~ 6e-5 per check)
constexpr double kEps = std::numeric_limits<Float>::epsilon();

/// A spectrally varying albedo: scale times a fixed shape with maximum 1.
SampledSpectrum tinted(Float scale) {
    SampledSpectrum s;
    const Float shape[4] = {1.0f, 0.8f, 0.55f, 0.9f};
    for (int i = 0; i < kSpectrumSamples; ++i) s[i] = scale * shape[i % 4];
    return s;
}

struct Case {
    Float kd, ks, n;
    bool absorb;
};
const Case kCases[] = {
    {0.5f, 0.5f, 0, false},   {0.3f, 0.7f, 1, false},    {0.2f, 0.8f, 10, false},
    {0.1f, 0.9f, 100, false}, {0.0f, 1.0f, 1000, false}, {0.4f, 0.4f, 30, true},
    {0.1f, 0.3f, 5, true},
};
const double kThetas[] = {0, 35, 70, 88, 125};  // 125: wo below the surface
constexpr int kNumChi2Tests = int(std::size(kCases) * std::size(kThetas));

PhongLobe lobe_of(const Case& c) { return PhongLobe{tinted(c.kd), tinted(c.ks), c.n, c.absorb}; }

TEST(Phong, SamplingMatchesPdfChi2) {
    const double alpha = sidak_alpha(0.01, kNumChi2Tests);
    double p_min = 1;
    for (const Case& c : kCases) {
        PhongLobe lobe = lobe_of(c);
        for (double t : kThetas) {
            testing::SphereChi2Config cfg;
            cfg.seed = uint64_t(1000 * t + 10 * c.n + (c.absorb ? 7 : 3));
            testing::SphereChi2Outcome r =
                testing::lobe_chi2(lobe, direction_deg(t), TransportMode::Radiance, cfg);
            std::printf("[chi2] phong kd %g ks %g n %g absorb %d theta_o %g: %s\n", c.kd, c.ks, c.n,
                        c.absorb, t, r.summary().c_str());
            p_min = std::min(p_min, r.chi2.p_value);
            EXPECT_GT(r.chi2.p_value, alpha) << "n " << c.n << " theta_o " << t << "\n"
                                             << r.tables();
        }
    }
    std::printf("[chi2] phong: %d tests, smallest p %.3g, per-test alpha %.3g\n", kNumChi2Tests,
                p_min, alpha);
}

// The weight f |cos| / pdf that an integrator forms from sample() must equal the one from f()
// and pdf() at the same wi. sample() takes the chosen strategy's density from its sampling
// variables (cos alpha = u^(1/(n+1))), pdf() from the direction: rounding of wi, amplified by
// the exponent, bounds the difference.
TEST(Phong, SampleAgreesWithFAndPdf) {
    for (const Case& c : kCases) {
        PhongLobe lobe = lobe_of(c);
        double tol = 64 * kEps * (2 + c.n);
        for (double t : kThetas) {
            testing::ConsistencyResult r = testing::check_sample_consistency(
                lobe, direction_deg(t), TransportMode::Radiance, 20000);
            EXPECT_GT(r.samples, 2000);
            EXPECT_LT(r.max_rel_f, tol) << c.n << " " << t << ": " << r.worst;
            EXPECT_LT(r.max_rel_pdf, tol) << c.n << " " << t << ": " << r.worst;
        }
    }
}

TEST(Phong, HelmholtzReciprocity) {
    for (const Case& c : kCases)
        EXPECT_LT(testing::max_reciprocity_error(lobe_of(c), 20000, 11), 64 * kEps * (2 + c.n))
            << "n " << c.n;
}

// kd + ks = 1 (the largest the material allows): the albedo is at most 1 at every incidence,
// by Monte Carlo (mean within kZ standard errors) for both sampling schemes, and by cubature
// (within its error bound). f is linear in (kd, ks) and the Lambert part's albedo is kd, so
// the cubature of the specular lobe alone, A_s, gives every mix: kd + (1 - kd) A_s.
TEST(Phong, AlbedoAtMostOneWhenKdPlusKsIsOne) {
    for (Float n : {0.f, 1.f, 5.f, 50.f, 500.f}) {
        double a_min = 2, a_max = 0;
        for (double t : testing::albedo_thetas()) {
            Vec3 wo = direction_deg(t);
            PhongLobe specular{SampledSpectrum(0), SampledSpectrum(1), n, false};
            double a_s = testing::albedo_by_cubature(specular, wo, 0);
            a_min = std::min(a_min, a_s);
            a_max = std::max(a_max, a_s);
            EXPECT_LE(a_s, 1 + testing::cubature_error(1)) << n << " " << t;
            for (Float kd : {0.f, 0.3f, 0.8f}) {
                double q = kd + (1 - kd) * a_s;
                for (bool absorb : {false, true}) {
                    PhongLobe lobe{SampledSpectrum(kd), SampledSpectrum(1 - kd), n, absorb};
                    testing::Albedo a =
                        testing::directional_albedo(lobe, wo, TransportMode::Radiance, 40000);
                    EXPECT_LE(a.mean[0], 1 + kZ * a.std_error[0])
                        << n << " " << kd << " " << t << " " << absorb;
                    EXPECT_NEAR(a.mean[0], q, kZ * a.std_error[0] + testing::cubature_error(q))
                        << n << " " << kd << " " << t << " " << absorb;
                }
            }
        }
        std::printf("[albedo] phong n %g, ks = 1: specular albedo in [%.5f, %.5f]\n", n, a_min,
                    a_max);
    }
}

// Closed form at normal incidence: the mirror direction is the normal, so the lobe is not
// clipped and int (n + 2) / (2 pi) cos^n(theta) cos(theta) dw = 1: albedo = kd + ks exactly,
// at every wavelength (Monte Carlo here; SpecularAlbedoIsLargestAtNormalIncidence checks the
// specular lobe's 1 by cubature).
TEST(Phong, AlbedoAtNormalIncidenceIsKdPlusKs) {
    for (const Case& c : kCases) {
        PhongLobe lobe = lobe_of(c);
        for (Vec3 wo : {Vec3(0, 0, 1), Vec3(0, 0, -1)}) {
            testing::Albedo a =
                testing::directional_albedo(lobe, wo, TransportMode::Radiance, 100000);
            for (int i = 0; i < kSpectrumSamples; ++i)
                EXPECT_NEAR(a.mean[i], lobe.kd[i] + lobe.ks[i], kZ * a.std_error[i] + 8 * kEps)
                    << c.n;
        }
    }
}

// ks = 0: f = kd / pi and every sample is cosine-weighted, so each weight is kd exactly (up to
// rounding) and the albedo is kd at every incidence (zero variance).
TEST(Phong, LambertPartIsExactlyKd) {
    PhongLobe lobe{tinted(0.7f), SampledSpectrum(0), 10, false};
    EXPECT_EQ(lobe.flags(), kLobeReflection | kLobeDiffuse);
    for (double t : testing::albedo_thetas()) {
        testing::Albedo a =
            testing::directional_albedo(lobe, direction_deg(t), TransportMode::Radiance, 10000);
        for (int i = 0; i < kSpectrumSamples; ++i) {
            EXPECT_NEAR(a.mean[i], lobe.kd[i], 8 * kEps) << t;
            EXPECT_LE(a.std_error[i], 8 * kEps) << t;
        }
    }
}

// The horizon only removes lobe mass as wo tilts: the specular albedo is largest at normal
// incidence (where it is ks), so kd + ks <= 1 suffices for energy conservation.
TEST(Phong, SpecularAlbedoIsLargestAtNormalIncidence) {
    for (Float n : {0.f, 1.f, 3.f, 10.f, 100.f, 1000.f}) {
        PhongLobe lobe{SampledSpectrum(0), SampledSpectrum(1), n, false};
        double normal = testing::albedo_by_cubature(lobe, Vec3(0, 0, 1), 0);
        EXPECT_NEAR(normal, 1, testing::cubature_error(1)) << n;
        double prev = normal;
        for (double t = 5; t < 90; t += 5) {
            double a = testing::albedo_by_cubature(lobe, direction_deg(t), 0);
            EXPECT_LE(a, prev + 2 * testing::cubature_error(1)) << "n " << n << " theta " << t;
            prev = a;
        }
    }
}

// The Lafortune-Willems scheme absorbs with probability 1 - avg(kd) - avg(ks): at normal
// incidence nothing else fails (the specular lobe's hemisphere is the upper one), so the
// failed fraction is binomial with that probability.
TEST(Phong, ModifiedPhongAbsorbsWithProbabilityOneMinusAlbedo) {
    PhongLobe lobe{tinted(0.3f), tinted(0.4f), 20, true};
    double p_absorb = 1 - lobe.kd.average() - lobe.ks.average();
    const int n = 200000;
    Pcg32 rng(17);
    int failed = 0;
    for (int k = 0; k < n; ++k) {
        Float uc = rng.next_float();
        Point2 u{rng.next_float(), rng.next_float()};
        if (!lobe.sample(Vec3(0, 0, 1), uc, u, TransportMode::Radiance)) ++failed;
    }
    double frac = double(failed) / n, se = std::sqrt(p_absorb * (1 - p_absorb) / n);
    EXPECT_NEAR(frac, p_absorb, kZ * se);
    // The pdf integrates to the probability of not absorbing.
    double mass = 0;
    const double pi = 3.141592653589793;
    auto pdf = [&](Vec3 w) { return lobe.pdf(Vec3(0, 0, 1), w, TransportMode::Radiance); };
    for (int i = 0; i < 9; ++i)
        for (int j = 0; j < 18; ++j)
            mass +=
                testing::sphere_cell_integral(pdf, i * pi / 18, (i + 1) * pi / 18, -pi + j * pi / 9,
                                              -pi + (j + 1) * pi / 9, testing::kCellTolerance);
    EXPECT_NEAR(mass, 1 - p_absorb, testing::cubature_error(1));
}

}  // namespace
}  // namespace sr
