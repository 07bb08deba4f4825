// pbrt-v4's "subsurface" material: its parameters against pbrt-v4's SubsurfaceMaterial::Create
// (defaults, the named measured media times "scale", the located errors), the exit lobe's
// normalisation, and the albedo inversion used for "reflectance" + "mfp".
#include "steradian/material/subsurface.h"

#include <gtest/gtest.h>

#include <cmath>
#include <string>

#include "steradian/bsdf/normalized_fresnel.h"
#include "steradian/sampling/rng.h"
#include "steradian/scene/build.h"
#include "steradian/scene/pbrt/parser.h"

namespace sr {
namespace {

/// Builds a scene whose line 2 is `material`, followed by a sphere that uses it.
Scene build(const std::string& material) {
    return build_scene(
        parse_pbrt_string("WorldBegin\n" + material + "\nShape \"sphere\"\n", "sss.pbrt"));
}

const SubsurfaceMaterial& only_subsurface(const Scene& s) {
    const SubsurfaceMaterial* found = nullptr;
    for (const Material& m : s.materials)
        if (const auto* p = std::get_if<SubsurfaceMaterial>(&m)) found = p;
    EXPECT_NE(found, nullptr);
    static const SubsurfaceMaterial none;
    return found ? *found : none;
}

const SampledWavelengths kLambda = SampledWavelengths::sample_uniform(0.17f);

SubsurfaceCoefficients coefficients(const Scene& s) {
    SurfaceHit h;
    h.ng = h.ns = Normal3(0, 0, 1);
    return subsurface_coefficients(only_subsurface(s), s.material_context(), h, kLambda);
}

/// pbrt-v4's RGBUnboundedSpectrum of an sRGB triple at the wavelengths of kLambda.
SampledSpectrum rgb(Float r, Float g, Float b) {
    return Spectrum(rgb_unbounded_spectrum(Rgb{r, g, b})).sample(kLambda);
}

void expect_near(const SampledSpectrum& a, const SampledSpectrum& b, double rel) {
    for (int i = 0; i < kSpectrumSamples; ++i)
        EXPECT_NEAR(a[i], b[i], rel * std::abs(b[i]) + 1e-9) << "wavelength " << kLambda.lambda[i];
}

// pbrt-v4's defaults: sigma_a = RGB(.0011, .0024, .014), sigma_s = RGB(2.55, 3.21, 3.77) (per
// unit length), scale 1, eta 1.33, g 0, roughness 0 with remapping; the scene then takes the
// volumetric kernel although it has no "medium".
TEST(SubsurfaceMaterial, DefaultsArePbrtV4s) {
    Scene s = build(R"(Material "subsurface")");
    const SubsurfaceMaterial& m = only_subsurface(s);
    EXPECT_FLOAT_EQ(m.eta, 1.33f);
    EXPECT_EQ(m.g, 0);
    EXPECT_EQ(m.scale, 1);
    EXPECT_TRUE(m.roughness.remap);
    EXPECT_FLOAT_EQ(m.exit_c, normalized_fresnel_c(1.33f));
    SubsurfaceCoefficients c = coefficients(s);
    expect_near(c.sigma_a, rgb(.0011f, .0024f, .014f), 1e-5);
    expect_near(c.sigma_s, rgb(2.55f, 3.21f, 3.77f), 1e-5);
    EXPECT_TRUE(s.integrator.volumetric);
    EXPECT_TRUE(s.media.empty());
}

// "name": pbrt-v4's measured table (Jensen et al. 2001: sigma_s' and sigma_a of "Skin1" per
// mm, as sRGB), times "scale"; a "g" given with it is ignored with a warning (the table holds
// reduced scattering coefficients, which assume g = 0).
TEST(SubsurfaceMaterial, NamedMediumTimesScale) {
    ::testing::internal::CaptureStderr();
    Scene s = build(
        R"(Material "subsurface" "string name" "Skin1" "float scale" 50 "float eta" 1.5 "float g" 0.5)");
    std::string err = ::testing::internal::GetCapturedStderr();
    EXPECT_NE(err.find("sss.pbrt:2:"), std::string::npos) << err;
    EXPECT_NE(err.find("\"g\""), std::string::npos) << err;
    const SubsurfaceMaterial& m = only_subsurface(s);
    EXPECT_EQ(m.g, 0);
    EXPECT_FLOAT_EQ(m.eta, 1.5f);
    SubsurfaceCoefficients c = coefficients(s);
    expect_near(c.sigma_a, rgb(0.032f, 0.17f, 0.48f) * 50, 1e-5);
    expect_near(c.sigma_s, rgb(0.74f, 0.88f, 1.01f) * 50, 1e-5);
}

// "reflectance" + "mfp" (default 1; both times scale, as pbrt-v4 scales mfp): sigma_t = 1 / mfp
// and the albedo from the inversion, per wavelength.
TEST(SubsurfaceMaterial, ReflectanceAndMeanFreePath) {
    Scene s =
        build(R"(Material "subsurface" "spectrum reflectance" [ 300 0.5 900 0.5 ] "spectrum mfp" [ 300 0.25 900 0.25 ] "float scale" 2)");
    SubsurfaceCoefficients c = coefficients(s);
    // The boundary (eta 1.33, the default) reflects r_i of the diffuse light inside back in:
    // the interior's reflectance A_0 solves 0.5 = A_0 (1 - r_i) / (1 - r_i A_0).
    const Float r_i = only_subsurface(s).internal_r;
    const Float alpha = subsurface_albedo(0.5f / (1 - r_i + r_i * 0.5f));
    for (int i = 0; i < kSpectrumSamples; ++i) {
        EXPECT_NEAR(c.sigma_s[i] + c.sigma_a[i], 2.0, 1e-5);  // 1 / (0.25 * 2)
        EXPECT_NEAR(c.sigma_s[i], 2 * alpha, 1e-5);
    }
    Scene d = build(R"(Material "subsurface" "spectrum reflectance" [ 300 0.5 900 0.5 ])");
    SubsurfaceCoefficients e = coefficients(d);
    EXPECT_NEAR(e.sigma_s[0] + e.sigma_a[0], 1.0, 1e-6);
}

TEST(SubsurfaceMaterial, RoughnessAndEtaReachTheBoundary) {
    Scene s = build(
        R"(Material "subsurface" "float uroughness" 0.1 "float vroughness" 0.2 "bool remaproughness" false "float eta" 1.4)");
    SurfaceHit h;
    h.ng = h.ns = Normal3(0, 0, 1);
    h.dpdu = Vec3(1, 0, 0);
    SampledWavelengths lambda = kLambda;
    std::optional<Bsdf> b = make_bsdf(s.materials.back(), s.material_context(), h, lambda);
    ASSERT_TRUE(b);
    ASSERT_TRUE(std::holds_alternative<DielectricLobe>(b->lobe()));
    const auto& l = std::get<DielectricLobe>(b->lobe());
    EXPECT_FLOAT_EQ(l.eta, 1.4f);
    EXPECT_FLOAT_EQ(l.mf.alpha_x, 0.1f);
    EXPECT_FLOAT_EQ(l.mf.alpha_y, 0.2f);
}

/// Expects build() to throw an sr::Error on line 2 whose message contains `what`, located at
/// the first occurrence of `at` in `material`.
void expect_error(const std::string& material, const std::string& what, const std::string& at) {
    SCOPED_TRACE(material);
    const int column = int(material.find(at)) + 1;
    try {
        build(material);
        ADD_FAILURE() << "no error";
    } catch (const Error& e) {
        EXPECT_NE(e.message().find(what), std::string::npos) << e.message();
        EXPECT_EQ(e.loc().file, "sss.pbrt");
        EXPECT_EQ(e.loc().line, 2);
        EXPECT_EQ(e.loc().column, column) << e.what();
    }
}

// pbrt-v4 stops with an error when only one of sigma_a and sigma_s is given, or the name is
// not in its table; we locate them at the parameter.
TEST(SubsurfaceMaterial, ErrorsAreLocated) {
    expect_error(R"(Material "subsurface" "rgb sigma_a" [ 1 1 1 ])", "without \"sigma_s\"",
                 "\"rgb sigma_a\"");
    expect_error(R"(Material "subsurface" "float scale" 2 "rgb sigma_s" [ 1 1 1 ])",
                 "without \"sigma_a\"", "\"rgb sigma_s\"");
    expect_error(R"(Material "subsurface" "string name" "Skin9")", "\"Skin9\"", "\"string name\"");
    expect_error(R"(Material "subsurface" "float eta" 0)", "\"eta\"", "\"float eta\"");
    expect_error(R"(Material "subsurface" "float g" 1)", "\"g\"", "\"float g\"");
    expect_error(R"(Material "subsurface" "rgb reflectance" [ .5 .5 .5 ] "spectrum mfp" [ 300 0 900 0 ])",
                 "\"mfp\"", "\"spectrum mfp\"");
}

/// pbrt-v4's FresnelMoment1 (a polynomial fit of int_0^1 F_r(mu, eta) mu dmu), as a reference
/// for the quadrature that normalises the exit lobe.
double pbrt_fresnel_moment1(double eta) {
    double e2 = eta * eta, e3 = e2 * eta, e4 = e3 * eta, e5 = e4 * eta;
    if (eta < 1)
        return 0.45966 - 1.73965 * eta + 3.37668 * e2 - 3.904945 * e3 + 2.49277 * e4 - 0.68441 * e5;
    return -4.61686 + 11.1136 * eta - 10.4646 * e2 + 5.11455 * e3 - 1.27198 * e4 + 0.12746 * e5;
}

// The exit lobe integrates to 1: int f |cos| dw over the hemisphere, by a 2D midpoint rule in
// (cos theta, phi), is 1 in Importance mode and eta^2 in Radiance mode; its normalisation
// agrees with pbrt-v4's c = 1 - 2 FresnelMoment1(1 / eta) where that fit is accurate; sampling
// is consistent with pdf() and its weights average to the same integral.
TEST(NormalizedFresnelLobe, IntegratesToOne) {
    for (Float eta : {1.0f, 1.1f, 1.33f, 1.5f, 2.0f, 0.8f}) {
        SCOPED_TRACE(eta);
        NormalizedFresnelLobe l{eta, normalized_fresnel_c(eta)};
        const Vec3 wo = normalize(Vec3(0.3f, -0.2f, 0.9f));
        constexpr int kMu = 2000, kPhi = 8;
        double imp = 0, rad = 0;
        for (int i = 0; i < kMu; ++i)
            for (int j = 0; j < kPhi; ++j) {
                double mu = (i + 0.5) / kMu, phi = 2 * M_PI * (j + 0.5) / kPhi;
                double s = std::sqrt(1 - mu * mu);
                Vec3 wi(Float(s * std::cos(phi)), Float(s * std::sin(phi)), Float(mu));
                double w = mu * (1.0 / kMu) * (2 * M_PI / kPhi);
                imp += l.f(wo, wi, TransportMode::Importance)[0] * w;
                rad += l.f(wo, wi, TransportMode::Radiance)[0] * w;
                EXPECT_EQ(l.f(wo, -wi, TransportMode::Importance)[0], 0);  // reflection only
            }
        EXPECT_NEAR(imp, 1.0, 2e-4);
        EXPECT_NEAR(rad, double(eta) * eta, 2e-4 * eta * eta);
        if (eta >= 1.1f) {
            EXPECT_NEAR(l.c, 1 - 2 * pbrt_fresnel_moment1(1 / eta), 1e-4);
        }
        // Cosine sampling: pdf matches, weight f cos / pdf averages to 1.
        Pcg32 rng(7, 11);
        double sum = 0, sum2 = 0;
        constexpr int kN = 20000;
        for (int k = 0; k < kN; ++k) {
            Point2 u(rng.next_float(), rng.next_float());
            auto bs = l.sample(wo, 0, u, TransportMode::Importance);
            ASSERT_TRUE(bs);
            EXPECT_GT(bs->wi.z, 0);
            EXPECT_NEAR(bs->pdf_sa, l.pdf(wo, bs->wi, TransportMode::Importance), 1e-5);
            double w = bs->f[0] * bs->wi.z / bs->pdf_sa;
            sum += w;
            sum2 += w * w;
        }
        double mean = sum / kN, se = std::sqrt(std::max(0.0, sum2 / kN - mean * mean) / kN);
        EXPECT_NEAR(mean, 1.0, 4.5 * se + 1e-6) << "se " << se;
    }
}

/// van de Hulst's approximation for the diffuse reflectance of a semi-infinite isotropic
/// medium of single-scattering albedo alpha (index-matched), which the inversion's fit
/// inverts: A = (1 - s)(1 - 0.139 s) / (1 + 1.17 s), s = sqrt(1 - alpha).
double van_de_hulst(double alpha) {
    double s = std::sqrt(1 - alpha);
    return (1 - s) * (1 - 0.139 * s) / (1 + 1.17 * s);
}

TEST(SubsurfaceAlbedo, InvertsVanDeHulstMonotonically) {
    EXPECT_EQ(subsurface_albedo(0), 0);
    EXPECT_EQ(subsurface_albedo(1), 1);
    EXPECT_EQ(subsurface_albedo(-0.5f), 0);
    EXPECT_EQ(subsurface_albedo(2), 1);
    EXPECT_EQ(subsurface_albedo(std::nanf("")), 0);
    Float prev = 0;
    for (int i = 1; i <= 1000; ++i) {
        Float a = Float(i) / 1000;
        Float alpha = subsurface_albedo(a);
        EXPECT_GE(alpha, prev) << a;
        EXPECT_LE(alpha, 1);
        prev = alpha;
        if (i < 1000) {
            EXPECT_NEAR(van_de_hulst(alpha), a, 2e-4) << a;
        }
    }
}

// Diffuse light crossing a boundary of relative IOR eta: by reciprocity the fraction the
// boundary passes from inside, 1 - r_i, is the fraction it passes from outside, 1 - r_e,
// over eta^2 (radiance is divided by eta^2 on the way in). r_e is the exit lobe's 1 - c.
TEST(SubsurfaceMaterial, InternalReflectanceObeysReciprocity) {
    for (Float eta : {1.0f, 1.33f, 1.5f, 2.4f}) {
        const Float r_e = 1 - normalized_fresnel_c(eta);
        EXPECT_NEAR(diffuse_internal_reflectance(eta), 1 - (1 - r_e) / (eta * eta), 2e-4)
            << "eta " << eta;
    }
    EXPECT_NEAR(diffuse_internal_reflectance(1.0f), 0, 1e-6);
}

}  // namespace
}  // namespace sr
