// pbrt-v4's "cylinder" shape, end to end: an upward illuminance meter on the axis of a black
// open cylinder (radius r, wall from below the meter to height h above it) under a uniform
// sky of radiance L sees the sky only through the top opening, a cone of half-angle
// alpha = atan(r / h): E = pi L sin^2 alpha = pi L r^2 / (r^2 + h^2). With half the wall
// (phimax 180) the other half of the sky is open: E = (pi L / 2)(1 + sin^2 alpha).
// Tolerances: kZ standard errors of the meter.
#include <gtest/gtest.h>

#include "steradian/integrators/measure.h"
#include "steradian/scene/build.h"
#include "steradian/scene/pbrt/parser.h"
#include "support/render_util.h"

namespace sr::test {
namespace {

constexpr double kZ = 4;
constexpr double kPiD = 3.14159265358979323846;

MeasureResult measure_text(const std::string& text) { return measure_string(text, 2e-3); }

std::string well(const std::string& extra) {
    return R"(
Camera "perspective"
Film "rgb" "integer xresolution" [ 4 ] "integer yresolution" [ 4 ]
WorldBegin
LightSource "infinite" "spectrum L" [ 300 1 900 1 ]
Material "diffuse" "spectrum reflectance" [ 300 0 900 0 ]
AttributeBegin
  Translate 0 0 -5
  Shape "cylinder" "float radius" [ 1 ] "float zmin" [ 0 ] "float zmax" [ 7 ] )" +
           extra + R"(
AttributeEnd
Meter "illuminance" "point3 p" [ 0 0 0 ] "normal n" [ 0 0 1 ]
)";
}

TEST(Cylinder, SkyThroughTheOpening) {
    MeasureResult m = measure_text(well(""));
    const double e = m.readings[0].values[0], se = m.readings[0].stderrs[0];
    const double expected = kPiD * 1.0 / (1.0 + 4.0);  // r = 1, h = 2
    EXPECT_NEAR(e, expected, kZ * se) << "se " << se;
}

TEST(Cylinder, HalfAWallOpensHalfTheSky) {
    MeasureResult m = measure_text(well("\"float phimax\" [ 180 ]"));
    const double e = m.readings[0].values[0], se = m.readings[0].stderrs[0];
    const double expected = kPiD / 2 * (1 + 1.0 / 5.0);
    EXPECT_NEAR(e, expected, kZ * se) << "se " << se;
}

TEST(Cylinder, IntersectionAndHitRecord) {
    Cylinder c;
    c.radius = 2;
    c.z_min = -1;
    c.z_max = 3;
    Float t;
    Point3 p;
    // From outside along -x at height 1: enters at x = 2, t = 5 - 2.
    ASSERT_TRUE(c.intersect_object(Point3(5, 0, 1), Vec3(-1, 0, 0), 100, t, p));
    EXPECT_NEAR(t, 3, 1e-5);
    // From the axis: the wall at distance r; above z_max: missed.
    ASSERT_TRUE(c.intersect_object(Point3(0, 0, 0), Vec3(0, 1, 0), 100, t, p));
    EXPECT_NEAR(t, 2, 1e-5);
    EXPECT_FALSE(c.intersect_object(Point3(0, 0, 3.5f), Vec3(0, 1, 0), 100, t, p));
    // Past the near wall (t_min) the far wall is found.
    ASSERT_TRUE(c.intersect_object(Point3(5, 0, 1), Vec3(-1, 0, 0), 100, t, p, 3.5f));
    EXPECT_NEAR(t, 7, 1e-5);
    SurfaceHit h;
    c.fill_hit(Point3(0, 2, 2), h);  // phi = 90 degrees, z = 2
    EXPECT_NEAR(h.uv.x, 0.25f, 1e-6);
    EXPECT_NEAR(h.uv.y, 0.75f, 1e-6);
    EXPECT_NEAR(h.ng.y, 1, 1e-6);  // outwards
    EXPECT_NEAR(c.area(), 2 * kPiD * 2 * 4, 1e-4);
}

}  // namespace
}  // namespace sr::test
