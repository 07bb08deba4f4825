// The "hair" material and the "curve" shape through the builder and the path integrator:
// in a white furnace (uniform radiance 1 from every direction) a scatterer that absorbs
// nothing is invisible, whatever it scatters where: every pixel reads 1. A hair sphere and a
// fringe of hair curves in front of it, with sigma_a = 0 given directly, through a white
// "reflectance", and (absorbing) by the default melanin, which must be darker.
#include <gtest/gtest.h>

#include <cstdio>
#include <string>

#include "support/render_util.h"

namespace sr::test {
namespace {

constexpr double kZ = 4.5;  // tolerance in standard errors

/// Hair curves across the camera's view (it looks along +z from z = -4 at the unit sphere),
/// at z = -1.5: 24 vertical cubic curves of width 0.06, bent towards the camera.
std::string fringe(const char* type) {
    std::string s;
    for (int i = 0; i < 24; ++i) {
        const std::string x = std::to_string(-0.9 + 0.08 * i);
        s += std::string("Shape \"curve\" \"string type\" \"") + type + "\" \"float width0\" 0.06 " +
             "\"float width1\" 0.02 \"point3 P\" [" + x + " -1.2 -1.5  " + x + " -0.4 -1.8  " + x +
             " 0.4 -1.2  " + x + " 1.2 -1.5]\n";
    }
    return s;
}

TEST(HairCurves, NonAbsorbingHairIsInvisibleInTheFurnace) {
    for (const std::string& material :
         {std::string(R"(Material "hair" "rgb sigma_a" [0 0 0] "float beta_m" 0.2)"),
          std::string(R"(Material "hair" "rgb reflectance" [1 1 1] "float alpha" 0)")}) {
        for (const char* type : {"cylinder", "flat"}) {
            Rendered r = render_string(furnace_scene(material + "\n" + fringe(type), 64, 1000));
            MeanSe m = mean_se(region(r, 2, 2, 14, 14));
            std::printf("%s, %s curves: %.5f +- %.5f\n", material.c_str(), type, m.mean, m.se);
            EXPECT_LT(std::abs(m.mean - 1), kZ * m.se + 1e-4) << material << " " << type;
            EXPECT_EQ(r.stats.nonfinite, 0u);
        }
    }
}

TEST(HairCurves, MelaninAbsorbs) {
    Rendered r = render_string(furnace_scene("Material \"hair\"\n" + fringe("cylinder"), 32, 1000));
    MeanSe m = mean_se(region(r, 6, 6, 10, 10));  // sphere and curves: eumelanin 1.3 absorbs
    std::printf("default hair: %.5f +- %.5f\n", m.mean, m.se);
    EXPECT_LT(m.mean + kZ * m.se, 0.9);
    EXPECT_EQ(r.stats.nonfinite, 0u);
}

/// A horizontal fibre (along x, radius 0.5) seen head-on by an orthographic camera and lit
/// by a distant light 45 degrees above the view direction, in the fibre's normal plane.
/// Returns the luminance of the image's upper half minus that of its lower half, over their
/// sum.
double upper_minus_lower(const std::string& world) {
    Rendered r = render_string(R"(
LookAt 0 0 5  0 0 0  0 1 0
Camera "orthographic" "float screenwindow" [ -1 1 -1 1 ]
Film "rgb" "integer xresolution" [ 16 ] "integer yresolution" [ 16 ] "string filename" "x.exr"
Sampler "zsobol" "integer pixelsamples" [ 16 ]
Integrator "path" "integer maxdepth" [ 1 ]
WorldBegin
LightSource "distant" "point3 from" [ 0 1 1 ] "point3 to" [ 0 0 0 ] "float illuminance" [ 3 ]
)" + world);
    double up = 0, down = 0;
    for (int y = 0; y < 16; ++y)
        for (int x = 0; x < 16; ++x) (y < 8 ? up : down) += r.y[size_t(y) * 16 + x];
    return (up - down) / (up + down);
}

TEST(HairCurves, TheSurfaceGlintIsOnTheSideTowardsTheLight) {
    // A convex specular cylinder reflects the light where its normal bisects the directions
    // to the light and to the viewer: 22.5 degrees from the view direction towards the light,
    // so the highlight lies on the half of the fibre towards the light. A rough conductor on
    // an exact cylinder shows which image half that is; hair that only reflects at its
    // surface (sigma_a large: R alone) must glint on the same half. This fixes the sign of
    // the offset h that curves give the hair model.
    const double cylinder = upper_minus_lower(
        R"(Material "conductor" "float roughness" 0.1
Rotate 90 0 1 0
Shape "cylinder" "float radius" 0.5 "float zmin" -2 "float zmax" 2)");
    const double hair = upper_minus_lower(
        R"(Material "hair" "rgb sigma_a" [ 1000 1000 1000 ] "float beta_m" 0.2 "float beta_n" 0.2 "float alpha" 0
Shape "curve" "string type" "cylinder" "float width" 1 "point3 P" [ -2 0 0  -0.7 0 0  0.7 0 0  2 0 0 ])");
    std::printf("(upper - lower) / sum: conductor cylinder %.3f, hair curve %.3f\n", cylinder, hair);
    EXPECT_GT(std::abs(cylinder), 0.3);
    EXPECT_GT(hair * cylinder, 0) << "the hair's glint is on the other half";
    EXPECT_GT(std::abs(hair), 0.1);
}

TEST(HairCurves, BundledHairSceneRendersCleanly) {
    SceneDesc d = parse_pbrt_file(std::string(STERADIAN_SOURCE_DIR) + "/scenes/hair.pbrt");
    Scene s = build_scene(d, {});
    Film film(s.film);
    RenderOptions ro;
    ro.spp = 1;
    ro.threads = 2;
    RenderStats st = render(s, film, ro);
    EXPECT_EQ(st.nonfinite, 0u);
    double sum = 0;
    for (double y : film.luminance()) sum += y;
    EXPECT_GT(sum, 0);
}

}  // namespace
}  // namespace sr::test
