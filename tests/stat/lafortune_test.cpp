// LafortuneLobe (material "lafortune"): chi-square of sample() against pdf() for Phong-like,
// off-specular, retro-reflective, anisotropic, multi-lobe, n = 0 and below-the-horizon lobes
// from normal to grazing incidence and from below; consistency of sample() with f() and pdf();
// Helmholtz reciprocity; the closed-form albedo at normal incidence; albedo <= 1 for parameter
// sets that satisfy the sufficient condition of lafortune.h (Monte Carlo and cubature);
// equality with the Phong lobe for C = (-1, -1, 1) scaled; and a parameter set that creates
// energy, which the model allows and lafortune_max_albedo detects.
#include "steradian/bsdf/lafortune.h"

#include <gtest/gtest.h>

#include <cstdio>
#include <limits>
#include <string>
#include <vector>

#include "stat/chi2.h"
#include "stat/lobe_util.h"
#include "stat/reflection_util.h"
#include "steradian/bsdf/phong.h"
#include "steradian/sampling/stats.h"

namespace sr {
namespace {

using testing::direction_deg;

constexpr double kZ = 4;  // tolerance in standard errors
constexpr double kEps = std::numeric_limits<Float>::epsilon();
constexpr double kPiD = 3.141592653589793;

LafortuneLobe make(Float rho_d, std::vector<LafortuneCosine> lobes) {
    LafortuneLobe l;
    l.rho_d = SampledSpectrum(rho_d);
    // A spectrally varying diffuse term, so the four wavelengths differ.
    l.rho_d[1] *= 0.7f;
    l.rho_d[2] *= 0.4f;
    l.count = int(lobes.size());
    for (size_t i = 0; i < lobes.size(); ++i) l.lobes[i] = lobes[i];
    return l;
}

/// rho of a Phong lobe C = (-1, -1, 1), exponent n, normalised to specular albedo ks at normal
/// incidence: ks (n + 2) / (2 pi).
Float phong_rho(Float ks, Float n) { return Float(ks * (n + 2) / (2 * kPiD)); }

struct Case {
    const char* name;
    LafortuneLobe lobe;
};
const std::vector<Case>& cases() {
    static const std::vector<Case> c = {
        {"phong-like", make(0.3f, {{-1, -1, 1, 20, phong_rho(0.7f, 20)}})},
        {"off-specular", make(0.1f, {{-1.1f, -1.1f, 1, 10, 0.5f}})},
        {"retro", make(0.2f, {{0.8f, 0.8f, 1, 8, 0.6f}})},
        {"anisotropic", make(0.2f, {{-1, -0.5f, 0.9f, 15, 1.2f}})},
        {"three lobes", make(0.15f, {{-1, -1, 1, 50, phong_rho(0.3f, 50)},
                                     {0, 0, 1, 3, phong_rho(0.2f, 3)},
                                     {0.9f, 0.9f, 0.9f, 5, 0.3f}})},
        {"n = 0", make(0, {{-1, -1, 1, 0, 0.3f}})},
        {"axis below horizon", make(0.1f, {{1, 1, -0.3f, 4, 0.5f}})},
        {"sharp", make(0, {{-1, -1, 1, 500, phong_rho(0.9f, 500)}})},
    };
    return c;
}
const double kThetas[] = {0, 35, 70, 88, 125};

Float max_exponent(const LafortuneLobe& l) {
    Float n = 0;
    for (int i = 0; i < l.count; ++i) n = std::max(n, l.lobes[i].n);
    return n;
}

TEST(Lafortune, SamplingMatchesPdfChi2) {
    const int num_tests = int(cases().size() * std::size(kThetas));
    const double alpha = sidak_alpha(0.01, num_tests);
    double p_min = 1;
    int k = 0;
    for (const Case& c : cases()) {
        for (double t : kThetas) {
            testing::SphereChi2Config cfg;
            cfg.seed = uint64_t(100 + k++);
            testing::SphereChi2Outcome r =
                testing::lobe_chi2(c.lobe, direction_deg(t), TransportMode::Radiance, cfg);
            std::printf("[chi2] lafortune %s theta_o %g: %s\n", c.name, t, r.summary().c_str());
            p_min = std::min(p_min, r.chi2.p_value);
            EXPECT_GT(r.chi2.p_value, alpha) << c.name << " theta_o " << t << "\n" << r.tables();
        }
    }
    std::printf("[chi2] lafortune: %d tests, smallest p %.3g, per-test alpha %.3g\n", num_tests,
                p_min, alpha);
}

// sample() takes the chosen component's density from its sampling variables and the others'
// from wi; pdf() all from wi. Rounding of wi, amplified by the exponent, bounds the difference.
TEST(Lafortune, SampleAgreesWithFAndPdf) {
    for (const Case& c : cases()) {
        double tol = 64 * kEps * (2 + max_exponent(c.lobe));
        for (double t : kThetas) {
            testing::ConsistencyResult r = testing::check_sample_consistency(
                c.lobe, direction_deg(t), TransportMode::Radiance, 20000);
            EXPECT_LT(r.max_rel_f, tol) << c.name << " " << t << ": " << r.worst;
            EXPECT_LT(r.max_rel_pdf, tol) << c.name << " " << t << ": " << r.worst;
        }
    }
}

TEST(Lafortune, HelmholtzReciprocity) {
    for (const Case& c : cases())
        EXPECT_LT(testing::max_reciprocity_error(c.lobe, 20000, 13),
                  64 * kEps * (2 + max_exponent(c.lobe)))
            << c.name;
}

// Normal incidence, wo = z: the bracket of lobe i is Cz wi.z, so its albedo is
// rho_i max(Cz, 0)^n 2 pi / (n + 2); the diffuse term adds rho_d.
TEST(Lafortune, AlbedoAtNormalIncidenceHasClosedForm) {
    for (const Case& c : cases()) {
        double lobes = 0;
        for (int i = 0; i < c.lobe.count; ++i) {
            const LafortuneCosine& l = c.lobe.lobes[i];
            lobes +=
                l.rho * std::pow(std::max(0.0, double(l.cz)), double(l.n)) * 2 * kPiD / (l.n + 2);
        }
        for (Vec3 wo : {Vec3(0, 0, 1), Vec3(0, 0, -1)}) {
            testing::Albedo a =
                testing::directional_albedo(c.lobe, wo, TransportMode::Radiance, 100000);
            for (int i = 0; i < kSpectrumSamples; ++i)
                EXPECT_NEAR(a.mean[i], c.lobe.rho_d[i] + lobes, kZ * a.std_error[i] + 8 * kEps)
                    << c.name;
        }
    }
}

/// A set satisfying lafortune.h's sufficient condition: lobe i gets rho_i = w_i (n_i + 1) /
/// (2 pi Cmax_i^n_i), and rho_d + sum w_i = 1.
LafortuneLobe sufficient(Float rho_d, std::vector<std::pair<LafortuneCosine, Float>> lobes) {
    std::vector<LafortuneCosine> v;
    for (auto [l, w] : lobes) {
        double cmax = std::max({std::abs(l.cx), std::abs(l.cy), std::abs(l.cz)});
        l.rho = Float(w * (l.n + 1) / (2 * kPiD * std::pow(cmax, double(l.n))));
        v.push_back(l);
    }
    LafortuneLobe out = make(rho_d, v);
    out.rho_d = SampledSpectrum(rho_d);
    return out;
}

// "Physically sensible" parameter sets: those meeting the sufficient condition, and
// Phong-normalised lobes with rho_d + ks = 1. Their albedo must be <= 1 at every incidence
// and azimuth (Monte Carlo within kZ standard errors; cubature within its error bound, and
// both must agree).
TEST(Lafortune, AlbedoAtMostOneForSensibleParameters) {
    const std::vector<std::pair<const char*, LafortuneLobe>> sets = {
        {"phong-like", sufficient(0.2f, {{{-1, -1, 1, 10, 1}, 0.8f}})},
        {"off-specular + retro",
         sufficient(0.1f, {{{-0.9f, -0.9f, 1, 30, 1}, 0.5f}, {{0.7f, 0.7f, 0.8f, 5, 1}, 0.4f}})},
        {"anisotropic", sufficient(0, {{{-1, -0.4f, 0.8f, 12, 1}, 1}})},
        {"normal lobe", sufficient(0.3f, {{{0, 0, 1, 2, 1}, 0.7f}})},
        {"phong-normalised",
         [] {
             LafortuneLobe l = make(0.4f, {{-1, -1, 1, 25, phong_rho(0.6f, 25)}});
             l.rho_d = SampledSpectrum(0.4f);
             return l;
         }()},
    };
    for (const auto& [name, lobe] : sets) {
        for (double t : testing::albedo_thetas()) {
            for (double phi : {0.3, 1.2}) {
                Vec3 wo = direction_deg(t, phi);
                testing::Albedo a =
                    testing::directional_albedo(lobe, wo, TransportMode::Radiance, 40000);
                EXPECT_LE(a.mean[0], 1 + kZ * a.std_error[0]) << name << " " << t << " " << phi;
                if (phi != 0.3) continue;
                double q = testing::albedo_by_cubature(lobe, wo, 0);
                EXPECT_LE(q, 1 + testing::cubature_error(1)) << name << " " << t;
                EXPECT_NEAR(a.mean[0], q, kZ * a.std_error[0] + testing::cubature_error(q))
                    << name << " " << t;
            }
        }
    }
}

// With C = (-k, -k, k), k^n = (n + 2) / (2 pi) ks / rho, the model is the normalised Phong
// BRDF: f agrees with PhongLobe everywhere.
TEST(Lafortune, ReducesToPhong) {
    for (Float n : {0.5f, 4.f, 40.f}) {
        Float kd = 0.35f, ks = 0.6f, rho = 0.8f;
        Float k = Float(std::pow((n + 2) / (2 * kPiD) * ks / rho, 1.0 / n));
        LafortuneLobe laf = make(kd, {{-k, -k, k, n, rho}});
        laf.rho_d = SampledSpectrum(kd);
        PhongLobe phong{SampledSpectrum(kd), SampledSpectrum(ks), n, false};
        Pcg32 rng(5);
        double worst = 0;
        for (int j = 0; j < 20000; ++j) {
            Vec3 wo = sample_uniform_sphere({rng.next_float(), rng.next_float()});
            Vec3 wi = sample_uniform_sphere({rng.next_float(), rng.next_float()});
            Float a = laf.f(wo, wi, TransportMode::Radiance)[0];
            Float b = phong.f(wo, wi, TransportMode::Radiance)[0];
            worst = std::max(worst, testing::rel_diff(a, b));
        }
        EXPECT_LT(worst, 64 * kEps * (2 + n)) << n;
    }
}

// The model does not conserve energy for arbitrary parameters: a lobe with |Cx| = |Cy| > Cz,
// normalised to albedo 1 at normal incidence, grows as (|C o wo| cos)^n towards grazing and
// reflects more than it receives. lafortune_max_albedo (the builder's warning) detects it.
TEST(Lafortune, ArbitraryParametersCanCreateEnergy) {
    const Float n = 6;
    LafortuneLobe lobe = make(0, {{-1.6f, -1.6f, 1, n, Float((n + 2) / (2 * kPiD))}});
    testing::Albedo normal =
        testing::directional_albedo(lobe, Vec3(0, 0, 1), TransportMode::Radiance, 100000);
    EXPECT_NEAR(normal.mean[0], 1, kZ * normal.std_error[0]);
    testing::Albedo grazing =
        testing::directional_albedo(lobe, direction_deg(75), TransportMode::Radiance, 100000);
    EXPECT_GT(grazing.mean[0], 1 + kZ * grazing.std_error[0]);
    LafortuneAlbedo worst = lafortune_max_albedo(lobe);
    EXPECT_GT(worst.albedo - 3 * worst.std_error, 1);
    EXPECT_GT(worst.theta_deg, 45);
    // A conserving set is not flagged.
    LafortuneAlbedo fine = lafortune_max_albedo(sufficient(0.2f, {{{-1, -1, 1, 10, 1}, 0.8f}}));
    EXPECT_LE(fine.albedo - 3 * fine.std_error, 1);
}

}  // namespace
}  // namespace sr
