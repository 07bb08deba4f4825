// Participating media through the whole pipeline (parser, builder, volpath kernel), against
// closed forms of radiative transfer: Beer-Lambert attenuation, energy conservation of an
// albedo-1 medium in a white furnace, the single-scattering radiance of a thin slab, and a
// constant-density grid against the homogeneous medium it equals.
#include <fmt/format.h>
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <random>

#include "support/nvdb_writer.h"
#include "steradian/spectrum/spectrum.h"
#include "support/render_util.h"

namespace sr::test {
namespace {

using test::NvdbGridSpec;
using test::write_nvdb;

constexpr double kZ = 4.5;  // tolerance in standard errors

std::string flat(double v) { return fmt::format("[ 300 {} 900 {} ]", v, v); }

/// A closed box [lo, hi] as a triangle mesh whose normals point outwards (pbrt-v4's
/// convention: n = (p1 - p0) x (p2 - p0)), so that its MediumInterface "inside" is the box.
std::string box(double x0, double y0, double z0, double x1, double y1, double z1) {
    return fmt::format(
        R"(Shape "trianglemesh" "point3 P" [ {0} {1} {2}  {3} {1} {2}  {3} {4} {2}  {0} {4} {2}
    {0} {1} {5}  {3} {1} {5}  {3} {4} {5}  {0} {4} {5} ]
  "integer indices" [ 0 2 1  0 3 2  4 5 6  4 6 7  0 1 5  0 5 4  1 2 6  1 6 5  2 3 7  2 7 6  3 0 4  3 4 7 ])",
        x0, y0, z0, x1, y1, z1);
}

/// An orthographic camera looking down -z at [-1, 1]^2, 16 x 16 pixels.
std::string ortho_header(int spp, int max_depth, const std::string& integrator = "volpath") {
    return fmt::format(R"(
LookAt 0 0 5  0 0 0  0 1 0
Camera "orthographic" "float screenwindow" [ -1 1 -1 1 ]
Film "rgb" "integer xresolution" [ 16 ] "integer yresolution" [ 16 ] "string filename" "x.exr"
Sampler "independent" "integer pixelsamples" [ {} ]
Integrator "{}" "integer maxdepth" [ {} ]
PixelFilter "box"
WorldBegin
)",
                       spp, integrator, max_depth);
}

// A purely absorbing slab of thickness d in front of an emitter of luminance 1: every pixel
// sees exp(-sigma_a d) (Beer-Lambert), whatever the slab's sides do elsewhere.
TEST(Media, BeerLambertThroughAnAbsorbingSlab) {
    const double sigma_a = 0.8, d = 1.5;
    std::string scene =
        ortho_header(64, 5) + fmt::format(R"(
MakeNamedMedium "slab" "string type" "homogeneous" "spectrum sigma_a" {} "spectrum sigma_s" {}
AttributeBegin
  MediumInterface "slab" ""
  Material "interface"
  {}
AttributeEnd
AttributeBegin
  AreaLightSource "diffuse" "spectrum L" {}
  Translate 0 0 -3
  Shape "trianglemesh" "point3 P" [ -5 -5 0  5 -5 0  5 5 0  -5 5 0 ] "integer indices" [ 0 1 2  0 2 3 ]
AttributeEnd
)",
                                          flat(sigma_a), flat(0), box(-3, -3, -d / 2, 3, 3, d / 2),
                                          flat(1));
    Rendered r = render_string(scene);
    MeanSe m = mean_se(r.y);
    const double expected = std::exp(-sigma_a * d);
    EXPECT_NEAR(m.mean, expected, kZ * m.se) << "se " << m.se;
    EXPECT_GT(m.se, 0);  // the estimate is stochastic (delta tracking): the test can fail
    EXPECT_EQ(r.stats.nonfinite, 0u);

    // "path" renders media too (pbrt-v4's PathIntegrator would ignore them and see 1).
    std::string path_scene = scene;
    path_scene.replace(path_scene.find("\"volpath\""), 9, "\"path\"");
    MeanSe p = mean_se(render_string(path_scene).y);
    EXPECT_NEAR(p.mean, expected, kZ * p.se) << "se " << p.se;
}

// An albedo-1 medium (sigma_a = 0) inside a sphere under a uniform environment of radiance 1:
// radiance is conserved along every path, so every pixel is 1 (any g, any density).
TEST(Media, AlbedoOneMediumInAWhiteFurnaceConservesEnergy) {
    for (double g : {0.0, 0.7}) {
        std::string scene = fmt::format(R"(
LookAt 0 0 -4  0 0 0  0 1 0
Camera "perspective" "float fov" [ 30 ]
Film "rgb" "integer xresolution" [ 16 ] "integer yresolution" [ 16 ] "string filename" "x.exr"
Sampler "independent" "integer pixelsamples" [ 32 ]
Integrator "volpath" "integer maxdepth" [ 100000 ]
PixelFilter "box"
WorldBegin
LightSource "infinite" "spectrum L" {}
MakeNamedMedium "cloud" "string type" "homogeneous" "spectrum sigma_a" {} "spectrum sigma_s" {}
  "float g" [ {} ]
MediumInterface "cloud" ""
Material "interface"
Shape "sphere" "float radius" [ 1 ]
)",
                                        flat(1), flat(0), flat(3), g);
        Rendered r = render_string(scene);
        // The sphere covers the pixels [4, 12)^2; its optical radius is 3.
        MeanSe c = mean_se(region(r, 5, 5, 11, 11));
        EXPECT_NEAR(c.mean, 1.0, std::max(kZ * c.se, 1e-4)) << "g " << g << " se " << c.se;
        MeanSe m = mean_se(r.y);
        EXPECT_NEAR(m.mean, 1.0, std::max(kZ * m.se, 1e-4)) << "g " << g;
        EXPECT_EQ(r.stats.nonfinite, 0u);
    }
}

// Single scattering in a slab z in [-d, 0] lit from +z by a distant light of perpendicular
// illuminance E, seen straight from above (maxdepth 1: one scattering event). Light reaching
// depth z is E exp(-sigma_t z); scattered back towards the camera (wo = wi, the
// Henyey-Greenstein value p(1) = (1 - g^2) / (4 pi (1 + g)^3)) and attenuated on the way up:
//   L = int_0^d sigma_s p E exp(-2 sigma_t z) dz = sigma_s p E (1 - exp(-2 sigma_t d)) / (2
//   sigma_t).
TEST(Media, SingleScatteringOfASlabMatchesTheClosedForm) {
    const double sigma_a = 0.3, sigma_s = 1.2, d = 0.5, g = 0.4, E = 10;
    std::string scene = ortho_header(128, 1) + fmt::format(R"(
LightSource "distant" "point3 from" [ 0 0 1 ] "point3 to" [ 0 0 0 ] "float illuminance" [ {} ]
MakeNamedMedium "slab" "string type" "homogeneous" "spectrum sigma_a" {} "spectrum sigma_s" {}
  "float g" [ {} ]
MediumInterface "slab" ""
Material "interface"
{}
)",
                                                           E, flat(sigma_a), flat(sigma_s), g,
                                                           box(-50, -50, -d, 50, 50, 0));
    Rendered r = render_string(scene);
    MeanSe m = mean_se(r.y);
    const double st = sigma_a + sigma_s;
    const double p = (1 - g * g) / (4 * M_PI * std::pow(1 + g, 3));
    const double expected = sigma_s * p * E * (1 - std::exp(-2 * st * d)) / (2 * st);
    EXPECT_NEAR(m.mean, expected, kZ * m.se) << "se " << m.se << " expected " << expected;
    EXPECT_LT(m.se, 0.02 * expected);  // precise enough to tell g = 0.4 from isotropic
}

// A "uniformgrid" of constant density c over a box much larger than the view equals the
// homogeneous medium with sigma scaled by c, away from the grid's boundary (where pbrt-v4's
// interpolation falls to zero over half a cell): the same slab scene both ways.
/// The slab [-5, 5]^2 x [-d, 0] of `medium` (its MakeNamedMedium parameters) inside an
/// interface box, lit by a distant light, seen from above at 128 spp.
std::string slab_scene(double d, const std::string& medium) {
    return ortho_header(128, 20) + fmt::format(R"(
LightSource "distant" "point3 from" [ 0.3 0 1 ] "point3 to" [ 0 0 0 ] "float illuminance" [ 5 ]
MakeNamedMedium "slab" {}
MediumInterface "slab" ""
Material "interface"
{}
)",
                                               medium, box(-5, -5, -d, 5, 5, 0));
}

/// `r` (a render of slab_scene(d, ...)) equals, within the estimates' standard errors, the
/// slab of the homogeneous medium sigma_a = 0.2 c, sigma_s = 0.6 c, g = 0.5.
void expect_homogeneous_slab(const Rendered& r, double d, double c) {
    Rendered homo = render_string(slab_scene(d, fmt::format(
        R"("string type" "homogeneous" "spectrum sigma_a" {} "spectrum sigma_s" {} "float g" [ 0.5 ])",
        flat(0.2 * c), flat(0.6 * c))));
    MeanSe a = mean_se(r.y), b = mean_se(homo.y);
    EXPECT_GT(b.mean, 0.01);
    EXPECT_NEAR(a.mean, b.mean, kZ * std::hypot(a.se, b.se)) << a.se << " " << b.se;
    EXPECT_EQ(r.stats.nonfinite, 0u);
}

TEST(Media, ConstantDensityGridEqualsTheHomogeneousMedium) {
    const double d = 0.5, c = 2.0;
    // The grid: 4 x 4 x 4 nodes over [-20, 20]^2 x [-2, 2]: its interior holds the slab.
    std::string density = "[";
    for (int i = 0; i < 64; ++i) density += fmt::format(" {}", c);
    density += " ]";
    Rendered grid = render_string(slab_scene(d, fmt::format(
        R"("string type" "uniformgrid" "integer nx" [ 4 ] "integer ny" [ 4 ] "integer nz" [ 4 ]
  "float density" {} "point3 p0" [ -20 -20 -2 ] "point3 p1" [ 20 20 2 ]
  "spectrum sigma_a" {} "spectrum sigma_s" {} "float g" [ 0.5 ])",
        density, flat(0.2), flat(0.6))));
    expect_homogeneous_slab(grid, d, c);
}

// A "nanovdb" grid of constant density c covering a slab, the slab an interface box naming
// it: the same image as the homogeneous medium of coefficients c sigma (inside the box the
// grid's interpolation is exactly c; pbrt-v4 scales sigma by the density the same way).
TEST(Media, ConstantNanoVdbGridEqualsTheHomogeneousMedium) {
    const double d = 0.5, c = 2.0;
    std::random_device rd;
    const std::filesystem::path dir =
        std::filesystem::temp_directory_path() / ("sr_media_nvdb_" + std::to_string(rd()));
    std::filesystem::create_directories(dir);
    // Voxels [-7, 7]^2 x [-3, 3] of size 1 at the origin: c on [-7, 7]^2 x [-3, 3], which
    // holds the slab [-5, 5]^2 x [-0.5, 0].
    NvdbGridSpec g;
    g.value = [c](int, int, int) { return float(c); };
    g.lo = nanovdb::Coord(-7, -7, -3);
    g.hi = nanovdb::Coord(7, 7, 3);
    write_nvdb((dir / "slab.nvdb").string(), {g});
    Rendered vdb = render_string(
        slab_scene(d, fmt::format(R"("string type" "nanovdb" "string filename" "slab.nvdb"
  "spectrum sigma_a" {} "spectrum sigma_s" {} "float g" [ 0.5 ] "float scale" [ 0.5 ])",
                          flat(0.4), flat(1.2))),
        2, 0, dir.string());
    std::filesystem::remove_all(dir);
    expect_homogeneous_slab(vdb, d, c);
}

// A "cloud" of density parameter 0 has density min(1, 2 max(0, 0.5 - y)): 1 wherever y <= 0.
// Over bounds with y <= 0, inside an interface box of the same extent, it renders as the
// homogeneous medium of its sigma_a and sigma_s. A noisy cloud renders finite values.
TEST(Media, CloudOfUnitDensityEqualsTheHomogeneousMedium) {
    const std::string slab = box(-3, -3, -0.5, 3, 0, 0);
    auto scene = [&](const std::string& medium) {
        return ortho_header(128, 20) + fmt::format(R"(
LightSource "distant" "point3 from" [ 0.3 -0.2 1 ] "point3 to" [ 0 0 0 ] "float illuminance" [ 5 ]
MakeNamedMedium "c" {}
MediumInterface "c" ""
Material "interface"
{}
)",
                                                   medium, slab);
    };
    const std::string coeffs = fmt::format(R"("spectrum sigma_a" {} "spectrum sigma_s" {} "float g" [ 0.3 ])",
                                           flat(0.3), flat(1.5));
    Rendered cl = render_string(scene(R"("string type" "cloud" "float density" [ 0 ]
  "point3 p0" [ -3 -3 -0.5 ] "point3 p1" [ 3 0 0 ] )" + coeffs));
    Rendered homo = render_string(scene(R"("string type" "homogeneous" )" + coeffs));
    MeanSe a = mean_se(cl.y), b = mean_se(homo.y);
    EXPECT_GT(b.mean, 0.01);
    EXPECT_NEAR(a.mean, b.mean, kZ * std::hypot(a.se, b.se)) << a.se << " " << b.se;
    // The default cloud (noise, wispiness) over [0, 1]^3, seen through its unit box.
    Rendered noisy = render_string(ortho_header(16, 20) + fmt::format(R"(
LightSource "distant" "point3 from" [ 0.3 -0.2 1 ] "point3 to" [ 0 0 0 ] "float illuminance" [ 5 ]
MakeNamedMedium "c" "string type" "cloud" "float density" [ 3 ]
MediumInterface "c" ""
Material "interface"
Translate -0.5 -0.5 -0.5
{}
)",
                                                                      box(0, 0, 0, 1, 1, 1)));
    EXPECT_EQ(noisy.stats.nonfinite, 0u);
    EXPECT_GT(mean_se(noisy.y).mean, 0);
}

// Delta and ratio tracking draw their collisions from streams keyed by the sampler's values
// (and the shadow ray), so a scene with media renders the same bits on any number of threads.
TEST(Media, SameImageOnOneAndTwoThreads) {
    std::string scene = ortho_header(8, 20) + fmt::format(R"(
LightSource "distant" "point3 from" [ 0.3 0.2 1 ] "point3 to" [ 0 0 0 ] "float illuminance" [ 5 ]
MakeNamedMedium "slab" "string type" "homogeneous" "rgb sigma_a" [ 0.1 0.4 0.9 ]
  "rgb sigma_s" [ 1.5 1 0.5 ] "float g" [ 0.3 ]
MediumInterface "slab" ""
Material "interface"
{}
MediumInterface "" ""
Material "diffuse"
Shape "sphere" "float radius" [ 0.3 ]
)",
                                                          box(-5, -5, -1, 5, 5, 0));
    Rendered a = render_string(scene, 1), b = render_string(scene, 2);
    ASSERT_EQ(a.rgb.data.size(), b.rgb.data.size());
    EXPECT_TRUE(a.rgb.data == b.rgb.data);
    EXPECT_GT(mean_se(a.y).mean, 0);
}

// ---- meters in media (Meter is a steradian extension; docs/photometry.md) ---------------
// A meter's points are in the outside medium of the MediumInterface at its directive.

const char* kMeterHeader = R"(
Camera "perspective"
Film "rgb" "integer xresolution" [ 8 ] "integer yresolution" [ 8 ] "string filename" "x.exr"
Integrator "volpath"
WorldBegin
)";

/// `v` within kZ standard errors of `expected` (and the standard error itself small enough
/// for the check to mean something).
void expect_reading(const MeasureResult& r, const std::string& name, double expected,
                    double max_rel_se = 0.01) {
    for (const MeterReading& m : r.readings) {
        if (m.meter.name != name) continue;
        {
            ASSERT_EQ(m.values.size(), 1u);
            const double v = m.values[0], se = m.stderrs[0];
            EXPECT_NEAR(v, expected, std::max(kZ * se, 1e-9 * std::abs(expected)))
                << name << ": se " << se;
            if (expected != 0) {
                EXPECT_LT(se, max_rel_se * std::abs(expected)) << name;
            }
            return;
        }
    }
    ADD_FAILURE() << "no meter " << name;
}

double reading(const MeasureResult& r, const std::string& name) {
    for (const MeterReading& m : r.readings)
        if (m.meter.name == name) return m.values[0];
    ADD_FAILURE() << "no meter " << name;
    return 0;
}

// A point light of 1 cd at height 2 above a homogeneous fog filling z < 1, and an
// illuminance meter in the fog at the origin facing it: the light that reaches it unscattered
// crossed 1 m of fog, E_direct = exp(-sigma_t) / 2^2 lx (Beer-Lambert and the inverse-square
// law). A purely absorbing fog adds nothing else (the indirect component is exactly 0); a
// scattering one adds light scattered towards the meter, and "all" = direct + indirect. A
// meter in the vacuum above the fog, facing the light 0.5 m away, reads 1 / 0.5^2 = 4 lx.
TEST(Media, IlluminanceMetersInFogSeeBeerLambert) {
    for (double sigma_s : {0.0, 0.5}) {
        const double sigma_a = 0.4, sigma_t = sigma_a + sigma_s;
        std::string meters;
        for (const char* c : {"all", "direct", "indirect"})
            meters += fmt::format("Meter \"illuminance\" \"string name\" \"{0}\" \"string "
                                  "component\" \"{0}\" \"point3 p\" [ 0 0 0 ] \"normal n\" "
                                  "[ 0 0 1 ]\n",
                                  c);
        std::string s = kMeterHeader + fmt::format(R"(
MakeNamedMedium "fog" "string type" "homogeneous" "spectrum sigma_a" {} "spectrum sigma_s" {}
AttributeBegin
  MediumInterface "fog" ""
  Material "interface"
  {}
AttributeEnd
LightSource "point" "point3 from" [ 0 0 2 ] "spectrum I" {}
MediumInterface "" "fog"
{}MediumInterface "" ""
Meter "illuminance" "string name" "vacuum" "point3 p" [ 0 0 1.5 ] "normal n" [ 0 0 1 ]
)",
                                                   flat(sigma_a), flat(sigma_s),
                                                   box(-20, -20, -20, 20, 20, 1), flat(1), meters);
        MeasureResult r = measure_string(s, 4e-3);
        const double direct = std::exp(-sigma_t) / 4;
        expect_reading(r, "direct", direct);
        expect_reading(r, "vacuum", 4.0);
        if (sigma_s == 0) {
            expect_reading(r, "all", direct);
            expect_reading(r, "indirect", 0.0);
        } else {
            const double ind = reading(r, "indirect");
            EXPECT_GT(ind, 0.05 * direct);  // the scattered light is there, and counted
            expect_reading(r, "all", direct + ind, 0.02);
        }
    }
}

// An albedo-1 fog in a sphere of radius R under a uniform sky of 1 cd/m^2: radiance is 1
// cd/m^2 everywhere and in every direction, so an illuminance meter at the centre reads
// E = pi lx in all; the unscattered part crossed R in every direction, pi exp(-sigma_s R);
// the rest is the indirect component (any g).
TEST(Media, IlluminanceMeterInAnAlbedoOneFurnaceSplitsIntoItsComponents) {
    for (double g : {0.0, 0.7}) {
        const double sigma_s = 2, R = 1;
        std::string s = kMeterHeader + fmt::format(R"(
LightSource "infinite" "spectrum L" {}
MakeNamedMedium "cloud" "string type" "homogeneous" "spectrum sigma_a" {} "spectrum sigma_s" {}
  "float g" [ {} ]
AttributeBegin
  MediumInterface "cloud" ""
  Material "interface"
  Shape "sphere" "float radius" [ {} ]
AttributeEnd
MediumInterface "" "cloud"
Meter "illuminance" "string name" "all" "point3 p" [ 0 0 0 ] "normal n" [ 0.6 0 0.8 ]
Meter "illuminance" "string name" "direct" "string component" "direct" "point3 p" [ 0 0 0 ]
  "normal n" [ 0.6 0 0.8 ]
Meter "illuminance" "string name" "indirect" "string component" "indirect" "point3 p" [ 0 0 0 ]
  "normal n" [ 0.6 0 0.8 ]
)",
                                                   flat(1), flat(0), flat(sigma_s), g, R);
        MeasureResult r = measure_string(s, 4e-3);
        const double direct = kPi * std::exp(-sigma_s * R);
        expect_reading(r, "all", kPi);
        expect_reading(r, "direct", direct);
        expect_reading(r, "indirect", kPi - direct);
    }
}

/// pbrt-v4's BlackbodySpectrum at T (Planck's law normalised to its peak, Wien's
/// displacement constant b = 2.897771955e-3 m K), integrated against CIE 1931 ybar at 1 nm
/// over 360..830 nm: the luminance (cd/m^2, docs/units.md) of that emission spectrum.
double blackbody_luminance(double t) {
    auto planck = [](double lambda_nm, double temp) {
        const double h = 6.62607015e-34, c = 299792458, kb = 1.380649e-23;
        const double l = lambda_nm * 1e-9;
        return 2 * h * c * c / (std::pow(l, 5) * (std::exp(h * c / (l * kb * temp)) - 1));
    };
    const double peak = planck(2.897771955e-3 / t * 1e9, t);
    double sum = 0;
    for (int l = 360; l <= 830; ++l) sum += planck(l, t) / peak * cie_y()(Float(l));
    return sum;
}

// A luminance meter looking through a purely absorbing, emitting slab of thickness D at a
// black background sees L = Le (1 - exp(-sigma_a D)) (the emission-absorption solution of
// radiative transfer), with pbrt-v4's normalisations of Le: a "spectrum Le" is scaled to
// 1 cd/m^2 times "Lescale" (homogeneous and uniformgrid media); a temperature grid emits
// Lescale x the peak-normalised blackbody; an rgbgrid's "rgb Le" (c, c, c) is c times the
// colour space's illuminant, whose ybar integral pbrt-v4 fixes at CIE_Y_integral =
// 106.856895 (not normalised to 1 cd/m^2). (An rgbgrid without "sigma_s" scatters with
// sigma_s = 1, as pbrt-v4's: the test gives zeros.)
TEST(Media, LuminanceMeterThroughEmittingSlabs) {
    const double D = 0.8;
    auto measure_slab = [&](const std::string& medium) {
        std::string s = kMeterHeader + fmt::format(R"(
MakeNamedMedium "glow" {}
AttributeBegin
  MediumInterface "glow" ""
  Material "interface"
  {}
AttributeEnd
Meter "luminance" "string name" "L" "point3 p" [ 0 0 3 ] "vector3 direction" [ 0 0 -1 ]
  "float coneangle" [ 0 ]
)",
                                                   medium, box(-2, -2, -D, 2, 2, 0));
        return measure_string(s, 4e-3);
    };
    auto eight = [](const std::string& v) {
        std::string out;
        for (int i = 0; i < 8; ++i) out += v + " ";
        return out;
    };
    const std::string grid = R"("integer nx" [ 2 ] "integer ny" [ 2 ] "integer nz" [ 2 ]
  "point3 p0" [ -5 -5 -5 ] "point3 p1" [ 5 5 5 ])";
    {
        SCOPED_TRACE("homogeneous Le");
        MeasureResult r = measure_slab(fmt::format(
            R"("string type" "homogeneous" "spectrum sigma_a" {} "spectrum sigma_s" {}
  "blackbody Le" [ 4000 ] "float Lescale" [ 2 ])",
            flat(0.7), flat(0)));
        expect_reading(r, "L", 2 * (1 - std::exp(-0.7 * D)));
    }
    {
        SCOPED_TRACE("uniformgrid Le");
        MeasureResult r = measure_slab(fmt::format(
            R"("string type" "uniformgrid" {} "float density" [ {} ] "spectrum sigma_a" {}
  "spectrum sigma_s" {} "spectrum Le" [ 400 1 700 3 ] "float Lescale" [ {} ])",
            grid, eight("1.5"), flat(0.7), flat(0), eight("2")));
        expect_reading(r, "L", 2 * (1 - std::exp(-0.7 * 1.5 * D)));
    }
    {
        SCOPED_TRACE("uniformgrid temperature");
        MeasureResult r = measure_slab(fmt::format(
            R"("string type" "uniformgrid" {} "float density" [ {} ] "spectrum sigma_a" {}
  "spectrum sigma_s" {} "float temperature" [ {} ] "float Lescale" [ {} ])",
            grid, eight("1.5"), flat(0.7), flat(0), eight("2500"), eight("0.5")));
        expect_reading(r, "L", 0.5 * blackbody_luminance(2500) * (1 - std::exp(-0.7 * 1.5 * D)));
    }
    {
        SCOPED_TRACE("rgbgrid Le");
        MeasureResult r = measure_slab(fmt::format(
            R"("string type" "rgbgrid" {} "rgb sigma_a" [ {} ] "rgb sigma_s" [ {} ]
  "rgb Le" [ {} ] "float Lescale" [ 2 ])",
            grid, eight("0.7 0.7 0.7"), eight("0 0 0"), eight("0.25 0.25 0.25")));
        expect_reading(r, "L", 2 * 0.25 * 106.856895 * (1 - std::exp(-0.7 * D)));
    }
}

TEST(Media, ErrorsAreLocated) {
    auto expect_error = [](const std::string& world, const std::string& what) {
        std::string scene = ortho_header(1, 1) + world;
        try {
            render_string(scene);
            ADD_FAILURE() << "expected an error: " << what;
        } catch (const Error& e) {
            EXPECT_NE(std::string(e.what()).find(what), std::string::npos) << e.what();
            EXPECT_NE(std::string(e.what()).find("<test>:"), std::string::npos) << e.what();
        }
    };
    expect_error("MediumInterface \"fog\" \"\"\nShape \"sphere\"\n",
                 "medium \"fog\" is not defined");
    expect_error("MakeNamedMedium \"m\" \"string type\" \"homogeneous\" \"float g\" [ 1 ]\n",
                 "\"g\"");
    expect_error(
        "MakeNamedMedium \"m\" \"string type\" \"homogeneous\" \"string preset\" \"Nope\"\n",
        "unknown medium preset");
    expect_error(
        "MakeNamedMedium \"m\" \"string type\" \"uniformgrid\" \"float density\" [ 1 2 3 ]"
        " \"integer nx\" [ 2 ]\n",
        "expected nx * ny * nz");
    expect_error("MakeNamedMedium \"m\" \"string type\" \"fancy\"\n", "unknown medium type");
    // A list of colours is for an rgbgrid's grids; a spectrum parameter takes one.
    expect_error("Material \"diffuse\" \"rgb reflectance\" [ 0.5 0.5 0.5  0.2 0.2 0.2 ]\n"
                 "Shape \"sphere\"\n",
                 "exactly 3");
    expect_error("MakeNamedMedium \"m\" \"string type\" \"homogeneous\" \"float foo\" [ 1 ]\n",
                 "foo");
    // pbrt-v4's CloudMedium reads no "scale" (its ReportUnused rejects one).
    expect_error("MakeNamedMedium \"m\" \"string type\" \"cloud\" \"float scale\" [ 2 ]\n",
                 "unused parameter \"float scale\"");
    expect_error("MakeNamedMedium \"m\" \"string type\" \"cloud\" \"point3 p1\" [ 0 1 1 ]\n",
                 "not a box");
    expect_error("MakeNamedMedium \"m\" \"string type\" \"nanovdb\"\n", "\"string filename\"");
    expect_error("MakeNamedMedium \"m\" \"string type\" \"nanovdb\" \"string filename\" \"no.nvdb\"\n",
                 "no.nvdb");
}

}  // namespace
}  // namespace sr::test
