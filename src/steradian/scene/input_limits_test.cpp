// Scene values that overflow the renderer's 32-bit floats, or that would allocate without
// bound, are errors at their directive or parameter, not infinities or NaNs in the image nor
// gigabytes of memory (found with the fuzzing harnesses of fuzz/).
#include <gtest/gtest.h>

#include <string>

#include "steradian/scene/build.h"
#include "steradian/scene/pbrt/parser.h"

namespace sr {
namespace {

std::string build_error(const std::string& world) {
    std::string text = R"(
Camera "perspective"
Film "rgb" "integer xresolution" [4] "integer yresolution" [4]
WorldBegin
)" + world;
    try {
        build_scene(parse_pbrt_string(text, "limits.pbrt"));
    } catch (const Error& e) {
        return e.what();
    }
    return "(no error)";
}

TEST(SceneInputLimits, LightPowerBeyondFloatIsAnError) {
    EXPECT_EQ(build_error(R"(LightSource "point" "rgb I" [3e38 3e38 3e38] "float scale" [3e38]
Shape "sphere")"),
              "limits.pbrt:5:1: the light's emitted power overflows a 32-bit float: its "
              "intensity, scale, power or size is too large");
    // An area light's power is per emitting primitive, over its area.
    EXPECT_NE(build_error(R"(AreaLightSource "diffuse" "rgb L" [1 1 1] "float power" [3e38]
Shape "sphere" "float radius" [1e-20])")
                  .find("limits.pbrt:5:1: the light's emitted power overflows"),
              std::string::npos);
}

TEST(SceneInputLimits, SpectrumValuesWhoseDifferenceOverflowsAreErrors) {
    // Interpolating between 1e38 and -3e38 computed -4e38: -inf, then NaN.
    EXPECT_EQ(build_error(R"(Material "conductor" "spectrum eta" [360 1 830 1]
    "spectrum k" [360 1e38 830 -3e38]
Shape "sphere")"),
              "limits.pbrt:6:5: \"spectrum k\": the value -3e+38 is outside +-1e+38");
    std::string msg = "(no error)";
    try {
        parse_spectrum_file("360 1\n500 2\n830 -3e38\n", "k.spd", {"s.pbrt", 1, 1});
    } catch (const Error& e) {
        msg = e.what();
    }
    EXPECT_EQ(msg, "s.pbrt:1:1: k.spd:3: the value -3e+38 is outside +-1e+38");
}

TEST(SceneInputLimits, MeterGridHasAtMostAMillionCells) {
    const std::string grid = R"(LightSource "point" "rgb I" [1 1 1]
Meter "illuminancegrid" "point3 corner" [0 0 0] "vector3 u" [1 0 0] "vector3 v" [0 1 0]
    "integer resolution" )";
    EXPECT_EQ(build_error(grid + "[10000 10000]"),
              "limits.pbrt:7:5: Meter \"illuminancegrid\": \"resolution\" [10000 10000] has "
              "more than 1048576 cells");
    EXPECT_EQ(build_error(grid + "[1024 1024]"), "(no error)");
}

TEST(SceneInputLimits, SpectrumFileLinesHoldExactlyTwoNumbers) {
    auto error = [](const std::string& text) -> std::string {
        try {
            parse_spectrum_file(text, "s.spd", {"s.pbrt", 1, 1});
        } catch (const Error& e) {
            return e.what();
        }
        return "(no error)";
    };
    EXPECT_EQ(error("# header\n\n360 1 # a\r\n \t\n830 2\r\n"), "(no error)");
    // Each of these was skipped or cut short without a word.
    EXPECT_EQ(error("360 1\nwavelength value\n830 2\n"),
              "s.pbrt:1:1: s.spd:2: expected \"wavelength value\" (two numbers), got "
              "\"wavelength value\"");
    EXPECT_EQ(error("360 1\n1e400 3\n830 2\n"),
              "s.pbrt:1:1: s.spd:2: expected \"wavelength value\" (two numbers), got \"1e400 3\"");
    EXPECT_EQ(error("360 1 400 2\n830 2\n"),
              "s.pbrt:1:1: s.spd:1: expected \"wavelength value\" (two numbers), got "
              "\"360 1 400 2\"");
}

TEST(SceneInputLimits, BilinearMeshNeedsOneNormalAndUvPerVertex) {
    // The tessellation of a non-planar patch read N and uv by vertex index, past their end.
    const std::string mesh = R"(Shape "bilinearmesh" "point3 P" [0 0 0  1 0 0  0 1 0  1 1 1] )";
    EXPECT_EQ(build_error(mesh + R"("normal N" [0 0 1  0 0 1])"),
              "limits.pbrt:5:1: Shape \"bilinearmesh\": 2 normals for 4 vertices");
    EXPECT_EQ(build_error(mesh + R"("point2 uv" [0 0])"),
              "limits.pbrt:5:1: Shape \"bilinearmesh\": 1 uvs for 4 vertices");
}

}  // namespace
}  // namespace sr

namespace sr {
namespace {

// Attribute defaults are copied into every entity they apply to: a large default over many
// shapes would take memory growing with the square of the file (a 256 KB scene took 1.7 GB).
// The copies are counted, and beyond 2^26 values the parse stops at the default's line.
TEST(SceneInputLimits, AttributeDefaultsCopiedWithoutBoundAreAnError) {
    std::string text = "WorldBegin\nAttribute \"shape\" \"float padding\" [";
    for (int i = 0; i < 1000; ++i) text += " 1";
    text += " ]\n";
    for (int i = 0; i < 70000; ++i) text += "Shape \"sphere\"\n";  // 70 M values copied
    try {
        parse_pbrt_string(text, "attrs.pbrt");
        FAIL() << "expected an error";
    } catch (const Error& e) {
        const std::string m = e.what();
        EXPECT_NE(m.find("attrs.pbrt:2:"), std::string::npos) << m;
        EXPECT_NE(m.find("Attribute defaults"), std::string::npos) << m;
    }
    // Small defaults on many shapes stay fine.
    std::string ok = "WorldBegin\nAttribute \"shape\" \"float radius\" [ 2 ]\n";
    for (int i = 0; i < 20000; ++i) ok += "Shape \"sphere\"\n";
    EXPECT_NO_THROW(parse_pbrt_string(ok, "attrs.pbrt"));
}

}  // namespace
}  // namespace sr
