// Fresnel equations, reflection and refraction against closed forms and physical identities:
// normal incidence, Brewster's angle, total internal reflection, Stokes reciprocity of the
// transmittance, the conductor limit k -> 0, gold's normal-incidence reflectance from its
// tabulated n and k, and Snell's law.
#include "steradian/bsdf/fresnel.h"

#include <gtest/gtest.h>

#include <cmath>
#include <complex>

#include "stat/lobe_util.h"
#include "steradian/spectrum/spectrum.h"

namespace sr {
namespace {

using testing::direction_deg;

constexpr double kPiD = 3.141592653589793;

TEST(Fresnel, NormalIncidence) {
    for (double eta : {1.0, 1.33, 1.5, 2.42, 1 / 1.5}) {
        double expected = std::pow((eta - 1) / (eta + 1), 2);
        EXPECT_NEAR(fr_dielectric(1, Float(eta)), expected, 1e-7) << eta;
        // From the far side: the same reflectance (eta inverted, the formula is symmetric).
        EXPECT_NEAR(fr_dielectric(-1, Float(eta)), expected, 1e-7) << eta;
        FresnelSp sp = fr_dielectric_sp(1, Float(eta));
        EXPECT_NEAR(sp.rs, expected, 1e-7);
        EXPECT_NEAR(sp.rp, expected, 1e-7);
    }
    EXPECT_NEAR(fr_dielectric(1, 1.5f), 0.04, 1e-7);
}

TEST(Fresnel, BrewsterAngleHasNoPPolarisedReflection) {
    for (double eta : {1.33, 1.5, 2.0, 1 / 1.5}) {
        double theta_b = std::atan(eta);  // tan(theta_B) = n_t / n_i
        FresnelSp sp = fr_dielectric_sp(Float(std::cos(theta_b)), Float(eta));
        EXPECT_LT(sp.rp, 1e-7) << eta;
        EXPECT_GT(sp.rs, 0.01) << eta;
        // Slightly off Brewster's angle rp is positive again.
        EXPECT_GT(fr_dielectric_sp(Float(std::cos(theta_b + 0.1)), Float(eta)).rp, 1e-4);
        EXPECT_GT(fr_dielectric_sp(Float(std::cos(theta_b - 0.1)), Float(eta)).rp, 1e-4);
    }
}

TEST(Fresnel, TotalInternalReflectionPastTheCriticalAngle) {
    const double eta = 1.5;
    const double theta_c = std::asin(1 / eta);  // from inside the glass
    for (double dt : {1e-3, 0.05, 0.3}) {
        // Inside looking out: eta = 1/1.5 seen from the near side, or 1.5 from the far side.
        double c_past = std::cos(theta_c + dt), c_before = std::cos(theta_c - dt);
        EXPECT_EQ(fr_dielectric(Float(c_past), Float(1 / eta)), 1);
        EXPECT_EQ(fr_dielectric(-Float(c_past), Float(eta)), 1);
        EXPECT_LT(fr_dielectric(Float(c_before), Float(1 / eta)), 1);
        EXPECT_LT(fr_dielectric(-Float(c_before), Float(eta)), 1);
        Vec3 wt;
        EXPECT_FALSE(refract(direction_deg(-(theta_c + dt) * 180 / kPiD + 180), Vec3(0, 0, 1),
                             Float(eta), nullptr, &wt));
    }
    // Grazing incidence reflects everything.
    EXPECT_EQ(fr_dielectric(0, 1.5f), 1);
    EXPECT_NEAR(fr_complex(0, 0.2f, 3.0f), 1, 1e-6);
}

TEST(Fresnel, TransmittanceIsReciprocal) {
    // Stokes relations: T(theta_i, eta) = T(theta_t, 1/eta), so R is the same from both sides
    // of the interface along a refracted pair of directions.
    for (double eta : {1.33, 1.5, 2.4}) {
        for (double t = 0; t < 89.5; t += 7.5) {
            double ti = t * kPiD / 180;
            double tt = std::asin(std::sin(ti) / eta);
            EXPECT_NEAR(fr_dielectric(Float(std::cos(ti)), Float(eta)),
                        fr_dielectric(Float(std::cos(tt)), Float(1 / eta)), 2e-6)
                << eta << " " << t;
        }
    }
}

TEST(Fresnel, ConductorWithoutAbsorptionIsADielectric) {
    for (double eta : {1.2, 1.5, 3.0}) {
        for (double c = 0.02; c <= 1; c += 0.07) {
            EXPECT_NEAR(fr_complex(Float(c), Float(eta), 0), fr_dielectric(Float(c), Float(eta)),
                        2e-6)
                << eta << " " << c;
        }
    }
}

/// The conductor Fresnel equations in complex double arithmetic (Born & Wolf Sec. 14.2),
/// the direct transcription that fr_complex rewrites in real float arithmetic.
double fr_complex_reference(double cos_i, double n, double k) {
    using C = std::complex<double>;
    C eta(n, k);
    double s2 = 1 - cos_i * cos_i;
    C cos_t = std::sqrt(1.0 - s2 / (eta * eta));
    C r_s = (cos_i - eta * cos_t) / (cos_i + eta * cos_t);
    C r_p = (eta * cos_i - cos_t) / (eta * cos_i + cos_t);
    return 0.5 * (std::norm(r_s) + std::norm(r_p));
}

TEST(Fresnel, ConductorMatchesComplexReference) {
    // Metals (n < 1, large k), absorbing dielectrics, and n < 1 without absorption (total
    // reflection past the critical angle).
    const double nks[][2] = {{0.13, 4.1}, {0.05, 4.0}, {1.4, 1.9}, {2.9, 3.0},
                             {1.5, 0.01}, {0.7, 0.0},  {1.0, 1e3}, {3.5, 0.5}};
    for (const auto& nk : nks) {
        for (double c = 0; c <= 1.0001; c += 0.05) {
            double cc = std::min(c, 1.0);
            EXPECT_NEAR(fr_complex(Float(cc), Float(nk[0]), Float(nk[1])),
                        fr_complex_reference(cc, nk[0], nk[1]), 3e-6)
                << nk[0] << " " << nk[1] << " " << cc;
        }
    }
}

TEST(Fresnel, GoldAtNormalIncidence) {
    std::optional<Spectrum> n = named_spectrum("metal-Au-eta"), k = named_spectrum("metal-Au-k");
    ASSERT_TRUE(n && k);
    for (double lambda : {420.0, 500.0, 550.0, 620.0, 700.0}) {
        double nn = (*n)(Float(lambda)), kk = (*k)(Float(lambda));
        double expected = ((nn - 1) * (nn - 1) + kk * kk) / ((nn + 1) * (nn + 1) + kk * kk);
        EXPECT_NEAR(fr_complex(1, Float(nn), Float(kk)), expected, 1e-6) << lambda;
    }
    // Gold is yellow: it reflects red far better than blue.
    EXPECT_GT(fr_complex(1, (*n)(700), (*k)(700)), 0.9);
    EXPECT_LT(fr_complex(1, (*n)(450), (*k)(450)), 0.5);
    // The spectral version is the scalar one per wavelength, and reflectance rises to 1 at
    // grazing incidence.
    SampledWavelengths lam = SampledWavelengths::sample_uniform(0.3f);
    SampledSpectrum se = n->sample(lam), sk = k->sample(lam);
    for (double c : {1.0, 0.5, 0.1}) {
        SampledSpectrum r = fr_complex(Float(c), se, sk);
        for (int i = 0; i < kSpectrumSamples; ++i)
            EXPECT_FLOAT_EQ(r[i], fr_complex(Float(c), se[i], sk[i]));
    }
    for (int i = 0; i < kSpectrumSamples; ++i)
        EXPECT_GT(fr_complex(0.01f, se, sk)[i], fr_complex(1, se, sk)[i]);
}

TEST(Fresnel, SpectralDielectricMatchesScalar) {
    SampledSpectrum eta;
    eta.v = Float4{1.3f, 1.5f, 1 / 1.5f, 2.0f};
    SampledSpectrum r = fr_dielectric(0.4f, eta);
    // Equal up to rounding: the compiler may vectorise or contract the two forms differently.
    for (int i = 0; i < kSpectrumSamples; ++i) EXPECT_FLOAT_EQ(r[i], fr_dielectric(0.4f, eta[i]));
}

TEST(Fresnel, ReflectAndRefractObeySnellsLaw) {
    Vec3 n(0, 0, 1);
    for (double eta : {1.5, 1 / 1.5, 1.0}) {
        for (double t : {0.0, 20.0, 40.0, 60.0, 85.0, 100.0, 130.0, 170.0}) {
            Vec3 wi = direction_deg(t, 0.9);
            Vec3 wr = reflect(wi, n);
            EXPECT_NEAR(wr.x, -wi.x, 1e-6);
            EXPECT_NEAR(wr.y, -wi.y, 1e-6);
            EXPECT_NEAR(wr.z, wi.z, 1e-6);

            Vec3 wt;
            Float etap = 0;
            bool ok = refract(wi, n, Float(eta), &etap, &wt);
            // The relative IOR crossed: eta from above, 1/eta from below.
            double eta_rel = wi.z >= 0 ? eta : 1 / eta;
            double sin_i = std::sqrt(std::max(0.0, 1.0 - double(wi.z) * wi.z));
            if (sin_i / eta_rel >= 1) {
                EXPECT_FALSE(ok) << eta << " " << t;
                continue;
            }
            ASSERT_TRUE(ok) << eta << " " << t;
            EXPECT_NEAR(etap, eta_rel, 1e-6);
            EXPECT_NEAR(length(wt), 1, 1e-5);
            EXPECT_LT(wt.z * wi.z, 0);  // the other side
            double sin_t = std::sqrt(std::max(0.0, 1.0 - double(wt.z) * wt.z));
            EXPECT_NEAR(eta_rel * sin_t, sin_i, 1e-5) << eta << " " << t;
            // Coplanar with wi and n, on the other side of the normal in azimuth.
            EXPECT_NEAR(dot(cross(wi, n), wt), 0, 1e-6);
            if (sin_i > 1e-3) {
                EXPECT_LT(wi.x * wt.x + wi.y * wt.y, 0);
            }
            // Refracting back returns the original direction.
            Vec3 back;
            ASSERT_TRUE(refract(wt, n, Float(eta), nullptr, &back));
            EXPECT_NEAR(back.x, wi.x, 1e-5);
            EXPECT_NEAR(back.y, wi.y, 1e-5);
            EXPECT_NEAR(back.z, wi.z, 1e-5);
        }
    }
}

}  // namespace
}  // namespace sr
