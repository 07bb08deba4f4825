// MeasuredLobe (material "measured", bsdf/measured.h) on stand-in .bsdf files tabulated from
// a closed-form rough conductor (tests/support/measured_standin.h: GGX, Smith's
// height-correlated masking, Schlick's Fresnel term per wavelength), isotropic and
// anisotropic:
// - sample() follows pdf() (chi-square, at incidences on and between the tabulated theta_i
//   and phi_i, and from below), and the pdf's mass plus the fraction of failed samples (the
//   reflection fell below the surface) is 1;
// - sample() returns what f() and pdf() give at its direction;
// - f() converges to the analytic BRDF as the tables are refined: the relative L1 error of
//   f cos over the hemisphere falls as h^2 (bilinear interpolation of smooth functions): the
//   observed order log2(E(h) / E(h/2)) is above 1.5 (2 in theory; 1 would be first order);
// - the albedo is at most 1 and equals the analytic BRDF's albedo within the L1 error of f
//   (|A - A_ref| <= integral |f - f_ref| cos) and the Monte Carlo error;
// - between the file's wavelengths f is linear in the wavelength, outside it takes the
//   nearest (pbrt-v4's interpolation of the spectral table).
#include "steradian/bsdf/measured.h"

#include <gtest/gtest.h>

#include <cstdio>

#include "stat/chi2.h"
#include "stat/lobe_util.h"
#include "stat/reflection_util.h"
#include "steradian/sampling/stats.h"
#include "support/measured_standin.h"

namespace sr {
namespace {

using testing::direction_deg;
constexpr double kZ = 4;

MeasuredBrdf load(const test::StandinSpec& s) {
    return parse_measured_brdf(test::standin_bytes(s), "standin.bsdf");
}

SampledWavelengths file_wavelengths() {
    SampledWavelengths w;
    w.lambda = {400, 500, 600, 700};
    w.pdf = {1, 1, 1, 1};
    return w;
}

test::StandinSpec isotropic(Float alpha) {
    test::StandinSpec s;
    s.alpha_x = s.alpha_y = alpha;
    return s;
}

test::StandinSpec anisotropic() {
    test::StandinSpec s;
    s.alpha_x = 0.15f;
    s.alpha_y = 0.4f;
    s.anisotropic = true;
    s.n_phi_i = 9;
    s.n_theta_i = 8;
    s.vndf_res = s.spectra_res = 24;
    return s;
}

struct Chi2Case {
    const char* name;
    test::StandinSpec spec;
};

TEST(Measured, SamplingMatchesPdfChi2) {
    const Chi2Case cases[] = {{"iso 0.3", isotropic(0.3f)},
                              {"iso 0.08", isotropic(0.08f)},
                              {"aniso 0.15/0.4", anisotropic()}};
    // theta_i of the isotropic stand-ins are multiples of 85/9 deg: 28.33 is one, 37 is not.
    const double thetas[] = {0, 28.333, 37, 65, 84, 130};
    const double phis[] = {0.3, 0.7854};  // between and on the anisotropic phi_i
    const int n_tests = int(std::size(cases) * std::size(thetas) * std::size(phis));
    const double alpha = sidak_alpha(0.01, n_tests);
    for (const Chi2Case& c : cases) {
        MeasuredBrdf b = load(c.spec);
        MeasuredLobe lobe{&b, file_wavelengths()};
        for (double t : thetas)
            for (double phi : phis) {
                testing::SphereChi2Config cfg;
                cfg.seed = uint64_t(t * 1000 + phi * 100);
                Vec3 wo = direction_deg(t, phi);
                testing::SphereChi2Outcome r =
                    testing::lobe_chi2(lobe, wo, TransportMode::Radiance, cfg);
                std::printf("[chi2] measured %s theta_o %g phi_o %g: %s\n", c.name, t, phi,
                            r.summary().c_str());
                EXPECT_GT(r.chi2.p_value, alpha) << c.name << " " << t << "\n" << r.tables();
                // Mass of the pdf + probability of failing = 1 (binomial error of the
                // failure fraction, and the cubature's tolerance).
                double n = double(cfg.sample_count), q = double(r.failures) / n;
                double tol = kZ * std::sqrt(std::max(q * (1 - q), 1 / n) / n) + 1e-4;
                EXPECT_NEAR(r.pdf_mass + q, 1, tol) << c.name << " " << t << " " << phi;
            }
    }
}

TEST(Measured, SampleAgreesWithFAndPdf) {
    for (const test::StandinSpec& s : {isotropic(0.3f), isotropic(0.08f), anisotropic()}) {
        MeasuredBrdf b = load(s);
        MeasuredLobe lobe{&b, file_wavelengths()};
        for (double t : {0.0, 37.0, 70.0, 130.0}) {
            testing::ConsistencyResult r = testing::check_sample_consistency(
                lobe, direction_deg(t), TransportMode::Radiance, 20000);
            EXPECT_GT(r.samples, 10000);
            // sample() and f()/pdf() reach u' by sample() and invert() of the VNDF table,
            // which agree to float rounding.
            EXPECT_LT(r.max_rel_pdf, 2e-3) << s.alpha_x << " " << t << ": " << r.worst;
            EXPECT_LT(r.max_rel_f, 2e-3) << s.alpha_x << " " << t << ": " << r.worst;
        }
    }
}

/// Relative L1 error of the tabulated f cos against the analytic one over wo's hemisphere
/// (midpoint rule on a theta x phi grid), at the wavelength of channel 0; *ref_albedo gets
/// the analytic albedo from the same grid.
double relative_l1_error(const test::StandinSpec& s, const MeasuredBrdf& b, Vec3 wo,
                         double* ref_albedo = nullptr) {
    MeasuredLobe lobe{&b, file_wavelengths()};
    const int nt = 180, np = 360;
    const double dt = 0.5 * 3.141592653589793 / nt, dp = 2 * 3.141592653589793 / np;
    double err = 0, ref = 0;
    for (int i = 0; i < nt; ++i)
        for (int j = 0; j < np; ++j) {
            double theta = (i + 0.5) * dt, phi = -3.141592653589793 + (j + 0.5) * dp;
            Vec3 wi = test::standin_direction(Float(theta), Float(phi));
            double w = std::cos(theta) * std::sin(theta) * dt * dp;
            double ft = lobe.f(wo, wi, TransportMode::Radiance)[0];
            double fr = test::standin_f(s, wo, wi, 400);
            err += std::abs(ft - fr) * w;
            ref += fr * w;
        }
    if (ref_albedo) *ref_albedo = ref;
    return err / ref;
}

TEST(Measured, EvalConvergesToAnalyticBrdf) {
    struct Config {
        const char* name;
        test::StandinSpec spec;
        Vec3 wo;  // on tabulated theta_i (and phi_i)
    };
    test::StandinSpec aniso = anisotropic();
    aniso.n_theta_i = 10;
    const Config configs[] = {
        {"iso 0.3, 28 deg", isotropic(0.3f), direction_deg(85.0 * 3 / 9, 0.3)},
        {"iso 0.3, 57 deg", isotropic(0.3f), direction_deg(85.0 * 6 / 9, 1.0)},
        {"aniso, 38 deg", aniso, direction_deg(85.0 * 4 / 9, 3.14159265 / 4)},
    };
    for (const Config& c : configs) {
        double prev = 0;
        for (int r : {16, 32, 64}) {
            test::StandinSpec s = c.spec;
            s.ndf_res = 2 * r;
            s.vndf_res = s.spectra_res = r;
            MeasuredBrdf b = load(s);
            double e = relative_l1_error(s, b, c.wo);
            std::printf("[eval] measured %s, grids %d: relative L1 error of f cos %.5f%s\n", c.name,
                        r, e, prev > 0 ? fmt::format(" (ratio {:.2f})", prev / e).c_str() : "");
            // Order p = log2(E(h) / E(h / 2)): 2 for bilinear interpolation of smooth
            // functions, 1 if some part of the tables were only first-order accurate.
            if (prev > 0) {
                EXPECT_GT(std::log2(prev / e), 1.5) << c.name << " grid " << r;
            }
            prev = e;
        }
    }
}

TEST(Measured, AlbedoAtMostOneAndMatchesAnalytic) {
    for (test::StandinSpec s : {isotropic(0.3f), isotropic(0.08f), anisotropic()}) {
        s.f0 = {1.0f, 0.5f, 0.7f, 0.3f};  // a perfect reflector at 400 nm
        MeasuredBrdf b = load(s);
        MeasuredLobe lobe{&b, file_wavelengths()};
        for (double t : {0.0, 30.0, 60.0, 80.0}) {
            Vec3 wo = direction_deg(t, 0.3);
            double a_ref = 0;
            double l1 = relative_l1_error(s, b, wo, &a_ref);
            testing::Albedo a =
                testing::directional_albedo(lobe, wo, TransportMode::Radiance, 200000);
            std::printf(
                "[albedo] measured alpha (%g, %g) theta_o %g: %.5f +- %.5f, analytic "
                "%.5f, L1 error bound %.5f\n",
                s.alpha_x, s.alpha_y, t, a.mean[0], a.std_error[0], a_ref, l1 * a_ref);
            EXPECT_LE(a.mean[0], 1 + kZ * a.std_error[0]) << s.alpha_x << " " << t;
            EXPECT_NEAR(a.mean[0], a_ref, kZ * a.std_error[0] + l1 * a_ref)
                << s.alpha_x << " " << t;
        }
    }
}

TEST(Measured, LinearBetweenTheFileWavelengths) {
    test::StandinSpec s = isotropic(0.3f);
    MeasuredBrdf b = load(s);
    MeasuredLobe at_file{&b, file_wavelengths()};
    SampledWavelengths other;
    other.lambda = {450, 620, 380, 760};
    other.pdf = {1, 1, 1, 1};
    MeasuredLobe between{&b, other};
    Pcg32 rng(5);
    for (int k = 0; k < 500; ++k) {
        Vec3 wo = direction_deg(80 * rng.next_float(), 6.283 * rng.next_float());
        Vec3 wi = direction_deg(80 * rng.next_float(), 6.283 * rng.next_float());
        SampledSpectrum f = at_file.f(wo, wi, TransportMode::Radiance);
        SampledSpectrum g = between.f(wo, wi, TransportMode::Radiance);
        double tol = 1e-5 * (1 + f.max_value());
        EXPECT_NEAR(g[0], 0.5 * (f[0] + f[1]), tol);
        EXPECT_NEAR(g[1], 0.8 * f[2] + 0.2 * f[3], tol);
        EXPECT_NEAR(g[2], f[0], tol);
        EXPECT_NEAR(g[3], f[3], tol);
    }
}

}  // namespace
}  // namespace sr
