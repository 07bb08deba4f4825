// Scenes with closed-form answers, rendered end to end. Each expected value comes from
// physics (derivations in the comments); each tolerance is a multiple of the standard error
// estimated from the render itself, with fixed seeds (deterministic).
#include <gtest/gtest.h>

#include "support/render_util.h"

namespace sr::test {
namespace {

constexpr double kZ = 4.5;  // tolerance in standard errors (two-sided p ~ 7e-6)

// A spectrally flat "spectrum" parameter of value v over the whole tabulated range.
std::string flat(double v) { return fmt::format("[ 300 {} 900 {} ]", v, v); }

std::string camera_inside_sphere(int res, int spp) {
    return fmt::format(R"(
LookAt 0 0 0  0 0 1  0 1 0
Camera "perspective" "float fov" [ 120 ]
Film "rgb" "integer xresolution" [ {0} ] "integer yresolution" [ {0} ] "string filename" "x.exr"
Sampler "independent" "integer pixelsamples" [ {1} ]
Integrator "path" "integer maxdepth" [ 10000 ]
PixelFilter "box"
WorldBegin
)",
                       res, spp);
}

// Closed Lambertian sphere (radius R = 1, albedo rho = 0.5), isotropic point light of
// intensity I = pi (photometric units) at the centre. Direct irradiance E = I / R^2; the
// sphere's radiance L is uniform, so the indirect irradiance is pi L and
// L = rho (E + pi L) / pi  =>  L = rho I / (pi R^2 (1 - rho)) = 1.
TEST(Analytic, PointLightInClosedSphereGivesUnitRadiance) {
    std::string scene = camera_inside_sphere(32, 64) + fmt::format(R"(
LightSource "point" "spectrum I" {} "float scale" [ 3.14159265358979 ]
Material "diffuse" "spectrum reflectance" {}
Shape "sphere" "float radius" [ 1 ]
)",
                                                                   flat(1), flat(0.5));
    Rendered r = render_string(scene);
    MeanSe m = mean_se(r.y);
    std::printf("mean luminance %.5f +- %.5f (expected 1)\n", m.mean, m.se);
    EXPECT_LT(m.se, 0.01);
    EXPECT_NEAR(m.mean, 1.0, kZ * m.se) << "se " << m.se;
    EXPECT_EQ(r.stats.nonfinite, 0u);
}

// An emitter so bright (1e38 nits, near the float range) that its radiance over the
// wavelength pdfs overflows: every sample is non-finite, so each is counted and dropped, and
// the image holds no NaN or Inf (it is black). At 1e36 the same emitter's samples are all
// finite and the image is its radiance (every channel near 1e36). The emitter is a disk of
// radius 1 mm, which every pixel of the orthographic view sees, so that its total power
// stays within float range; a light whose power (or spectrum) overflows is an error at its
// directive: the last cases.
TEST(Analytic, OverflowingSamplesAreCountedAndNeverReachTheImage) {
    auto scene = [](const char* l, const char* scale, const char* radius) {
        return fmt::format(R"(
LookAt 0 0 5  0 0 0  0 1 0
Camera "orthographic" "float screenwindow" [ -5e-4 5e-4 -5e-4 5e-4 ]
Film "rgb" "integer xresolution" [ 4 ] "integer yresolution" [ 4 ] "string filename" "x.exr"
Sampler "independent" "integer pixelsamples" [ 4 ]
WorldBegin
AreaLightSource "diffuse" "rgb L" [ {0} {0} {0} ] "float scale" [ {1} ]
Shape "disk" "float radius" [ {2} ]
)",
                           l, scale, radius);
    };
    Rendered huge = render_string(scene("1", "1e38", "1e-3"));
    EXPECT_EQ(huge.stats.nonfinite, 4u * 4u * 4u);
    for (float v : huge.rgb.data) EXPECT_TRUE(std::isfinite(v)) << v;
    Rendered big = render_string(scene("1", "1e36", "1e-3"));
    EXPECT_EQ(big.stats.nonfinite, 0u);
    for (float v : big.rgb.data) {
        EXPECT_TRUE(std::isfinite(v));
        EXPECT_GT(v, 1e35f);
        EXPECT_LT(v, 1e37f);
    }
    // pi L A over a disk of radius 10 overflows a float; so does an RGB of 1e38 (its
    // spectrum times the illuminant).
    EXPECT_THROW(render_string(scene("1", "5e37", "10")), Error);
    EXPECT_THROW(render_string(scene("1e38", "1", "1e-3")), Error);
}

// The same sphere, emitting Le = 0.5 inwards (ReverseOrientation), albedo 0.5:
// L = Le + rho L  =>  L = Le / (1 - rho) = 1. The emission is given three ways that
// pbrt-v4 defines to be equal: a flat spectrum with scale 0.5, "rgb L" [0.5 0.5 0.5]
// (an RGB illuminant's magnitude multiplies), and "rgb L" [1 1 1] with scale 0.5.
class EmittingSphere : public ::testing::TestWithParam<const char*> {};
TEST_P(EmittingSphere, GivesLeOverOneMinusRho) {
    std::string scene = camera_inside_sphere(32, 64) + fmt::format(R"(
AttributeBegin
  ReverseOrientation
  AreaLightSource "diffuse" {}
  Material "diffuse" "spectrum reflectance" {}
  Shape "sphere" "float radius" [ 1 ]
AttributeEnd
)",
                                                                   GetParam(), flat(0.5));
    Rendered r = render_string(scene);
    MeanSe m = mean_se(r.y);
    std::printf("mean luminance %.5f +- %.5f (expected 1)\n", m.mean, m.se);
    EXPECT_LT(m.se, 0.01);
    EXPECT_NEAR(m.mean, 1.0, kZ * m.se) << "se " << m.se;
}
INSTANTIATE_TEST_SUITE_P(
    Analytic, EmittingSphere,
    ::testing::Values("\"spectrum L\" [ 300 1 900 1 ] \"float scale\" [ 0.5 ]",
                      "\"rgb L\" [ 0.5 0.5 0.5 ]",
                      "\"rgb L\" [ 1 1 1 ] \"float scale\" [ 0.5 ]",
                      "\"blackbody L\" [ 3000 ] \"float scale\" [ 0.5 ]"));

// Direct illumination of a Lambertian plane (albedo rho = 0.5, maxdepth 1, nothing else in
// the scene) at the foot of each light type, with pbrt-v4's photometric parameters:
// reflected luminance L = rho E / pi with the illuminance E from the inverse-square and
// cosine laws. An orthographic camera below the light looks at a 2 cm patch at the foot.
struct DirectCase {
    const char* name;
    const char* light;
    double illuminance;  // lux at the foot, from the light's definition
};
class DirectIllumination : public ::testing::TestWithParam<DirectCase> {};
TEST_P(DirectIllumination, MatchesInverseSquareAndCosineLaws) {
    const DirectCase& c = GetParam();
    std::string scene = fmt::format(R"(
LookAt 0 1 0  0 0 0  0 0 1
Camera "orthographic" "float screenwindow" [ -0.01 0.01 -0.01 0.01 ]
Film "rgb" "integer xresolution" [ 8 ] "integer yresolution" [ 8 ] "string filename" "x.exr"
Sampler "independent" "integer pixelsamples" [ 64 ]
Integrator "path" "integer maxdepth" [ 1 ]
PixelFilter "box"
WorldBegin
{}
Material "diffuse" "spectrum reflectance" {}
Shape "bilinearmesh" "point3 P" [ -50 0 -50  50 0 -50  -50 0 50  50 0 50 ]
)",
                                    c.light, flat(0.5));
    Rendered r = render_string(scene);
    MeanSe m = mean_se(r.y);
    double expected = 0.5 * c.illuminance / kPi;
    std::printf("%s: %.5f +- %.5f (expected %.5f)\n", c.name, m.mean, m.se, expected);
    EXPECT_NEAR(m.mean, expected, std::max(kZ * m.se, 2e-5 * expected));
    EXPECT_LT(m.se, 0.01 * expected);
}
constexpr double kPiD = 3.14159265358979323846;
INSTANTIATE_TEST_SUITE_P(
    Analytic, DirectIllumination,
    ::testing::Values(
        // I = 100 cd at 2 m: E = I / d^2 = 25 lx.
        DirectCase{"point scale", "LightSource \"point\" \"point3 from\" [ 0 2 0 ] \"float scale\" [ 100 ]", 25},
        // power 1000 lm, isotropic: I = 1000 / (4 pi) cd; E = I / 4.
        DirectCase{"point power", "LightSource \"point\" \"point3 from\" [ 0 2 0 ] \"float power\" [ 1000 ]", 1000 / (4 * kPiD) / 4},
        DirectCase{"point rgb", "LightSource \"point\" \"point3 from\" [ 0 2 0 ] \"rgb I\" [ 30 30 30 ]", 30.0 / 4},
        // spot power 500 lm, cone 30 deg, delta 5 deg:
        // I = 500 / (2 pi ((1 - cos 25) + (cos 25 - cos 30) / 2)) on the axis.
        DirectCase{"spot power",
                   "LightSource \"spot\" \"point3 from\" [ 0 2 0 ] \"point3 to\" [ 0 0 0 ] \"float power\" [ 500 ]",
                   500 / (2 * kPiD * ((1 - std::cos(25 * kPiD / 180)) +
                                      (std::cos(25 * kPiD / 180) - std::cos(30 * kPiD / 180)) / 2)) / 4},
        // distant light with "illuminance" 1000 lx arriving along the normal.
        DirectCase{"distant", "LightSource \"distant\" \"point3 from\" [ 0 1 0 ] \"point3 to\" [ 0 0 0 ] \"float illuminance\" [ 1000 ]", 1000},
        // uniform sky with "illuminance" 200 lx on an upward-facing plane.
        DirectCase{"infinite", "LightSource \"infinite\" \"float illuminance\" [ 200 ]", 200},
        // emitting sphere of luminance 1000 cd/m^2, radius 0.5, centre 2 m above the foot:
        // E = pi L (r / d)^2 (a sphere subtending a cone of half-angle asin(r/d)).
        DirectCase{"sphere area", "AttributeBegin AreaLightSource \"diffuse\" \"float scale\" [ 1000 ] Translate 0 2 0 Shape \"sphere\" \"float radius\" [ 0.5 ] AttributeEnd", kPiD * 1000 * 0.0625 / 1}),
    [](const auto& param_info) {
        std::string n = param_info.param.name;
        for (auto& ch : n)
            if (ch == ' ') ch = '_';
        return n;
    });

// With the default orientation the emission faces outwards, away from the camera inside:
// only the interreflection of nothing remains, so the image is black.
TEST(Analytic, OneSidedEmitterFacingAwayIsBlack) {
    std::string scene = camera_inside_sphere(8, 4) + fmt::format(R"(
AreaLightSource "diffuse" "spectrum L" {}
Material "diffuse" "spectrum reflectance" {}
Shape "sphere" "float radius" [ 1 ]
)",
                                                                 flat(1), flat(0.5));
    Rendered r = render_string(scene);
    for (double y : r.y) ASSERT_EQ(y, 0.0);
}

// White furnace: a sphere of albedo 1 under a uniform infinite light of radiance 1 (nit).
// Every path eventually escapes carrying weight 1, so every pixel is exactly... in
// expectation 1, object or background.
TEST(Analytic, WhiteFurnaceReturnsTheLightsRadiance) {
    std::string scene = fmt::format(R"(
LookAt 0 0 -4  0 0 0  0 1 0
Camera "perspective" "float fov" [ 40 ]
Film "rgb" "integer xresolution" [ 32 ] "integer yresolution" [ 32 ] "string filename" "x.exr"
Sampler "independent" "integer pixelsamples" [ 64 ]
Integrator "path" "integer maxdepth" [ 10000 ]
PixelFilter "box"
WorldBegin
LightSource "infinite" "spectrum L" {}
Material "diffuse" "spectrum reflectance" {}
Shape "sphere" "float radius" [ 1 ]
)",
                                    flat(1), flat(1));
    Rendered r = render_string(scene);
    MeanSe m = mean_se(r.y);
    EXPECT_NEAR(m.mean, 1.0, std::max(kZ * m.se, 1e-4)) << "se " << m.se;
    // The object region alone (centre of the image) as well.
    MeanSe c = mean_se(region(r, 12, 12, 20, 20));
    EXPECT_NEAR(c.mean, 1.0, std::max(kZ * c.se, 1e-4)) << "se " << c.se;
}

// BSDF sampling alone, light sampling alone and their MIS combination are three unbiased
// estimators of the same integral: their region means must agree within noise.
TEST(Analytic, BsdfOnlyLightOnlyAndMisAgree) {
    auto scene = [](const char* strategy) {
        return fmt::format(R"(
LookAt 0 3 -6  0 0.5 0  0 1 0
Camera "perspective" "float fov" [ 45 ]
Film "rgb" "integer xresolution" [ 48 ] "integer yresolution" [ 32 ] "string filename" "x.exr"
Sampler "independent" "integer pixelsamples" [ 256 ] "integer seed" [ 7 ]
Integrator "path" "integer maxdepth" [ 5 ] "string strategy" "{}"
PixelFilter "box"
WorldBegin
AttributeBegin
  AreaLightSource "diffuse" "rgb L" [ 4 4 4 ]
  Translate 0 3 0
  Rotate 90 1 0 0
  Shape "disk" "float radius" [ 1 ]
AttributeEnd
Material "diffuse" "rgb reflectance" [ 0.6 0.5 0.4 ]
Shape "bilinearmesh" "point3 P" [ -5 0 -5  5 0 -5  -5 0 5  5 0 5 ]
Material "diffuse" "rgb reflectance" [ 0.3 0.6 0.3 ]
Translate 0 0.75 0
Shape "sphere" "float radius" [ 0.75 ]
)",
                           strategy);
    };
    Rendered mis = render_string(scene("mis"));
    Rendered bsdf = render_string(scene("bsdf"));
    Rendered light = render_string(scene("light"));
    for (int by = 0; by < 2; ++by)
        for (int bx = 0; bx < 3; ++bx) {
            int x0 = bx * 16, y0 = by * 16;
            MeanSe a = mean_se(region(mis, x0, y0, x0 + 16, y0 + 16));
            MeanSe b = mean_se(region(bsdf, x0, y0, x0 + 16, y0 + 16));
            MeanSe c = mean_se(region(light, x0, y0, x0 + 16, y0 + 16));
            double sab = std::sqrt(a.se * a.se + b.se * b.se);
            double sac = std::sqrt(a.se * a.se + c.se * c.se);
            EXPECT_NEAR(a.mean, b.mean, kZ * sab) << "block " << bx << "," << by;
            EXPECT_NEAR(a.mean, c.mean, kZ * sac) << "block " << bx << "," << by;
            EXPECT_GT(a.mean, 0.0);
            std::printf("block %d,%d: mis %.4f+-%.4f bsdf %.4f+-%.4f light %.4f+-%.4f\n", bx, by,
                        a.mean, a.se, b.mean, b.se, c.mean, c.se);
        }
}

// Same scene, seed and sample count on 1 and 2 threads: bit-identical images.
TEST(Analytic, ImageDoesNotDependOnThreadCount) {
    std::string scene = camera_inside_sphere(24, 8) + fmt::format(R"(
LightSource "point" "spectrum I" {} "float scale" [ 3.14159265358979 ]
Material "diffuse" "spectrum reflectance" {}
Shape "sphere" "float radius" [ 1 ]
)",
                                                                  flat(1), flat(0.5));
    const std::string old_line = "Sampler \"independent\" \"integer pixelsamples\" [ 8 ]";
    for (const char* line :
         {"Sampler \"independent\" \"integer pixelsamples\" [ 8 ]",
          "Sampler \"zsobol\" \"integer pixelsamples\" [ 8 ]",
          "Sampler \"sobol\" \"integer pixelsamples\" [ 8 ]",
          "Sampler \"stratified\" \"integer xsamples\" [ 2 ] \"integer ysamples\" [ 3 ]"}) {
        std::string s = scene;
        size_t at = s.find(old_line);
        ASSERT_NE(at, std::string::npos);
        s.replace(at, old_line.size(), line);
        Rendered a = render_string(s, 1);
        Rendered b = render_string(s, 2);
        ASSERT_EQ(a.rgb.data.size(), b.rgb.data.size());
        for (size_t i = 0; i < a.rgb.data.size(); ++i)
            ASSERT_EQ(a.rgb.data[i], b.rgb.data[i]) << line << " at " << i;
    }
}

}  // namespace
}  // namespace sr::test

namespace sr::test {
namespace {

// White furnace per material: a sphere of a lossless material under a uniform environment
// of radiance 1 is invisible (every path escapes with throughput 1 in expectation): the
// smooth dielectric (Fresnel R + T = 1, total internal reflection inside), the thin
// dielectric, a diffuse transmitter with r + t = 1, and a mirror conductor of reflectance 1.
// (Rough microfacet lobes lose energy to single scattering and are bounded by <= 1 in the
// stat suite instead.)
class MaterialFurnace : public ::testing::TestWithParam<const char*> {};
TEST_P(MaterialFurnace, LosslessMaterialIsInvisibleInAWhiteFurnace) {
    std::string scene = furnace_scene(GetParam(), 64, 1000);
    Rendered r = render_string(scene);
    MeanSe m = mean_se(region(r, 4, 4, 12, 12));  // the sphere covers the centre
    std::printf("%s: %.5f +- %.5f (expected 1)\n", GetParam(), m.mean, m.se);
    EXPECT_NEAR(m.mean, 1.0, std::max(4.5 * m.se, 2e-3));
    EXPECT_LT(m.se, 0.02);
}
INSTANTIATE_TEST_SUITE_P(
    Analytic, MaterialFurnace,
    ::testing::Values("Material \"dielectric\" \"float eta\" [ 1.5 ]",
                      "Material \"dielectric\" \"spectrum eta\" \"glass-BK7\"",
                      "Material \"thindielectric\" \"float eta\" [ 1.5 ]",
                      "Material \"diffusetransmission\" \"spectrum reflectance\" [ 300 0.3 900 0.3 ] "
                      "\"spectrum transmittance\" [ 300 0.7 900 0.7 ]",
                      "Material \"conductor\" \"spectrum reflectance\" [ 300 1 900 1 ] "
                      "\"float roughness\" [ 0 ]",
                      // Layered: a white base under a smooth coating, no absorbing slab (or a
                      // purely scattering one), walks long enough to end: lossless. Their f and
                      // pdf are estimates, so next-event estimation adds noise (nsamples 4
                      // halves it); BSDF sampling alone gives exactly 1 per path.
                      "Material \"coateddiffuse\" \"spectrum reflectance\" [ 300 1 900 1 ] "
                      "\"float thickness\" [ 0 ] \"integer maxdepth\" [ 1000 ]",
                      "Material \"coateddiffuse\" \"spectrum reflectance\" [ 300 1 900 1 ] "
                      "\"spectrum albedo\" [ 300 1 900 1 ] \"float thickness\" [ 0.5 ] "
                      "\"float g\" [ 0.5 ] \"integer maxdepth\" [ 1000 ] "
                      "\"integer nsamples\" [ 4 ]",
                      // Reflectance 1 is clamped to 0.9999 (k = 200 relative to air): a loss
                      // of about 1e-4 per bounce on the metal, far below the tolerance.
                      "Material \"coatedconductor\" \"spectrum reflectance\" [ 300 1 900 1 ] "
                      "\"float thickness\" [ 0 ] \"integer maxdepth\" [ 1000 ]",
                      // mix of two lossless materials is lossless whatever it picks.
                      "MakeNamedMaterial \"glass\" \"string type\" \"dielectric\" "
                      "\"float eta\" [ 1.5 ]\n"
                      "MakeNamedMaterial \"coat\" \"string type\" \"coateddiffuse\" "
                      "\"spectrum reflectance\" [ 300 1 900 1 ] \"float thickness\" [ 0 ] "
                      "\"integer maxdepth\" [ 1000 ]\n"
                      "Material \"mix\" \"string materials\" [ \"glass\" \"coat\" ] "
                      "\"float amount\" [ 0.3 ]"));

// A convex sphere under a uniform environment of radiance 1 sees only the environment, so its
// radiance towards the camera is its directional albedo. A "mix" of two Lambertian materials
// chooses reflectance r1 with probability "amount" and r0 otherwise: the object's mean
// radiance is (1 - amount) r0 + amount r1.
TEST(Analytic, MixMaterialAveragesAlbedosByAmount) {
    const double r0 = 0.2, r1 = 0.8, amount = 0.3;
    std::string scene = furnace_scene(
        fmt::format("MakeNamedMaterial \"a\" \"string type\" \"diffuse\" \"spectrum reflectance\" {}\n"
                    "MakeNamedMaterial \"b\" \"string type\" \"diffuse\" \"spectrum reflectance\" {}\n"
                    "Material \"mix\" \"string materials\" [ \"a\" \"b\" ] \"float amount\" [ {} ]",
                    flat(r0), flat(r1), amount),
        256, 5);
    Rendered r = render_string(scene);
    MeanSe m = mean_se(region(r, 4, 4, 12, 12));
    double expected = (1 - amount) * r0 + amount * r1;
    std::printf("mix: %.5f +- %.5f (expected %.5f)\n", m.mean, m.se, expected);
    EXPECT_NEAR(m.mean, expected, kZ * m.se);
}

}  // namespace
}  // namespace sr::test
