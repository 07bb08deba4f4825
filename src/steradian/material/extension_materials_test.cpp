// Wiring of steradian's extension materials "phong", "modifiedphong", "lafortune" and "ward":
// parameters and defaults reach the lobes, Kd + Ks > 1 is scaled with a located warning (and
// normalised per lookup for textures), bad or unknown parameters are located errors, a
// Lafortune set that creates energy is warned about, and Ward's alpha_x follows dpdu.
#include <gtest/gtest.h>

#include <string>

#include "steradian/material/material.h"
#include "steradian/scene/build.h"
#include "steradian/scene/pbrt/parser.h"

namespace sr {
namespace {

/// Builds a scene whose line 2 is `material`, followed by a sphere that uses it.
Scene build(const std::string& material) {
    return build_scene(
        parse_pbrt_string("WorldBegin\n" + material + "\nShape \"sphere\"\n", "ext.pbrt"));
}

template <typename M>
const M& only(const Scene& s) {
    const M* found = nullptr;
    for (const Material& m : s.materials)
        if (const M* p = std::get_if<M>(&m)) found = p;
    EXPECT_NE(found, nullptr);
    return *found;
}

/// The lobe of material M at a hit with shading normal z and dpdu along `dpdu`.
template <typename L>
L lobe_at(const Scene& s, Vec3 dpdu = Vec3(1, 0, 0)) {
    SurfaceHit h;
    h.ng = h.ns = Normal3(0, 0, 1);
    h.dpdu = dpdu;
    SampledWavelengths lambda = SampledWavelengths::sample_uniform(0.3f);
    for (const Material& m : s.materials) {
        std::optional<Bsdf> b = make_bsdf(m, s.material_context(), h, lambda);
        if (b && std::holds_alternative<L>(b->lobe())) return std::get<L>(b->lobe());
    }
    ADD_FAILURE() << "no such lobe";
    return L{};
}

/// Expects build() to throw an sr::Error on line 2 whose message contains `what`, located at
/// the first occurrence of `at` in `material`.
void expect_error(const std::string& material, const std::string& what, const std::string& at) {
    SCOPED_TRACE(material);
    int column = int(material.find(at)) + 1;
    try {
        build(material);
        ADD_FAILURE() << "no error";
    } catch (const Error& e) {
        EXPECT_NE(e.message().find(what), std::string::npos) << e.message();
        EXPECT_EQ(e.loc().file, "ext.pbrt");
        EXPECT_EQ(e.loc().line, 2);
        EXPECT_EQ(e.loc().column, column) << e.what();
    }
}

TEST(ExtensionMaterials, PhongParametersReachTheLobe) {
    ::testing::internal::CaptureStderr();
    Scene s =
        build(R"(Material "phong" "float Kd" 0.25 "rgb Ks" [ 0.5 0.5 0.5 ] "float exponent" 42)");
    EXPECT_EQ(::testing::internal::GetCapturedStderr(), "");
    auto lobe = lobe_at<PhongLobe>(s);
    EXPECT_EQ(lobe.exponent, 42);
    EXPECT_FALSE(lobe.absorb);
    for (int i = 0; i < kSpectrumSamples; ++i) {
        EXPECT_FLOAT_EQ(lobe.kd[i], 0.25f);
        EXPECT_NEAR(lobe.ks[i], 0.5f, 0.02f);  // RGB uplift of a grey: flat to within 2 %
    }
}

TEST(ExtensionMaterials, PhongDefaults) {
    auto p = lobe_at<PhongLobe>(build(R"(Material "phong")"));
    EXPECT_FLOAT_EQ(p.kd[0], 0.5f);
    EXPECT_FLOAT_EQ(p.ks[0], 0.25f);
    EXPECT_EQ(p.exponent, 20);
    auto m = lobe_at<PhongLobe>(build(R"(Material "modifiedphong" "float exponent" 7)"));
    EXPECT_TRUE(m.absorb);
    EXPECT_EQ(m.exponent, 7);
}

TEST(ExtensionMaterials, KdPlusKsAboveOneIsScaledWithALocatedWarning) {
    ::testing::internal::CaptureStderr();
    Scene s = build(R"(Material "phong" "float Kd" 0.7 "float Ks" 0.6)");
    std::string err = ::testing::internal::GetCapturedStderr();
    EXPECT_NE(err.find("warning: ext.pbrt:2:1: Material \"phong\": Kd + Ks reaches 1.3 > 1"),
              std::string::npos)
        << err;
    auto lobe = lobe_at<PhongLobe>(s);
    for (int i = 0; i < kSpectrumSamples; ++i) {
        EXPECT_NEAR(lobe.kd[i], 0.7 / 1.3, 1e-6);
        EXPECT_NEAR(lobe.ks[i], 0.6 / 1.3, 1e-6);
    }
    ::testing::internal::CaptureStderr();
    Scene w = build(R"(Material "ward" "float Kd" 0.9 "float Ks" 0.2)");
    err = ::testing::internal::GetCapturedStderr();
    EXPECT_NE(err.find("ext.pbrt:2:1: Material \"ward\": Kd + Ks reaches 1.1 > 1"),
              std::string::npos)
        << err;
    auto ward = lobe_at<WardLobe>(w);
    EXPECT_NEAR(ward.rho_d[0] + ward.rho_s[0], 1, 1e-6);
}

// Textures are not known at build time: the per-lookup normalisation divides by the sum where
// it exceeds 1.
TEST(ExtensionMaterials, TexturedKdPlusKsIsNormalisedPerLookup) {
    std::vector<SpectrumTexture> st = {ConstantSpectrumTexture{ConstantSpectrum{0.9f}},
                                       ConstantSpectrumTexture{ConstantSpectrum{0.6f}}};
    std::vector<FloatTexture> ft = {ConstantFloatTexture{10}, ConstantFloatTexture{0.2f}};
    MaterialContext ctx{&st, &ft};
    SurfaceHit h;
    h.ng = h.ns = Normal3(0, 0, 1);
    h.dpdu = Vec3(1, 0, 0);
    SampledWavelengths lambda = SampledWavelengths::sample_uniform(0.5f);
    PhongMaterial pm{{}, 0, 1, 0, 1, false};
    auto p = std::get<PhongLobe>(make_bsdf(pm, ctx, h, lambda)->lobe());
    EXPECT_NEAR(p.kd[0], 0.6, 1e-6);
    EXPECT_NEAR(p.ks[0], 0.4, 1e-6);
    WardMaterial wm{{}, 0, 1, 1, 1, 1};
    auto w = std::get<WardLobe>(make_bsdf(wm, ctx, h, lambda)->lobe());
    EXPECT_NEAR(w.rho_d[0] + w.rho_s[0], 1, 1e-6);
    EXPECT_FLOAT_EQ(w.alpha_x, 0.2f);
}

TEST(ExtensionMaterials, BadParametersAreLocatedErrors) {
    const std::string laf = R"(Material "lafortune" )";
    expect_error(R"(Material "phong" "float exponnt" 3)", "unused parameter \"float exponnt\"",
                 "\"float exponnt\"");
    expect_error(R"(Material "phong" "float Kd" 1.5)", "reflectance", "\"float Kd\"");
    expect_error(R"(Material "phong" "float exponent" -1)", "non-negative", "\"float exponent\"");
    expect_error(R"(Material "modifiedphong" "string Ks" "x")", "Ks", "\"string Ks\"");
    expect_error(R"(Material "ward" "float alpha_x" 0)", "positive", "\"float alpha_x\"");
    expect_error(R"(Material "ward" "float alpha_y" -0.1)", "positive", "\"float alpha_y\"");
    expect_error(R"(Material "ward" "float roughness" 0.1)", "unused parameter",
                 "\"float roughness\"");
    expect_error(laf + R"("float Cx" [-1 -1] "float Cy" [-1] "float Cz" [1 1] "float n" [3 4])",
                 "\"Cy\" has 1 values", "\"float Cy\"");
    expect_error(laf + R"("float Cx" [-1] "float Cy" [-1] "float Cz" [1] "float rhos" [1])",
                 "\"n\" has 0 values", "\"float Cx\"");
    expect_error(
        laf + R"("float Cx" [-1] "float Cy" [-1] "float Cz" [1] "float n" [3] "float rhos" [1 2])",
        "\"rhos\" has 2 values", "\"float rhos\"");
    expect_error(laf + R"("float Cx" [1 1 1 1] "float Cy" [1 1 1 1] "float Cz" [1 1 1 1] )"
                       R"("float n" [1 1 1 1])",
                 "at most 3 lobes", "\"float Cx\"");
    expect_error(laf + R"("float Cx" [-1] "float Cy" [-1] "float Cz" [1] "float n" [-2])", ">= 0",
                 "\"float n\"");
    expect_error(laf + R"("float Cx" [-2] "float Cy" [-1] "float Cz" [1] "float n" [200])",
                 "overflows", "\"float n\"");
}

TEST(ExtensionMaterials, LafortuneLobesReachTheLobe) {
    ::testing::internal::CaptureStderr();
    Scene s = build(R"(Material "lafortune" "rgb diffuse" [0.2 0.2 0.2] "float Cx" [-1 0.6] )"
                    R"("float Cy" [-0.8 0.6] "float Cz" [1 0.7] "float n" [12 3] )"
                    R"("float rhos" [0.9 0.1])");
    EXPECT_EQ(::testing::internal::GetCapturedStderr(), "");
    auto l = lobe_at<LafortuneLobe>(s);
    ASSERT_EQ(l.count, 2);
    EXPECT_FLOAT_EQ(l.lobes[0].cx, -1);
    EXPECT_FLOAT_EQ(l.lobes[0].cy, -0.8f);
    EXPECT_FLOAT_EQ(l.lobes[0].cz, 1);
    EXPECT_FLOAT_EQ(l.lobes[0].n, 12);
    EXPECT_FLOAT_EQ(l.lobes[0].rho, 0.9f);
    EXPECT_FLOAT_EQ(l.lobes[1].cx, 0.6f);
    EXPECT_FLOAT_EQ(l.lobes[1].rho, 0.1f);
    EXPECT_NEAR(l.rho_d[0], 0.2, 0.01);
    // Without lobes it is Lambertian with the default diffuse 0.5; rhos defaults to 1.
    auto d = lobe_at<LafortuneLobe>(build(R"(Material "lafortune")"));
    EXPECT_EQ(d.count, 0);
    EXPECT_FLOAT_EQ(d.rho_d[0], 0.5f);
    ::testing::internal::CaptureStderr();
    auto one = lobe_at<LafortuneLobe>(build(
        R"(Material "lafortune" "float Cx" [0] "float Cy" [0] "float Cz" [0.1] "float n" [1])"));
    EXPECT_EQ(::testing::internal::GetCapturedStderr(), "");
    EXPECT_FLOAT_EQ(one.lobes[0].rho, 1);
}

TEST(ExtensionMaterials, LafortuneThatCreatesEnergyIsWarnedAbout) {
    ::testing::internal::CaptureStderr();
    build(R"(Material "lafortune" "float diffuse" 0 "float Cx" [-1.6] "float Cy" [-1.6] )"
          R"("float Cz" [1] "float n" [6] "float rhos" [1.27])");
    std::string err = ::testing::internal::GetCapturedStderr();
    EXPECT_NE(err.find("ext.pbrt:2:1: Material \"lafortune\": not energy conserving"),
              std::string::npos)
        << err;
}

// alpha_x is the roughness along dpdu: with dpdu along world y, the highlight at normal
// incidence is wider towards world y than towards world x.
TEST(ExtensionMaterials, WardAlphaXFollowsDpdu) {
    Scene s = build(
        R"(Material "ward" "float Kd" 0 "float Ks" 1 "float alpha_x" 0.4 "float alpha_y" 0.1)");
    auto l = lobe_at<WardLobe>(s);
    EXPECT_FLOAT_EQ(l.alpha_x, 0.4f);
    EXPECT_FLOAT_EQ(l.alpha_y, 0.1f);
    SurfaceHit h;
    h.ng = h.ns = Normal3(0, 0, 1);
    h.dpdu = Vec3(0, 2, 0);
    SampledWavelengths lambda = SampledWavelengths::sample_uniform(0.3f);
    std::optional<Bsdf> b = make_bsdf(only<WardMaterial>(s), s.material_context(), h, lambda);
    ASSERT_TRUE(b);
    Vec3 wo(0, 0, 1);
    Float sn = std::sin(Float(0.1)), cs = std::cos(Float(0.1));
    // h = wo + wi has the tilt sn / (1 + cs) along the axis of the offset: the ratio of the
    // two values is exp(t2 / alpha_y^2 - t2 / alpha_x^2) with t2 = (sn / (1 + cs))^2.
    double t2 = std::pow(sn / (1 + cs), 2);
    double ratio = b->f(wo, Vec3(0, sn, cs))[0] / b->f(wo, Vec3(sn, 0, cs))[0];
    EXPECT_NEAR(std::log(ratio), t2 / (0.1 * 0.1) - t2 / (0.4 * 0.4), 1e-4);
    // alpha_y defaults to alpha_x.
    auto iso = lobe_at<WardLobe>(build(R"(Material "ward" "float alpha_x" 0.3)"));
    EXPECT_FLOAT_EQ(iso.alpha_y, 0.3f);
}

}  // namespace
}  // namespace sr
