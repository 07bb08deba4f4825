// pbrt-v4's "subsurface" material, rendered by a random walk (integrators/path/volpath.cpp),
// through the whole pipeline against closed forms: energy conservation of a non-absorbing
// interior in a white furnace, Beer-Lambert through an absorbing one, the diffuse reflectance
// of a semi-infinite medium whose albedo was inverted from it (van de Hulst), and a smoke
// render of pbrt-v4's sssdragon and head materials on a sphere.
#include <fmt/format.h>
#include <gtest/gtest.h>

#include <cmath>

#include "support/render_util.h"

namespace sr::test {
namespace {

constexpr double kZ = 4.5;  // tolerance in standard errors

std::string flat(double v) { return fmt::format("[ 300 {} 900 {} ]", v, v); }

// sigma_a = 0: every walk leaves the sphere again (nothing absorbs), the boundary's Fresnel
// split is exact (reflection R with weight 1, refraction T with 1 / eta^2) and the exit lobe
// carries eta^2 and integrates to 1, so under a uniform environment of radiance 1 every pixel
// is 1, whatever eta and g. Integrator "path" (furnace_scene) takes the volumetric kernel.
TEST(Subsurface, NonAbsorbingSphereInAWhiteFurnaceConservesEnergy) {
    for (auto [eta, g] : {std::pair{1.0, 0.0}, std::pair{1.5, 0.7}, std::pair{1.33, -0.3}}) {
        SCOPED_TRACE(fmt::format("eta {} g {}", eta, g));
        Rendered r = render_string(furnace_scene(
            fmt::format(R"(Material "subsurface" "spectrum sigma_a" {} "spectrum sigma_s" {}
  "float eta" [ {} ] "float g" [ {} ])",
                        flat(0), flat(4), eta, g),
            256, 5));
        MeanSe c = mean_se(region(r, 5, 5, 11, 11));
        EXPECT_NEAR(c.mean, 1.0, std::max(kZ * c.se, 1e-4)) << "se " << c.se;
        EXPECT_LT(c.se, 0.005);
        EXPECT_EQ(r.stats.nonfinite, 0u);
    }
}

/// An orthographic camera looking down -z at [-1, 1]^2, 16 x 16 pixels, box filter, under a
/// uniform environment of radiance 1.
std::string ortho_header(int spp, const std::string& integrator, int seed = 0) {
    return fmt::format(R"(
LookAt 0 0 5  0 0 0  0 1 0
Camera "orthographic" "float screenwindow" [ -1 1 -1 1 ]
Film "rgb" "integer xresolution" [ 16 ] "integer yresolution" [ 16 ] "string filename" "x.exr"
Sampler "independent" "integer pixelsamples" [ {} ] "integer seed" [ {} ]
Integrator "{}" "integer maxdepth" [ 5 ]
PixelFilter "box"
WorldBegin
LightSource "infinite" "spectrum L" [ 300 1 900 1 ]
)",
                       spp, seed, integrator);
}

// The same slab with eta = 2.5 (F0 = ((eta - 1) / (eta + 1))^2 = 0.184 at normal incidence):
// the camera ray is reflected with F0 (and sees the environment) or refracted straight in;
// inside, each crossing survives with e = exp(-sigma_a d), and each face reached reflects the
// walk back with F0 or lets it out (into the environment, whatever the exit direction). The
// pixel sees F0 + (1 - F0)^2 e (1 + F0 e + (F0 e)^2 + ...) = F0 + (1 - F0)^2 e / (1 - F0 e)
// (without the internal reflections it would be F0 + (1 - F0) e, 6 % more here).
TEST(Subsurface, InternalReflectionsOfAnAbsorbingSlab) {
    const double sigma_a = 0.5, d = 1.0, eta = 2.5;
    std::string scene = ortho_header(64, "volpath") + fmt::format(R"(
Material "subsurface" "spectrum sigma_a" {2} "spectrum sigma_s" {3} "float eta" [ {4} ]
Shape "trianglemesh" "point3 P" [ -3 -3 {0}  3 -3 {0}  3 3 {0}  -3 3 {0}
    -3 -3 {1}  3 -3 {1}  3 3 {1}  -3 3 {1} ]
  "integer indices" [ 0 2 1  0 3 2  4 5 6  4 6 7  0 1 5  0 5 4  1 2 6  1 6 5  2 3 7  2 7 6  3 0 4  3 4 7 ]
)",
                                                              -d / 2, d / 2, flat(sigma_a),
                                                              flat(0), eta);
    Rendered r = render_string(scene);
    MeanSe m = mean_se(r.y);
    const double f0 = std::pow((eta - 1) / (eta + 1), 2), e = std::exp(-sigma_a * d);
    const double expected = f0 + (1 - f0) * (1 - f0) * e / (1 - f0 * e);
    EXPECT_NEAR(m.mean, expected, kZ * m.se) << "se " << m.se;
    EXPECT_LT(kZ * m.se, 0.5 * (f0 + (1 - f0) * e - expected));  // tells the two apart
    EXPECT_EQ(r.stats.nonfinite, 0u);
}

// A purely absorbing, index-matched (eta = 1) subsurface slab of thickness d seen head-on
// under a uniform environment of radiance 1: the boundary passes the camera ray straight in,
// the walk reaches the back face with probability exp(-sigma_a d) (Beer-Lambert: the
// path-local medium's transmittance), and there leaves with the exit lobe (Lambertian at
// eta = 1), which sees the environment: every pixel is exp(-sigma_a d).
TEST(Subsurface, BeerLambertThroughAnAbsorbingSlab) {
    const double sigma_a = 0.8, d = 1.5;
    for (const char* integrator : {"volpath", "path"}) {
        SCOPED_TRACE(integrator);
        std::string scene =
            ortho_header(64, integrator) + fmt::format(R"(
Material "subsurface" "spectrum sigma_a" {2} "spectrum sigma_s" {3} "float eta" [ 1 ]
Shape "trianglemesh" "point3 P" [ -3 -3 {0}  3 -3 {0}  3 3 {0}  -3 3 {0}
    -3 -3 {1}  3 -3 {1}  3 3 {1}  -3 3 {1} ]
  "integer indices" [ 0 2 1  0 3 2  4 5 6  4 6 7  0 1 5  0 5 4  1 2 6  1 6 5  2 3 7  2 7 6  3 0 4  3 4 7 ]
)",
                                                       -d / 2, d / 2, flat(sigma_a), flat(0));
        Rendered r = render_string(scene);
        MeanSe m = mean_se(r.y);
        const double expected = std::exp(-sigma_a * d);
        EXPECT_NEAR(m.mean, expected, kZ * m.se) << "se " << m.se;
        EXPECT_GT(m.se, 0);
        EXPECT_LT(m.se, 0.01);
        EXPECT_EQ(r.stats.nonfinite, 0u);
    }
}

// "reflectance" A with a mean free path 500 times smaller than the sphere (locally a
// semi-infinite medium), eta = 1, under a uniform environment of radiance 1, seen by an
// orthographic camera whose window is the sphere's bounding square. Over the disk of the
// sphere the fraction of area with incidence cosine in [mu, mu + dmu] is 2 mu dmu, so the
// disk's mean radiance is the diffuse (bi-hemispherical) reflectance of the medium, which the
// albedo inversion (van de Hulst's semi-infinite, isotropic, index-matched medium) makes A;
// the corners outside the disk (1 - pi / 4 of the area) see the environment, 1. The pixels
// differ in expectation (disk, edge, corners), so the standard error comes from independent
// renders (seeds). Tolerance: the fit's accuracy for a random walk (0.003, see
// material/subsurface.h) plus the sphere's curvature (0.002) plus 4.5 standard errors.
TEST(Subsurface, InvertedAlbedoReflectsTheRequestedDiffuseReflectance) {
    for (double a : {0.2, 0.6}) {
        SCOPED_TRACE(a);
        std::vector<double> estimates;
        for (int seed = 1; seed <= 8; ++seed) {
            std::string scene =
                ortho_header(32, "volpath", seed) + fmt::format(R"(
Material "subsurface" "spectrum reflectance" {} "spectrum mfp" {} "float eta" [ 1 ]
Shape "sphere" "float radius" [ 1 ]
)",
                                                                flat(a), flat(0.002));
            Rendered r = render_string(scene);
            EXPECT_EQ(r.stats.nonfinite, 0u);
            const double disk = M_PI / 4;
            estimates.push_back((mean_se(r.y).mean - (1 - disk)) / disk);
        }
        MeanSe m = mean_se(estimates);
        EXPECT_NEAR(m.mean, a, 0.005 + kZ * m.se) << "se " << m.se;
        EXPECT_LT(m.se, 0.004);
    }
}

/// A sphere of `material` lit by a point light only (which no walk can hit: the object is lit
/// through next-event estimation at the exit points), in front of a grey floor.
std::string point_lit_sphere(const std::string& material, int spp) {
    return fmt::format(R"(
LookAt 0 0.3 3  0 0 0  0 1 0
Camera "perspective" "float fov" [ 40 ]
Film "rgb" "integer xresolution" [ 24 ] "integer yresolution" [ 24 ] "string filename" "x.exr"
Sampler "zsobol" "integer pixelsamples" [ {} ]
PixelFilter "gaussian"
WorldBegin
LightSource "point" "point3 from" [ 1 2 2 ] "spectrum I" [ 300 1 900 1 ] "float scale" [ 20 ]
Texture "checks" "spectrum" "checkerboard" "float uscale" [ 8 ] "float vscale" [ 8 ]
  "rgb tex1" [ 0.9 0.6 0.5 ] "rgb tex2" [ 0.5 0.3 0.2 ]
AttributeBegin
  {}
  Shape "sphere" "float radius" [ 0.6 ]
AttributeEnd
Material "diffuse" "rgb reflectance" [ 0.4 0.4 0.4 ]
Shape "trianglemesh" "point3 P" [ -5 -0.6 -5  5 -0.6 -5  5 -0.6 5  -5 -0.6 5 ]
  "integer indices" [ 0 2 1  0 3 2 ]
)",
                       spp, material);
}

// pbrt-v4's sssdragon material (Skin1 times 50, eta 1.5; the default integrator, volpath)
// and its head material (a textured reflectance, an RGB mean free path, a rough boundary) on
// a sphere: finite, lit by the point light through the exit vertices, the same bits on one
// and two threads, and quick.
TEST(Subsurface, SmokeRenderOfTheCorpusMaterials) {
    for (
        const char* material :
        {R"(Material "subsurface" "float scale" [ 50 ] "string name" [ "Skin1" ] "float eta" [ 1.5 ])",
         R"(Material "subsurface" "bool remaproughness" [ false ] "float vroughness" [ 0.1 ]
  "float uroughness" [ 0.1 ] "float eta" [ 1.33 ] "texture reflectance" [ "checks" ]
  "rgb mfp" [ 0.012953 0.0095238 0.0067114 ])"}) {
        SCOPED_TRACE(material);
        std::string scene = point_lit_sphere(material, 8);
        Rendered a = render_string(scene, 1), b = render_string(scene, 2);
        EXPECT_EQ(a.stats.nonfinite, 0u);
        ASSERT_EQ(a.rgb.data.size(), b.rgb.data.size());
        EXPECT_TRUE(a.rgb.data == b.rgb.data);
        // The sphere's centre pixels: lit (> 0) and finite in every channel.
        for (int c = 0; c < 3; ++c) {
            MeanSe m = mean_se(region(a, 10, 10, 14, 14, c));
            EXPECT_GT(m.mean, 0.01) << "channel " << c;
            EXPECT_TRUE(std::isfinite(m.mean));
        }
        for (float v : a.rgb.data) EXPECT_TRUE(std::isfinite(v));
    }
}

}  // namespace
}  // namespace sr::test
