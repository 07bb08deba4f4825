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
    for (const std::string material :
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

}  // namespace
}  // namespace sr::test
