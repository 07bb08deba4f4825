// Alpha cut-outs ("alpha" on shapes), end to end. A large horizontal sheet 1 m above an
// upward-facing illuminance meter under a uniform sky of radiance L: an opaque sheet leaves
// E = 0, an absent one E = pi L; a sheet that lets a fraction f of the rays through (a
// constant alpha 1 - f, decided per ray, or a fine checkerboard of opaque and clear squares)
// passes E = f pi L, up to the sky beyond the sheet's edges (a fraction cos^2 of the edge
// angle of the cosine-weighted hemisphere: 1e-6 here). Camera rays pass fully transparent
// shapes, shadow rays are cut the same way as camera rays, and a sphere's cut-out lets rays
// on to its far side.
#include <gtest/gtest.h>

#include <cmath>

#include "steradian/integrators/measure.h"
#include "steradian/scene/build.h"
#include "steradian/scene/pbrt/parser.h"
#include "support/render_util.h"
#include "support/view_factors.h"

namespace sr::test {
namespace {

constexpr double kZ = 4;
constexpr double kPiD = 3.14159265358979323846;

double sheet_illuminance(const std::string& sheet_params, const std::string& textures = "") {
    const std::string text = R"(
Camera "perspective"
Film "rgb" "integer xresolution" [ 4 ] "integer yresolution" [ 4 ]
WorldBegin
LightSource "infinite" "spectrum L" [ 300 1 900 1 ]
)" + textures + R"(
Material "diffuse" "spectrum reflectance" [ 300 0.5 900 0.5 ]
Shape "bilinearmesh" "point3 P" [ -1000 -1000 1  1000 -1000 1  -1000 1000 1  1000 1000 1 ]
    "point2 uv" [ 0 0  1 0  0 1  1 1 ] )" +
                             sheet_params + R"(
Meter "illuminance" "point3 p" [ 0 0 0 ] "normal n" [ 0 0 1 ] "integer maxdepth" [ 1 ]
)";
    MeasureResult r = measure_string(text, 2e-3);
    const double v = r.readings[0].values[0], se = r.readings[0].stderrs[0];
    std::printf("%s: E = %.5f +- %.5f\n", sheet_params.c_str(), v, se);
    return v;
}

// The meters' own standard error is at most 2e-3 relative (the target); kZ of it, plus the
// 1e-6 of sky beyond the sheet.
void expect_fraction(double e, double f) {
    const double expected = f * kPiD;
    EXPECT_NEAR(e, expected, kZ * 2e-3 * expected + 1e-6 * kPiD);
}

TEST(Alpha, OpaqueAndAbsentSheets) {
    EXPECT_LT(sheet_illuminance(""), 1e-5 * kPiD);  // only the edge sky
    expect_fraction(sheet_illuminance("\"float alpha\" [ 0 ]"), 1);
    EXPECT_LT(sheet_illuminance("\"float alpha\" [ 1 ]"), 1e-5 * kPiD);
}

TEST(Alpha, ConstantAlphaStopsThatFractionOfRays) {
    expect_fraction(sheet_illuminance("\"float alpha\" [ 0.3 ]"), 0.7);
    expect_fraction(sheet_illuminance("\"float alpha\" [ 0.75 ]"), 0.25);
}

TEST(Alpha, CheckerboardWithHalfItsSquaresClearPassesHalf) {
    // 2 mm squares on the 2 km sheet (uv 0..1: 1e6 squares a side), 1 m above the meter.
    expect_fraction(sheet_illuminance("\"texture alpha\" \"holes\"",
                                      R"(Texture "holes" "float" "checkerboard"
    "float uscale" [ 1000000 ] "float vscale" [ 1000000 ] "float tex1" [ 0 ] "float tex2" [ 1 ])"),
                    0.5);
}

TEST(Alpha, CameraRaysPassATransparentShape) {
    // A clear quad (alpha 0) in front of the scene changes nothing: the same rays hit the
    // same surfaces, bit for bit.
    const std::string base = R"(
LookAt 0 0 -4  0 0 0  0 1 0
Camera "perspective" "float fov" [ 40 ]
Film "rgb" "integer xresolution" [ 16 ] "integer yresolution" [ 16 ] "string filename" "x.exr"
Sampler "independent" "integer pixelsamples" [ 4 ]
WorldBegin
LightSource "infinite" "rgb L" [ 0.5 0.5 0.5 ]
Material "diffuse" "rgb reflectance" [ 0.6 0.3 0.2 ]
Shape "sphere" "float radius" [ 1 ]
)";
    const std::string quad =
        "Shape \"trianglemesh\" \"point3 P\" [ -3 -3 -2  3 -3 -2  3 3 -2  -3 3 -2 ]\n"
        "    \"integer indices\" [ 0 1 2  0 2 3 ] \"float alpha\" [ 0 ]\n";
    Rendered a = render_string(base);
    Rendered b = render_string(base + quad);
    ASSERT_EQ(a.rgb.data.size(), b.rgb.data.size());
    for (size_t i = 0; i < a.rgb.data.size(); ++i) ASSERT_EQ(a.rgb.data[i], b.rgb.data[i]) << i;
    // And an opaque one hides the sphere entirely: its pixels are then all one colour.
    Rendered c = render_string(base +
                               "Shape \"trianglemesh\" \"point3 P\" [ -3 -3 -2  3 -3 -2  3 3 -2  "
                               "-3 3 -2 ] \"integer indices\" [ 0 1 2  0 2 3 ]\n");
    EXPECT_NE(a.y[8 * 16 + 8], c.y[8 * 16 + 8]);
}

// Inside a black sphere of alpha 0.3 every ray meets the wall once: 70 % pass on to the
// sky, so the upward illuminance at its centre is 0.7 pi L.
TEST(Alpha, RaysPassASphereOfAlpha) {
    const std::string text = R"(
Camera "perspective"
Film "rgb" "integer xresolution" [ 4 ] "integer yresolution" [ 4 ]
WorldBegin
LightSource "infinite" "spectrum L" [ 300 1 900 1 ]
Material "diffuse" "spectrum reflectance" [ 300 0 900 0 ]
Shape "sphere" "float radius" [ 2 ] "float alpha" [ 0.3 ]
Meter "illuminance" "point3 p" [ 0 0 0 ] "normal n" [ 0 0 1 ]
)";
    MeasureResult r = measure_string(text, 2e-3);
    const double v = r.readings[0].values[0], se = r.readings[0].stderrs[0];
    EXPECT_NEAR(v, 0.7 * kPiD, kZ * se) << "se " << se;
}

TEST(Alpha, AnEmitterEmitsOnlyWhereItIsNotCutOut) {
    // pbrt-v4 masks an area light's emission by its alpha (where light samples land and
    // where rays hit it). A 2 x 2 two-sided emitter of luminance 1 at height 1 cut by a
    // checkerboard alpha into quadrants: only x < 0, y < 0 and x > 0, y > 0 emit. The
    // illuminance of an upward meter below is pi L times those quadrants' factors (in the
    // dark, one bounce of black surroundings).
    const std::string text = R"(
Camera "perspective"
Film "rgb" "integer xresolution" [ 4 ] "integer yresolution" [ 4 ]
WorldBegin
Texture "cut" "float" "checkerboard" "float tex1" [ 1 ] "float tex2" [ 0 ]
    "float uscale" [ 2 ] "float vscale" [ 2 ]
AreaLightSource "diffuse" "spectrum L" [ 300 1 900 1 ] "bool twosided" true
Material "diffuse" "spectrum reflectance" [ 300 0 900 0 ]
Shape "bilinearmesh" "point3 P" [ -1 -1 1  1 -1 1  -1 1 1  1 1 1 ]
    "point2 uv" [ 0 0  1 0  0 1  1 1 ] "texture alpha" "cut"
Meter "illuminance" "point3 p" [ 0 0 0 ] "normal n" [ 0 0 1 ]
Meter "illuminance" "point3 p" [ 0.5 -0.25 0 ] "normal n" [ 0 0 1 ]
)";
    MeasureResult r = measure_string(text, 2e-3);
    const double px[2] = {0, 0.5}, py[2] = {0, -0.25};
    for (int i = 0; i < 2; ++i) {
        const double f = rectangle_factor(-1, 0, -1, 0, px[i], py[i], 1) +
                         rectangle_factor(0, 1, 0, 1, px[i], py[i], 1);
        const double v = r.readings[size_t(i)].values[0], se = r.readings[size_t(i)].stderrs[0];
        std::printf("alpha emitter at (%g, %g): E = %.5f +- %.5f, expected %.5f\n", px[i], py[i],
                    v, se, kPiD * f);
        EXPECT_NEAR(v, kPiD * f, kZ * se + 1e-4 * kPiD * f);
    }
}

}  // namespace
}  // namespace sr::test
