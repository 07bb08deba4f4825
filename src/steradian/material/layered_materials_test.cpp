// Wiring of pbrt-v4's "coateddiffuse", "coatedconductor" and "mix": parameter names and
// defaults reach the layered lobes (the conductor's eta and k relative to the coating), mix
// names resolve in any order, and bad parameters are located errors.
#include <gtest/gtest.h>

#include <string>

#include "steradian/material/material.h"
#include "steradian/scene/build.h"
#include "steradian/scene/pbrt/parser.h"

namespace sr {
namespace {

/// Builds a scene from the lines `materials` (starting on line 2) and a sphere that uses the
/// last material.
Scene build(const std::string& materials) {
    return build_scene(
        parse_pbrt_string("WorldBegin\n" + materials + "\nShape \"sphere\"\n", "layered.pbrt"));
}

SurfaceHit test_hit() {
    SurfaceHit h;
    h.ng = h.ns = Normal3(0, 0, 1);
    h.dpdu = Vec3(1, 0, 0);
    h.wo = Vec3(0, 0, 1);
    return h;
}

/// The lobe that material `index` builds at test_hit().
template <typename L>
L lobe_of(const Scene& s, size_t index) {
    SampledWavelengths lambda = SampledWavelengths::sample_uniform(0.3f);
    std::optional<Bsdf> b =
        make_bsdf(s.materials.at(index), s.material_context(), test_hit(), lambda);
    if (b && std::holds_alternative<L>(b->lobe())) return std::get<L>(b->lobe());
    ADD_FAILURE() << "material " << index << " does not build that lobe";
    return L{};
}

/// Expects build() to throw an sr::Error whose message contains `what`, on line `line` at the
/// column of the first occurrence of `at` in that line.
void expect_error(const std::string& materials, const std::string& what, int line,
                  const std::string& at) {
    SCOPED_TRACE(materials);
    size_t start = 0;
    for (int l = 2; l < line; ++l) start = materials.find('\n', start) + 1;
    int column = int(materials.find(at, start) - start) + 1;
    try {
        build(materials);
        ADD_FAILURE() << "no error";
    } catch (const Error& e) {
        EXPECT_NE(e.message().find(what), std::string::npos) << e.message();
        EXPECT_EQ(e.loc().file, "layered.pbrt");
        EXPECT_EQ(e.loc().line, line);
        EXPECT_EQ(e.loc().column, column) << e.what();
    }
}

TEST(LayeredMaterials, CoatedDiffuseDefaultsArePbrtV4s) {
    auto l = lobe_of<CoatedDiffuseLobe>(build(R"(Material "coateddiffuse")"), 0);
    EXPECT_FLOAT_EQ(l.bottom.r[0], 0.5f);
    EXPECT_FLOAT_EQ(l.top.eta, 1.5f);
    EXPECT_TRUE(l.top.mf.effectively_smooth());
    EXPECT_FLOAT_EQ(l.thickness, 0.01f);
    EXPECT_TRUE(l.albedo.is_zero());
    EXPECT_EQ(l.g, 0);
    EXPECT_EQ(l.max_depth, 10);
    EXPECT_EQ(l.n_samples, 1);
}

TEST(LayeredMaterials, CoatedDiffuseParametersReachTheLobe) {
    Scene s = build(R"(Material "coateddiffuse" "spectrum reflectance" [ 300 0.25 900 0.25 ] )"
                    R"("float uroughness" 0.04 "float vroughness" 0.09 "float eta" 1.33 )"
                    R"("float thickness" 0.2 "spectrum albedo" [ 300 0.7 900 0.7 ] "float g" -0.3 )"
                    R"("integer maxdepth" 50 "integer nsamples" 3)");
    auto l = lobe_of<CoatedDiffuseLobe>(s, 0);
    EXPECT_FLOAT_EQ(l.bottom.r[0], 0.25f);
    EXPECT_FLOAT_EQ(l.top.eta, 1.33f);
    EXPECT_FLOAT_EQ(l.top.mf.alpha_x, 0.2f);  // remapped: sqrt(0.04)
    EXPECT_FLOAT_EQ(l.top.mf.alpha_y, 0.3f);
    EXPECT_FLOAT_EQ(l.thickness, 0.2f);
    EXPECT_FLOAT_EQ(l.albedo[2], 0.7f);
    EXPECT_FLOAT_EQ(l.g, -0.3f);
    EXPECT_EQ(l.max_depth, 50);
    EXPECT_EQ(l.n_samples, 3);
    // remaproughness false: roughness is alpha.
    auto r = lobe_of<CoatedDiffuseLobe>(
        build(R"(Material "coateddiffuse" "float roughness" 0.04 "bool remaproughness" false)"), 0);
    EXPECT_FLOAT_EQ(r.top.mf.alpha_x, 0.04f);
    EXPECT_FLOAT_EQ(r.top.mf.alpha_y, 0.04f);
    // g is clamped short of the delta phase functions at +-1.
    auto c = lobe_of<CoatedDiffuseLobe>(build(R"(Material "coateddiffuse" "float g" 1)"), 0);
    EXPECT_LT(c.g, 1);
    EXPECT_GT(c.g, 0.99f);
}

TEST(LayeredMaterials, CoatedConductorParametersReachTheLobe) {
    auto d = lobe_of<CoatedConductorLobe>(build(R"(Material "coatedconductor")"), 0);
    EXPECT_FLOAT_EQ(d.top.eta, 1.5f);
    EXPECT_TRUE(d.top.mf.effectively_smooth());
    EXPECT_TRUE(d.bottom.mf.effectively_smooth());
    EXPECT_FLOAT_EQ(d.thickness, 0.01f);
    EXPECT_GT(d.bottom.k[0], 0);  // copper by default

    Scene s = build(
        R"(Material "coatedconductor" "float interface.roughness" 0.01 "float interface.eta" 2 )"
        R"("spectrum conductor.eta" [ 300 0.5 900 0.5 ] "spectrum conductor.k" [ 300 3 900 3 ] )"
        R"("float conductor.uroughness" 0.16 "float conductor.vroughness" 0.25 )"
        R"("float thickness" 0.1)");
    auto l = lobe_of<CoatedConductorLobe>(s, 0);
    EXPECT_FLOAT_EQ(l.top.eta, 2);
    EXPECT_FLOAT_EQ(l.top.mf.alpha_x, 0.1f);
    EXPECT_FLOAT_EQ(l.top.mf.alpha_y, 0.1f);
    // Relative to the coating: divided by its eta.
    EXPECT_FLOAT_EQ(l.bottom.eta[0], 0.25f);
    EXPECT_FLOAT_EQ(l.bottom.k[0], 1.5f);
    EXPECT_FLOAT_EQ(l.bottom.mf.alpha_x, 0.4f);
    EXPECT_FLOAT_EQ(l.bottom.mf.alpha_y, 0.5f);
    EXPECT_FLOAT_EQ(l.thickness, 0.1f);

    // "reflectance": eta 1 and k for that normal-incidence reflectance, then relative.
    auto r = lobe_of<CoatedConductorLobe>(
        build(R"(Material "coatedconductor" "spectrum reflectance" [ 300 0.64 900 0.64 ])"), 0);
    EXPECT_FLOAT_EQ(r.bottom.eta[0], 1 / 1.5f);
    EXPECT_NEAR(r.bottom.k[0], 2 * 0.8f / 0.6f / 1.5f, 1e-5f);
}

TEST(LayeredMaterials, MixResolvesNamesInAnyOrder) {
    // The mix (material 0) names materials defined after it, one of them another mix.
    Scene s = build(
        "MakeNamedMaterial \"m\" \"string type\" \"mix\" \"string materials\" [ \"a\" \"inner\" ] "
        "\"float amount\" 0.25\n"
        "MakeNamedMaterial \"a\" \"string type\" \"coateddiffuse\"\n"
        "MakeNamedMaterial \"b\" \"string type\" \"conductor\"\n"
        "MakeNamedMaterial \"inner\" \"string type\" \"mix\" \"string materials\" [ \"b\" \"a\" ]\n"
        "NamedMaterial \"m\"");
    const auto& mix = std::get<MixMaterial>(s.materials.at(0));
    EXPECT_TRUE(std::holds_alternative<CoatedDiffuseMaterial>(s.materials.at(mix.materials[0])));
    const auto& inner = std::get<MixMaterial>(s.materials.at(mix.materials[1]));
    EXPECT_TRUE(std::holds_alternative<ConductorMaterial>(s.materials.at(inner.materials[0])));
    EXPECT_TRUE(std::holds_alternative<CoatedDiffuseMaterial>(s.materials.at(inner.materials[1])));
    // Every shading point resolves to a leaf material's lobe.
    SampledWavelengths lambda = SampledWavelengths::sample_uniform(0.3f);
    SurfaceHit h = test_hit();
    int coated = 0;
    for (int k = 0; k < 200; ++k) {
        h.p = Point3(Float(k) * 0.01f, 0, 0);
        std::optional<Bsdf> b = make_bsdf(s.materials[0], s.material_context(), h, lambda);
        ASSERT_TRUE(b);
        EXPECT_TRUE(std::holds_alternative<CoatedDiffuseLobe>(b->lobe()) ||
                    std::holds_alternative<ConductorLobe>(b->lobe()));
        coated += std::holds_alternative<CoatedDiffuseLobe>(b->lobe());
    }
    EXPECT_GT(coated, 0);
    EXPECT_LT(coated, 200);
}

TEST(LayeredMaterials, Errors) {
    expect_error(R"(Material "coateddiffuse" "integer nsamples" 0)",
                 "\"nsamples\" must be in [1, 65535]", 2, "\"integer nsamples\"");
    expect_error(R"(Material "coateddiffuse" "integer maxdepth" -1)",
                 "\"maxdepth\" must be in [0, 65535]", 2, "\"integer maxdepth\"");
    expect_error(R"(Material "coateddiffuse" "float conductor.roughness" 0.1)", "unused", 2,
                 "\"float conductor.roughness\"");
    expect_error(R"(Material "coatedconductor" "float roughness" 0.1)", "unused", 2,
                 "\"float roughness\"");
    expect_error(R"(Material "coatedconductor" "spectrum reflectance" [ 300 0.5 900 0.5 ] )"
                 R"("spectrum conductor.k" [ 300 2 900 2 ])",
                 "either \"reflectance\"", 2, "Material");
    expect_error(R"(Material "mix" "string materials" [ "a" ])", "must name two materials", 2,
                 "\"string materials\"");
    expect_error(R"(Material "mix" "string materials" [ "a" "b" ])",
                 "named material \"a\" is not defined", 2, "\"string materials\"");
    expect_error(
        "MakeNamedMaterial \"x\" \"string type\" \"mix\" \"string materials\" [ \"y\" \"x\" ]\n"
        "MakeNamedMaterial \"y\" \"string type\" \"diffuse\"",
        "contains itself", 2, "MakeNamedMaterial");
}

}  // namespace
}  // namespace sr
