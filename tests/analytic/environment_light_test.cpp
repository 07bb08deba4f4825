// The image "infinite" light (environment maps), end to end: expected values from physics —
// a furnace (a convex white object under an environment returns the environment's radiance
// scaled by its albedo), illuminance as the quadrature of the map's radiance over the
// hemisphere (independent of the renderer's sampling), MIS against its two halves, the
// "illuminance" normalisation, and lat-long maps. Tolerances: kZ standard errors plus the
// RGB uplift table's documented round-trip error (spectrum.h: at most ~3e-3 in linear sRGB).
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>

#include "steradian/film/image_io.h"
#include "steradian/integrators/measure.h"
#include "steradian/sampling/hash.h"
#include "steradian/sampling/warp.h"
#include "steradian/scene/build.h"
#include "steradian/scene/pbrt/parser.h"
#include "support/render_util.h"
#include "support/view_factors.h"

namespace sr::test {
namespace {

constexpr double kZ = 4;
constexpr double kUplift = 3e-3;  // relative round-trip error bound of the RGB uplift table

namespace fs = std::filesystem;

std::string temp_dir() {
    fs::path d = fs::temp_directory_path() / "steradian-envmap-test";
    fs::create_directories(d);
    return d.string();
}

/// Writes a PFM of w x h RGB pixels (rows from the top) given by f(x, y, channel).
template <typename F>
std::string write_map(const std::string& name, int w, int h, F f) {
    Image img;
    img.width = w;
    img.height = h;
    img.channels = 3;
    img.data.resize(size_t(w) * h * 3);
    for (int y = 0; y < h; ++y)
        for (int x = 0; x < w; ++x)
            for (int c = 0; c < 3; ++c) img.data[(size_t(y) * w + x) * 3 + c] = f(x, y, c);
    std::string path = temp_dir() + "/" + name;
    write_image(path, img);
    return path;
}

double luminance(double r, double g, double b) { return 0.2126 * r + 0.7152 * g + 0.0722 * b; }

MeasureResult measure_text(const std::string& text, double rel_error) {
    return measure_string(text, rel_error, temp_dir());
}

/// A deterministic, strongly non-uniform map: a dim noisy sky, a bright sun of a few texels.
float pattern(int x, int y, int c, int res) {
    const double noise = double(hash(uint32_t(x), uint32_t(y), uint32_t(c)) >> 11) * 0x1p-53;
    double v = 0.2 + 0.3 * noise + 0.2 * c * double(y) / res;
    if (std::abs(x - res / 3) <= 1 && std::abs(y - res / 4) <= 1) v = 400 + 100 * c;
    return float(v);
}

/// The illuminance on a patch with normal n from a map of res^2 texels of luminance
/// lum(x, y), turned by the rotation R (world = R light): each texel split into s x s
/// sub-squares of equal solid angle 4 pi / (res s)^2 (the map is equal-area), cos at each
/// sub-square's centre.
template <typename L>
double quadrature_illuminance(int res, L lum, Vec3 n, const Transform& world_from_light) {
    const int s = 8;
    double e = 0;
    for (int y = 0; y < res; ++y)
        for (int x = 0; x < res; ++x) {
            double c = 0;
            for (int j = 0; j < s; ++j)
                for (int i = 0; i < s; ++i) {
                    Point2 p((x + (i + 0.5f) / s) / res, (y + (j + 0.5f) / s) / res);
                    Vec3 w = normalize(world_from_light.vector(equal_area_square_to_sphere(p)));
                    c += std::max(0.0, double(dot(w, n)));
                }
            e += lum(x, y) * c;
        }
    return e * 4 * kPi / (double(res) * res * s * s);
}

TEST(EnvironmentLight, FurnaceReturnsTheMapRadianceTimesAlbedo) {
    // A constant map of RGB (0.5, 0.4, 0.3): a convex diffuse sphere of albedo 0.8 sees only
    // the environment, so its radiance is 0.8 times the background's, whatever the depth.
    write_map("const.pfm", 16, 16, [](int, int, int c) { return 0.5f - 0.1f * c; });
    Rendered r = render_string(R"(
LookAt 0 0 -4  0 0 0  0 1 0
Camera "perspective" "float fov" [ 40 ]
Film "rgb" "integer xresolution" [ 32 ] "integer yresolution" [ 32 ] "string filename" "x.exr"
Sampler "independent" "integer pixelsamples" [ 64 ]
Integrator "path" "integer maxdepth" [ 100 ]
PixelFilter "box"
WorldBegin
LightSource "infinite" "string filename" "const.pfm"
Material "diffuse" "spectrum reflectance" [ 300 0.8 900 0.8 ]
Shape "sphere" "float radius" [ 0.8 ]
)",
                               2, 0, temp_dir());
    const MeanSe bg = mean_se(region(r, 0, 0, 32, 3));      // top rows: background only
    const MeanSe obj = mean_se(region(r, 13, 13, 19, 19));  // centre: the sphere only
    const double expected_bg = luminance(0.5, 0.4, 0.3);
    EXPECT_NEAR(bg.mean, expected_bg, kZ * bg.se + kUplift * expected_bg);
    const double se = std::sqrt(sqr(obj.se) + sqr(0.8 * bg.se));
    EXPECT_NEAR(obj.mean, 0.8 * bg.mean, kZ * se) << "se " << obj.se;
}

TEST(EnvironmentLight, IlluminanceIsTheQuadratureOfTheRotatedMap) {
    const int res = 32;
    write_map("pattern.pfm", res, res, [](int x, int y, int c) { return pattern(x, y, c, res); });
    // The light turned 40 degrees about x then 25 about y (the CTM rotates the map).
    const Transform rot =
        Transform::rotate(25, Vec3d(0, 1, 0)) * Transform::rotate(40, Vec3d(1, 0, 0));
    const Vec3 n = normalize(Vec3(0.3f, 1, -0.2f));
    const double expected = quadrature_illuminance(
        res,
        [&](int x, int y) {
            return luminance(pattern(x, y, 0, res), pattern(x, y, 1, res), pattern(x, y, 2, res));
        },
        n, rot);
    MeasureResult m = measure_text(fmt::format(R"(
Camera "perspective"
Film "rgb" "integer xresolution" [ 4 ] "integer yresolution" [ 4 ]
WorldBegin
AttributeBegin
  Rotate 25 0 1 0
  Rotate 40 1 0 0
  LightSource "infinite" "string filename" "pattern.pfm"
AttributeEnd
Meter "illuminance" "point3 p" [ 0 0 0 ] "normal n" [ {} {} {} ]
)",
                                               n.x, n.y, n.z),
                                   2e-3);
    const double v = m.readings[0].values[0], se = m.readings[0].stderrs[0];
    std::printf("rotated map: E = %.5f +- %.5f, quadrature %.5f\n", v, se, expected);
    EXPECT_NEAR(v, expected, kZ * se + kUplift * expected);
}

TEST(EnvironmentLight, MisLightOnlyAndBsdfOnlyAgree) {
    // Light samples from the compensated density are complete only together with BSDF
    // samples; each strategy alone and their MIS combination estimate the same image.
    const int res = 32;
    write_map("pattern.pfm", res, res, [](int x, int y, int c) { return pattern(x, y, c, res); });
    auto scene = [](const char* strategy) {
        return fmt::format(R"(
LookAt 0 3 -6  0 0.5 0  0 1 0
Camera "perspective" "float fov" [ 45 ]
Film "rgb" "integer xresolution" [ 24 ] "integer yresolution" [ 16 ] "string filename" "x.exr"
Sampler "independent" "integer pixelsamples" [ 256 ] "integer seed" [ 3 ]
Integrator "path" "integer maxdepth" [ 3 ] "string strategy" "{}"
PixelFilter "box"
WorldBegin
AttributeBegin
  Rotate -90 1 0 0
  LightSource "infinite" "string filename" "pattern.pfm"
AttributeEnd
Material "diffuse" "rgb reflectance" [ 0.6 0.5 0.4 ]
Shape "bilinearmesh" "point3 P" [ -5 0 -5  5 0 -5  -5 0 5  5 0 5 ]
Material "conductor" "float roughness" [ 0.3 ]
Translate 0 0.75 0
Shape "sphere" "float radius" [ 0.75 ]
)",
                           strategy);
    };
    Rendered mis = render_string(scene("mis"), 2, 0, temp_dir());
    Rendered bsdf = render_string(scene("bsdf"), 2, 0, temp_dir());
    Rendered light = render_string(scene("light"), 2, 0, temp_dir());
    for (int by = 0; by < 2; ++by)
        for (int bx = 0; bx < 3; ++bx) {
            const int x0 = bx * 8, y0 = by * 8;
            MeanSe a = mean_se(region(mis, x0, y0, x0 + 8, y0 + 8));
            MeanSe b = mean_se(region(bsdf, x0, y0, x0 + 8, y0 + 8));
            MeanSe c = mean_se(region(light, x0, y0, x0 + 8, y0 + 8));
            EXPECT_NEAR(a.mean, b.mean, kZ * std::hypot(a.se, b.se)) << bx << "," << by;
            EXPECT_NEAR(a.mean, c.mean, kZ * std::hypot(a.se, c.se)) << bx << "," << by;
        }
}

TEST(EnvironmentLight, IlluminanceParameterGivesThatIlluminance) {
    const int res = 32;
    write_map("pattern.pfm", res, res, [](int x, int y, int c) { return pattern(x, y, c, res); });
    // "illuminance" is measured on an upward patch in the light's frame (+z); the scene
    // turns the light so that its +z is the world's +y.
    MeasureResult m = measure_text(R"(
Camera "perspective"
Film "rgb" "integer xresolution" [ 4 ] "integer yresolution" [ 4 ]
WorldBegin
AttributeBegin
  Rotate -90 1 0 0
  LightSource "infinite" "string filename" "pattern.pfm" "float illuminance" [ 500 ]
AttributeEnd
Meter "illuminance" "point3 p" [ 0 0 0 ] "normal n" [ 0 1 0 ]
)",
                                   1e-3);
    const double v = m.readings[0].values[0], se = m.readings[0].stderrs[0];
    // The texel-centre sum that normalises the map differs from the exact integral by the
    // cos variation within texels; the quadrature above bounds it below 1e-3 at res 32.
    EXPECT_NEAR(v, 500, kZ * se + (kUplift + 1e-3) * 500) << "se " << se;
}

TEST(EnvironmentLight, LatLongSkyGivesPiTimesItsRadiance) {
    // A 2:1 map, 1 above the horizon (theta < pi / 2: the top half) and 0 below: the
    // illuminance on an upward patch is pi. Resampling blurs the horizon band of texels,
    // where cos theta < 4 / res; its weight bounds the error by 16 pi / res^2.
    const int w = 128, h = 64;
    write_map("sky.pfm", w, h, [&](int, int y, int) { return y < h / 2 ? 1.f : 0.f; });
    MeasureResult m = measure_text(R"(
Camera "perspective"
Film "rgb" "integer xresolution" [ 4 ] "integer yresolution" [ 4 ]
WorldBegin
LightSource "infinite" "string filename" "sky.pfm"
Meter "illuminance" "point3 p" [ 0 0 0 ] "normal n" [ 0 0 1 ]
Meter "illuminance" "point3 p" [ 0 0 0 ] "normal n" [ 0 0 -1 ]
)",
                                   1e-3);
    const double up = m.readings[0].values[0], se = m.readings[0].stderrs[0];
    const double bias = 16 * kPi / (double(w) * w);
    EXPECT_NEAR(up, kPi, kZ * se + kUplift * kPi + bias) << "se " << se;
    EXPECT_NEAR(m.readings[1].values[0], 0, kZ * m.readings[1].stderrs[0] + bias);
}

TEST(EnvironmentLight, PortalWindowGivesTheApertureIlluminance) {
    // A uniform sky of luminance 1 above an opaque black ceiling at height 1 with a 1 x 0.6
    // window, the window given as the light's portal: the illuminance on the floor below is
    // pi L times the configuration factor of the window (corners summed by superposition).
    // The ceiling reaches 1000 m, so sky below it (grazing light) is below 1e-6 of it.
    write_map("white.pfm", 1, 1, [](int, int, int) { return 1.f; });
    const std::string ceiling = R"(
Material "diffuse" "rgb reflectance" [ 0 0 0 ]
Shape "bilinearmesh" "point3 P" [ -1000 -1000 1  1000 -1000 1  -1000 -0.3 1  1000 -0.3 1 ]
Shape "bilinearmesh" "point3 P" [ -1000 0.3 1  1000 0.3 1  -1000 1000 1  1000 1000 1 ]
Shape "bilinearmesh" "point3 P" [ -1000 -0.3 1  -0.5 -0.3 1  -1000 0.3 1  -0.5 0.3 1 ]
Shape "bilinearmesh" "point3 P" [ 0.5 -0.3 1  1000 -0.3 1  0.5 0.3 1  1000 0.3 1 ]
Meter "illuminance" "point3 p" [ 0 0 0 ] "normal n" [ 0 0 1 ]
Meter "illuminance" "point3 p" [ 0.2 0.1 0 ] "normal n" [ 0 0 1 ]
)";
    const std::string head = R"(
Camera "perspective"
Film "rgb" "integer xresolution" [ 4 ] "integer yresolution" [ 4 ]
WorldBegin
)";
    // pbrt-v4's portal frame: n = (p3 - p0) x (p1 - p0) = +x x +y = +z, the sky's side.
    const std::string portal =
        R"(LightSource "infinite" "string filename" "white.pfm" "point3 portal" [ -0.5 -0.3 1  -0.5 0.3 1  0.5 0.3 1  0.5 -0.3 1 ])";
    const double e_centre = kPi * 4 * corner_factor(0.5, 0.3, 1);
    const double e_off = kPi * (corner_factor(0.7, 0.4, 1) + corner_factor(0.7, 0.2, 1) +
                                corner_factor(0.3, 0.4, 1) + corner_factor(0.3, 0.2, 1));
    MeasureResult with = measure_text(head + portal + ceiling, 2e-3);
    MeasureResult without = measure_text(
        head + R"(LightSource "infinite" "string filename" "white.pfm")" + ceiling, 2e-3);
    // pbrt-v4 makes a portal light of a constant "L" a 1 x 1 map of L's sRGB: an
    // equal-energy spectrum of luminance 1 gives the same illuminance.
    MeasureResult with_l = measure_text(
        head +
            R"(LightSource "infinite" "spectrum L" [ 300 1 900 1 ] "point3 portal" [ -0.5 -0.3 1  -0.5 0.3 1  0.5 0.3 1  0.5 -0.3 1 ])" +
            ceiling,
        2e-3);
    for (const MeasureResult* m : {&with, &without, &with_l}) {
        const double a = m->readings[0].values[0], sa = m->readings[0].stderrs[0];
        const double b = m->readings[1].values[0], sb = m->readings[1].stderrs[0];
        std::printf("%s portal: E = %.5f +- %.5f (%.5f), %.5f +- %.5f (%.5f)\n",
                    m == &with ? "with" : m == &with_l ? "L with" : "without", a, sa, e_centre, b,
                    sb, e_off);
        EXPECT_NEAR(a, e_centre, kZ * sa + kUplift * e_centre);
        EXPECT_NEAR(b, e_off, kZ * sb + kUplift * e_off);
    }
}

TEST(EnvironmentLight, PortalLightComesOnlyFromItsOuterSide) {
    // pbrt-v4: the portal light's radiance is zero in directions w with w . n <= 0. In the
    // open, an upward patch sees pi L and a downward one nothing.
    write_map("white.pfm", 1, 1, [](int, int, int) { return 1.f; });
    MeasureResult m = measure_text(R"(
Camera "perspective"
Film "rgb" "integer xresolution" [ 4 ] "integer yresolution" [ 4 ]
WorldBegin
LightSource "infinite" "string filename" "white.pfm" "point3 portal" [ -1 -1 3  -1 1 3  1 1 3  1 -1 3 ]
Meter "illuminance" "point3 p" [ 0 0 0 ] "normal n" [ 0 0 1 ]
Meter "illuminance" "point3 p" [ 0 0 0 ] "normal n" [ 0 0 -1 ]
)",
                                   2e-3);
    EXPECT_NEAR(m.readings[0].values[0], kPi, kZ * m.readings[0].stderrs[0] + kUplift * kPi);
    EXPECT_EQ(m.readings[1].values[0], 0);
}

TEST(EnvironmentLight, BadMapsAreLocatedErrors) {
    write_map("wide.pfm", 30, 10, [](int, int, int) { return 1.f; });
    write_map("nan.pfm", 8, 8, [](int x, int, int) { return x == 3 ? NAN : 1.f; });
    auto build = [](const std::string& light) {
        return build_scene(parse_pbrt_string("Camera \"perspective\"\nWorldBegin\n" + light +
                                                 "\nShape \"sphere\"\n",
                                             "<test>", temp_dir()),
                           {});
    };
    auto message = [&](const std::string& light) {
        try {
            build(light);
        } catch (const Error& e) {
            return std::string(e.what());
        }
        return std::string("no error");
    };
    const std::string wide = message("LightSource \"infinite\" \"string filename\" \"wide.pfm\"");
    EXPECT_NE(wide.find("<test>:3:"), std::string::npos) << wide;
    EXPECT_NE(wide.find("neither square"), std::string::npos) << wide;
    const std::string nan = message("LightSource \"infinite\" \"string filename\" \"nan.pfm\"");
    EXPECT_NE(nan.find("NaN"), std::string::npos) << nan;
    const std::string both =
        message("LightSource \"infinite\" \"string filename\" \"nan.pfm\" \"rgb L\" [ 1 1 1 ]");
    EXPECT_NE(both.find("\"L\" and \"filename\""), std::string::npos) << both;
    const std::string missing =
        message("LightSource \"infinite\" \"string filename\" \"missing.exr\"");
    EXPECT_NE(missing.find("missing.exr"), std::string::npos) << missing;
    write_map("white.pfm", 1, 1, [](int, int, int) { return 1.f; });
    const std::string three = message(
        "LightSource \"infinite\" \"string filename\" \"white.pfm\" \"point3 portal\" "
        "[ 0 0 1  0 1 1  1 1 1 ]");
    EXPECT_NE(three.find("<test>:3:"), std::string::npos) << three;
    EXPECT_NE(three.find("needs 4 points"), std::string::npos) << three;
    const std::string skew = message(
        "LightSource \"infinite\" \"string filename\" \"white.pfm\" \"point3 portal\" "
        "[ 0 0 1  0 1 1  1 1 1.5  1 0 1 ]");
    EXPECT_NE(skew.find("not a planar parallelogram"), std::string::npos) << skew;
    const std::string flat = message(
        "LightSource \"infinite\" \"string filename\" \"white.pfm\" \"point3 portal\" "
        "[ 0 0 1  1 0 1  2 0 1  1 0 1 ]");
    EXPECT_NE(flat.find("span no area"), std::string::npos) << flat;
}

}  // namespace
}  // namespace sr::test
