// The radiosity integrator (integrators/radiosity/, docs/radiosity.md) on the CIE 171:2006
// cases with closed-form answers: 5.8 (interreflections in a closed cube: the face-averaged
// indirect illuminance is rho Phi / (S (1 - rho))) and 5.3 (direct light of a Lambertian
// panel), the energy balance of the solution itself, and its independence of the thread
// count. Tolerances: the issue's (0.2 % and 0.1 % of the closed form), with the gather's
// standard error required to be well inside them; fixed seeds (deterministic).
#include <gtest/gtest.h>

#include <array>
#include <cstdio>
#include <cstring>
#include <fstream>
#include <iterator>
#include <map>
#include <numbers>

#include <fmt/format.h>

#include "steradian/core/error.h"
#include "steradian/integrators/measure.h"
#include "steradian/integrators/radiosity/radiosity.h"
#include "steradian/scene/build.h"
#include "steradian/scene/pbrt/parser.h"
#include "steradian/spectrum/spectrum.h"
#include "support/render_util.h"

namespace sr::test {
namespace {

const std::string kCie = std::string(STERADIAN_SOURCE_DIR) + "/tests/data/cie171/";

Scene load(const std::string& name) { return build_scene(parse_pbrt_file(kCie + name), {}); }

MeasureResult measure_radiosity(const Scene& s, const RadiositySolution& sol, double rel_error) {
    MeasureOptions o;
    o.rel_error = rel_error;
    o.threads = 2;
    o.radiosity = &sol;
    return measure(s, o);
}

/// Radiosity's readings agree with the path tracer's (both solve the same transport where
/// every surface is diffuse) within the issue's 1 % per point plus three combined standard
/// errors.
void expect_agreement(const MeasureResult& rad, const MeasureResult& path) {
    ASSERT_EQ(rad.readings.size(), path.readings.size());
    for (size_t m = 0; m < rad.readings.size(); ++m)
        for (size_t i = 0; i < rad.readings[m].values.size(); ++i) {
            SCOPED_TRACE(rad.readings[m].meter.name + " " + std::to_string(i));
            const double r = rad.readings[m].values[i], p = path.readings[m].values[i];
            const double se = std::hypot(rad.readings[m].stderrs[i], path.readings[m].stderrs[i]);
            EXPECT_NEAR(r, p, 0.01 * p + 3 * se);
        }
}

/// Photopic reflected flux of the solution, sum over patch sides of A B (lm).
double reflected_flux(const RadiositySolution& sol) {
    double total = 0;
    for (const auto& p : sol.patches())
        for (int u : p.unknown) {
            if (u < 0) continue;
            double y = 0;
            for (int k = 0; k < radiosity::kBands; ++k) {
                const Float l = radiosity::band_lambda(k);
                y += double(cie_y()(l)) * double(sol.band(u, k)) * radiosity::kStepNm *
                     ((k == 0 || k == radiosity::kBands - 1) ? 0.5 : 1.0);
            }
            total += p.area * y;
        }
    return total;
}

class RadiosityCase5_8 : public ::testing::TestWithParam<double> {};

// Energy balance (CIE 171:2006 5.8): the direct flux Phi lands on the walls; each
// reflection returns rho of it, so the reflected flux is rho Phi / (1 - rho) and the
// face-averaged indirect illuminance rho Phi / (S (1 - rho)), S = 96 m^2.
TEST_P(RadiosityCase5_8, FaceAveragedIndirectIlluminance) {
    const double rho = GetParam();
    Scene s = load(fmt::format("case-5.8-rho{}.pbrt", rho));
    RadiosityParams prm;
    prm.max_patches = 1024;
    auto sol = solve_radiosity(s, prm, 2);
    const double phi = 10000, S = 96;
    // The solution alone: its reflected flux, within 0.2 % (the 10-nm band sum of V(lambda)
    // against the continuous 1 lm = 1 cd sr normalisation is part of that budget).
    const double flux = reflected_flux(*sol);
    EXPECT_NEAR(flux, rho * phi / (1 - rho), 2e-3 * rho * phi / (1 - rho)) << "rho " << rho;
    EXPECT_LE(sol->stats().residual, 1e-6);
    // The meters: indirect by the final gather, direct by light sampling.
    MeasureResult r = measure_radiosity(s, *sol, 4e-4);
    ASSERT_EQ(r.readings.size(), 2u);
    EXPECT_EQ(r.method, "radiosity");
    const MeterReading& ind = r.readings[0];
    const MeterReading& dir = r.readings[1];
    const double expected = rho * phi / (S * (1 - rho));
    EXPECT_TRUE(r.all_converged);
    EXPECT_LE(ind.avg_stderr, 5e-4 * expected);
    EXPECT_NEAR(ind.avg, expected, 2e-3 * expected) << "rho " << rho;
    EXPECT_NEAR(dir.avg, phi / S, 2e-3 * phi / S);
}

INSTANTIATE_TEST_SUITE_P(Reflectances, RadiosityCase5_8, ::testing::Values(0.2, 0.5, 0.8, 0.95));

// The secondary gather's own estimate (direct light by one light sample at the gather ray's
// hit, the rest by one more gather ray reading the solution) computing every first hit
// ("gatherdistance" far beyond the room): the floor's average indirect illuminance of case
// 5.8 (rho 0.5) is still rho Phi / (S (1 - rho)) within the solution's 0.2 % plus three
// standard errors. A secondary estimate that lost or double-counted the direct light at the
// hit (a quarter of the light leaving it here) would be off by percents.
TEST(Radiosity, SecondaryGatherEverywhereKeepsCase5_8) {
    Scene s = load("case-5.8-rho0.5.pbrt");
    s.integrator.radiosity.gather_distance = 100;
    RadiosityParams prm;
    prm.max_patches = 1024;
    auto sol = solve_radiosity(s, prm, 2);
    MeasureResult r = measure_radiosity(s, *sol, 1e-3);
    const double expected = 0.5 * 10000 / (96 * 0.5);
    const MeterReading& ind = r.readings[0];
    EXPECT_TRUE(r.all_converged);
    EXPECT_NEAR(ind.avg, expected, 2e-3 * expected + 3 * ind.avg_stderr);
}

TEST(Radiosity, RefusesANegativeGatherDistance) {
    try {
        build_scene(parse_pbrt_string("Integrator \"radiosity\" \"float gatherdistance\" [ -1 ]\n"
                                      "WorldBegin\n",
                                      "<test>"),
                    {});
        ADD_FAILURE() << "no error";
    } catch (const Error& e) {
        const std::string what = e.what();
        EXPECT_NE(what.find("<test>:1"), std::string::npos) << what;
        EXPECT_NE(what.find("gatherdistance"), std::string::npos) << what;
    }
}

// 5.3: the room is black, so the radiosity pass has nothing to solve and every reading is
// direct light, within 0.1 % of the published values.
TEST(Radiosity, Case5_3AreaSourceInBlackRoom) {
    Scene s = load("case-5.3.pbrt");
    auto sol = solve_radiosity(s, RadiosityParams{}, 2);
    EXPECT_EQ(sol->stats().unknowns, 0u);
    MeasureResult r = measure_radiosity(s, *sol, 3e-4);
    ASSERT_EQ(r.readings.size(), 2u);
    const double floor[] = {61.424, 79.255, 95.667, 105.778};
    const double wall[] = {32.677, 75.194, 81.323, 69.061, 53.404, 40.002};
    for (size_t i = 0; i < 4; ++i) {
        SCOPED_TRACE(i);
        EXPECT_NEAR(r.readings[0].values[i], floor[i], 1e-3 * floor[i]);
    }
    for (size_t i = 0; i < 6; ++i) {
        SCOPED_TRACE(i);
        EXPECT_NEAR(r.readings[1].values[i], wall[i], 1e-3 * wall[i]);
    }
}

TEST(Radiosity, SolutionDoesNotDependOnTheThreadCount) {
    Scene s = load("case-5.8-rho0.5.pbrt");
    RadiosityParams prm;
    prm.max_patches = 300;
    auto a = solve_radiosity(s, prm, 1);
    auto b = solve_radiosity(s, prm, 2);
    ASSERT_EQ(a->stats().unknowns, b->stats().unknowns);
    for (size_t u = 0; u < a->stats().unknowns; ++u)
        for (int k = 0; k < radiosity::kBands; ++k)
            ASSERT_EQ(a->band(int(u), k), b->band(int(u), k));
    // Curved shapes in object instances, the solution read interpolated.
    Scene c = build_scene(parse_pbrt_string(R"(Camera "perspective"
Film "rgb" "integer xresolution" [ 8 ] "integer yresolution" [ 8 ] "string filename" "x.exr"
Integrator "radiosity" "integer maxpatches" [ 2048 ] "bool interpolate" true
WorldBegin
Material "diffuse" "spectrum reflectance" [ 360 0.5 830 0.5 ]
Shape "trianglemesh" "point3 P" [ -3 -3 0 3 -3 0 3 3 0 -3 3 0 ] "integer indices" [ 0 1 2 0 2 3 ]
ObjectBegin "stool"
  Translate 0 0 0.5
  Shape "disk" "float radius" [ 0.4 ]
  Shape "cylinder" "float radius" [ 0.05 ] "float zmin" [ -0.5 ] "float zmax" [ 0 ]
  Translate 0 0 0.6
  Shape "sphere" "float radius" [ 0.3 ] "float zmax" [ 0.2 ]
ObjectEnd
AttributeBegin Translate -1 0 0 ObjectInstance "stool" AttributeEnd
AttributeBegin Translate 1 0.5 0 Rotate 30 0 0 1 ObjectInstance "stool" AttributeEnd
AttributeBegin
  Translate 0 0 3
  LightSource "point" "float power" [ 1000 ]
AttributeEnd
)", "<test>"), {});
    auto c1 = solve_radiosity(c, c.integrator.radiosity, 1);
    auto c2 = solve_radiosity(c, c.integrator.radiosity, 2);
    EXPECT_GT(c1->stats().diffuse_triangles, 2u);
    EXPECT_EQ(c1->digest(), c2->digest());
}

// The exported mesh: per face the patch's photopic exitance (the solution: its area sum is
// the reflected flux), per vertex the mean of the surface's patches there (so within the
// range of the face values, and smooth: equal at a shared corner).
TEST(Radiosity, MeshExportCarriesTheSolution) {
    Scene s = load("case-5.8-rho0.5.pbrt");
    RadiosityParams prm;
    prm.max_patches = 300;
    auto sol = solve_radiosity(s, prm, 2);
    const std::string path = ::testing::TempDir() + "radiosity_mesh_test.ply";
    write_radiosity_ply(*sol, path);
    std::ifstream in(path, std::ios::binary);
    const std::string data((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
    const size_t h = data.find("end_header\n");
    ASSERT_NE(h, std::string::npos);
    const size_t np = sol->patches().size();
    ASSERT_NE(data.find(fmt::format("element vertex {}\n", 3 * np)), std::string::npos);
    ASSERT_NE(data.find(fmt::format("element face {}\n", np)), std::string::npos);
    const char* v = data.data() + h + 11;
    constexpr size_t vsize = 12 + 3 + 4, fsize = 1 + 12 + 4;
    ASSERT_EQ(data.size(), h + 11 + 3 * np * vsize + np * fsize);
    auto f32 = [](const char* p) {
        float x;
        std::memcpy(&x, p, 4);
        return double(x);
    };
    const char* f = v + 3 * np * vsize;
    double flux = 0, lo = kInfinity, hi = 0;
    std::map<std::array<float, 3>, double> at;  // a corner's vertex exitance
    for (size_t i = 0; i < np; ++i) {
        const double e = f32(f + i * fsize + 13);
        flux += sol->patches()[i].area * e;
        lo = std::min(lo, e);
        hi = std::max(hi, e);
    }
    EXPECT_NEAR(flux, reflected_flux(*sol), 1e-5 * flux);
    for (size_t i = 0; i < 3 * np; ++i) {
        const char* p = v + i * vsize;
        const double e = f32(p + 15);
        EXPECT_GE(e, lo * (1 - 1e-6));
        EXPECT_LE(e, hi * (1 + 1e-6));
        const std::array<float, 3> key{float(f32(p)), float(f32(p + 4)), float(f32(p + 8))};
        // The cube's corners and edges join different planes; compare within a face's
        // interior only (all patches of a face share plane, side and material).
        int on_boundary = 0;
        for (float c : key) on_boundary += std::abs(c) > 1.99f;
        if (on_boundary != 1) continue;
        auto [it, fresh] = at.emplace(key, e);
        if (!fresh) {
            EXPECT_EQ(it->second, e);
        }
    }
    std::remove(path.c_str());
}

TEST(Radiosity, RefusesAMeshBeyondItsPatchBudget) {
    // The cube's 12 lit triangle sides need 12 patches at least.
    Scene s = load("case-5.8-rho0.5.pbrt");
    RadiosityParams prm;
    prm.max_patches = 8;
    try {
        solve_radiosity(s, prm, 1);
        ADD_FAILURE() << "no error";
    } catch (const Error& e) {
        EXPECT_NE(std::string(e.what()).find("at least 12 patches"), std::string::npos) << e.what();
    }
    prm.max_patches = 12;
    EXPECT_EQ(solve_radiosity(s, prm, 1)->stats().unknowns, 12u);
}

TEST(Radiosity, AutoChoosesRadiosityOnlyForDiffuseScenes) {
    std::string why;
    EXPECT_TRUE(radiosity_models_exactly(load("case-5.8-rho0.5.pbrt"), &why)) << why;
    Scene glossy = build_scene(parse_pbrt_string(R"(
Camera "perspective"
Film "rgb" "integer xresolution" [ 8 ] "integer yresolution" [ 8 ] "string filename" "x.exr"
WorldBegin
Material "conductor"
Shape "trianglemesh" "point3 P" [ 0 0 0 1 0 0 1 1 0 ] "integer indices" [ 0 1 2 ]
)", "<test>"), {});
    EXPECT_FALSE(radiosity_models_exactly(glossy, &why));
    EXPECT_NE(why.find("diffuse"), std::string::npos) << why;
}

}  // namespace
}  // namespace sr::test

namespace sr::test {
namespace {

// Estimator agreement where visibility matters: a 4 x 3 x 2.5 m grey room (walls 0.5,
// floor 0.2, ceiling 0.7) with a solid 1.2 x 0.6 x 0.75 m box as a desk and a point light
// above it. Both methods solve the same transport (every surface diffuse), so they must
// agree within the issue's 1 % per point (the office criterion) plus three combined standard
// errors: points in the open, in the desk's shadow on the floor, on the desk and on a wall.
TEST(Radiosity, AgreesWithThePathTracerInAnOccludedRoom) {
    const char* scene = R"(
Camera "perspective"
Film "rgb" "integer xresolution" [ 8 ] "integer yresolution" [ 8 ] "string filename" "x.exr"
Integrator "radiosity" "integer maxpatches" [ 1500 ]
WorldBegin
Material "diffuse" "spectrum reflectance" [ 360 0.2 830 0.2 ]
Shape "trianglemesh" "point3 P" [ 0 0 0 4 0 0 4 3 0 0 3 0 ] "integer indices" [ 0 1 2 0 2 3 ]
Material "diffuse" "spectrum reflectance" [ 360 0.7 830 0.7 ]
Shape "trianglemesh" "point3 P" [ 0 0 2.5 0 3 2.5 4 3 2.5 4 0 2.5 ] "integer indices" [ 0 1 2 0 2 3 ]
Material "diffuse" "spectrum reflectance" [ 360 0.5 830 0.5 ]
Shape "trianglemesh" "point3 P" [ 0 0 0 0 0 2.5 4 0 2.5 4 0 0 ] "integer indices" [ 0 1 2 0 2 3 ]
Shape "trianglemesh" "point3 P" [ 0 3 0 4 3 0 4 3 2.5 0 3 2.5 ] "integer indices" [ 0 1 2 0 2 3 ]
Shape "trianglemesh" "point3 P" [ 0 0 0 0 3 0 0 3 2.5 0 0 2.5 ] "integer indices" [ 0 1 2 0 2 3 ]
Shape "trianglemesh" "point3 P" [ 4 0 0 4 0 2.5 4 3 2.5 4 3 0 ] "integer indices" [ 0 1 2 0 2 3 ]
Material "diffuse" "spectrum reflectance" [ 360 0.4 830 0.4 ]
# The desk: a box [1.4, 2.6] x [1.2, 1.8] x [0, 0.75], faces outwards.
Shape "trianglemesh" "point3 P" [ 1.4 1.2 0.75 2.6 1.2 0.75 2.6 1.8 0.75 1.4 1.8 0.75 ] "integer indices" [ 0 1 2 0 2 3 ]
Shape "trianglemesh" "point3 P" [ 1.4 1.2 0 2.6 1.2 0 2.6 1.2 0.75 1.4 1.2 0.75 ] "integer indices" [ 0 1 2 0 2 3 ]
Shape "trianglemesh" "point3 P" [ 1.4 1.8 0 1.4 1.8 0.75 2.6 1.8 0.75 2.6 1.8 0 ] "integer indices" [ 0 1 2 0 2 3 ]
Shape "trianglemesh" "point3 P" [ 1.4 1.2 0 1.4 1.2 0.75 1.4 1.8 0.75 1.4 1.8 0 ] "integer indices" [ 0 1 2 0 2 3 ]
Shape "trianglemesh" "point3 P" [ 2.6 1.2 0 2.6 1.8 0 2.6 1.8 0.75 2.6 1.2 0.75 ] "integer indices" [ 0 1 2 0 2 3 ]
AttributeBegin
  Translate 2.3 1.5 2.2
  LightSource "point" "float power" [ 3000 ]
AttributeEnd
Meter "illuminance" "string name" "floor" "point3 p" [ 0.6 0.6 0  2.0 1.1 0  2.7 1.5 0 ] "normal n" [ 0 0 1 ]
Meter "illuminance" "string name" "desk" "point3 p" [ 2.0 1.5 0.75 ] "normal n" [ 0 0 1 ]
Meter "illuminance" "string name" "wall" "point3 p" [ 0 1.5 1.2 ] "normal n" [ 1 0 0 ]
)";
    Scene s = build_scene(parse_pbrt_string(scene, "<test>"), {});
    std::string why;
    ASSERT_TRUE(radiosity_models_exactly(s, &why)) << why;
    auto sol = solve_radiosity(s, s.integrator.radiosity, 2);
    MeasureResult rad = measure_radiosity(s, *sol, 1e-3);
    MeasureResult path = measure_scene(s, 2e-3);
    expect_agreement(rad, path);
}

}  // namespace
}  // namespace sr::test

namespace sr::test {
namespace {

// The proof scene of the radiosity method (docs/radiosity.md, "Accuracy"): the furnished
// office of scenes/office.pbrt, its 20 x 20 working-plane grid measured by radiosity and by
// the path tracer in the same run. Both solve the same transport (every surface is diffuse),
// so they must agree within the issue's 1 % at every point and 0.3 % on average, plus three
// combined standard errors (the path tracer's at a 0.5 % target, affordable here; the
// full-precision comparison is bench/radiosity.sh's).
TEST(Radiosity, OfficeWorkingPlaneAgreesWithThePathTracer) {
    Scene s = build_scene(
        parse_pbrt_file(std::string(STERADIAN_SOURCE_DIR) + "/scenes/office.pbrt"), {});
    std::erase_if(s.meters, [](const Meter& m) { return m.name != "working-plane"; });
    ASSERT_EQ(s.meters.size(), 1u);
    ASSERT_EQ(s.meters[0].points.size(), 400u);
    std::string why;
    ASSERT_TRUE(radiosity_models_exactly(s, &why)) << why;
    auto sol = solve_radiosity(s, s.integrator.radiosity, 2);
    EXPECT_LE(sol->stats().residual, double(s.integrator.radiosity.residual));
    MeasureResult rad = measure_radiosity(s, *sol, 3e-3);
    MeasureResult path = measure_scene(s, 5e-3);
    const MeterReading& r = rad.readings[0];
    const MeterReading& p = path.readings[0];
    EXPECT_EQ(r.estimator, "deterministic + monte carlo indirect");
    for (size_t i = 0; i < r.values.size(); ++i) {
        SCOPED_TRACE(i);
        const double se = std::hypot(r.stderrs[i], p.stderrs[i]);
        EXPECT_NEAR(r.values[i], p.values[i], 0.01 * p.values[i] + 3 * se);
    }
    EXPECT_NEAR(r.avg, p.avg, 3e-3 * p.avg + 3 * std::hypot(r.avg_stderr, p.avg_stderr));
}

}  // namespace
}  // namespace sr::test

namespace sr::test {
namespace {

// Curved shapes in the radiosity pass: an integrating sphere. Inside a diffuse sphere of
// area A and reflectance rho lit by a source of flux Phi anywhere inside it, the form factor
// from any point of the wall to a piece dA of it is dA / A, so the indirect irradiance at
// every point of the wall is the same, rho Phi / (A (1 - rho)), whatever the source's
// position (the integrating sphere's equation; e.g. Ohno, "Integrating sphere simulation",
// J. Illum. Eng. Soc. 23 (1994)). The meters sit 0.1 mm inside the wall (R = 2 m), facing
// inwards, at points the off-centre source lights very differently. The sphere is meshed in
// its (u, v) parameters; as an object instance, rotated and moved, the same must hold, and
// with the solution read interpolated between the patches' corners ("interpolate", with 4096
// patches allowed: the interpolation does not conserve a patch's flux, and its error falls as
// the patches' area, +0.25 % with the 192 patches of the other cases, +0.07 % with 768).
// Parameter: 0 top level, 1 instanced, 2 top level and interpolated.
class RadiosityIntegratingSphere : public ::testing::TestWithParam<int> {};

TEST_P(RadiosityIntegratingSphere, WallIndirectIlluminanceIsUniform) {
    const bool instanced = GetParam() == 1;
    const double R = 2, rho = 0.5, phi = 10000;
    std::string pts, ns;
    const double dirs[6][3] = {{1, 0, 0}, {0, -1, 0}, {0, 0, 1}, {0, 0, -1}, {-0.6, 0.8, 0}, {0.48, 0.6, -0.64}};
    for (const auto& d : dirs) {
        pts += fmt::format(" {} {} {}", 0.99995 * R * d[0], 0.99995 * R * d[1], 0.99995 * R * d[2]);
        ns += fmt::format(" {} {} {}", -d[0], -d[1], -d[2]);
    }
    const std::string sphere = fmt::format(R"(Material "diffuse" "spectrum reflectance" [ 360 {0} 830 {0} ]
Shape "sphere" "float radius" [ {1} ]
)", rho, R);
    const std::string world =
        instanced ? fmt::format(R"(ObjectBegin "ball"
Translate 0 0 5
{}ObjectEnd
AttributeBegin
  Rotate 30 1 1 0
  Translate 0 0 -5
  ObjectInstance "ball"
AttributeEnd
)", sphere)
                  : sphere;
    const std::string text = fmt::format(R"(Camera "perspective"
Film "rgb" "integer xresolution" [ 8 ] "integer yresolution" [ 8 ] "string filename" "x.exr"
Integrator "radiosity" "integer maxpatches" [ {} ] "bool interpolate" {}
WorldBegin
{}AttributeBegin
  Translate 0.6 -0.4 0.3
  LightSource "point" "float power" [ {} ]
AttributeEnd
Meter "illuminance" "string name" "wall" "string component" "indirect" "point3 p" [{}] "normal n" [{}]
)", GetParam() == 2 ? 4096 : 1024, GetParam() == 2 ? "true" : "false", world, phi, pts, ns);
    Scene s = build_scene(parse_pbrt_string(text, "<test>"), {});
    std::string why;
    ASSERT_TRUE(radiosity_models_exactly(s, &why)) << why;
    auto sol = solve_radiosity(s, s.integrator.radiosity, 2);
    EXPECT_TRUE(sol->stats().notes.empty()) << sol->stats().notes.front();
    EXPECT_EQ(sol->interpolated(), GetParam() == 2);
    // Only the inside is lit: the outside's sides are not in the system.
    EXPECT_EQ(sol->stats().unknowns, sol->stats().patches);
    // The source is enclosed: the reflected flux is rho Phi / (1 - rho) exactly.
    EXPECT_NEAR(reflected_flux(*sol), rho * phi / (1 - rho), 2e-3 * rho * phi / (1 - rho));
    MeasureResult r = measure_radiosity(s, *sol, 5e-4);
    const double A = 4 * std::numbers::pi * R * R, expected = rho * phi / (A * (1 - rho));
    const MeterReading& m = r.readings[0];
    for (size_t i = 0; i < m.values.size(); ++i) {
        SCOPED_TRACE(i);
        EXPECT_NEAR(m.values[i], expected, 2e-3 * expected + 3 * m.stderrs[i]);
    }
}

INSTANTIATE_TEST_SUITE_P(TopLevelInstancedInterpolated, RadiosityIntegratingSphere,
                         ::testing::Values(0, 1, 2));

// The outside of a sphere: alone in the dark, lit by a point source of flux Phi at distance d
// from its centre, a sphere of radius R intercepts the light of the cone of half-angle
// alpha, sin alpha = R / d: Phi (1 - cos alpha) / 2, and reflects rho of it (nothing else is
// there to return light). The solution's reflected flux must be that: the direct light is
// computed on the true surface (its chords, inside it, would catch 2-3 % less) and spread
// over the true area.
TEST(Radiosity, LoneSphereReflectsWhatItIntercepts) {
    const double R = 0.5, d = 2, rho = 0.6, phi = 10000;
    Scene s = build_scene(parse_pbrt_string(fmt::format(R"(Camera "perspective"
Film "rgb" "integer xresolution" [ 8 ] "integer yresolution" [ 8 ] "string filename" "x.exr"
WorldBegin
Material "diffuse" "spectrum reflectance" [ 360 {0} 830 {0} ]
AttributeBegin
  Rotate 40 1 2 3
  Shape "sphere" "float radius" [ {1} ]
AttributeEnd
AttributeBegin
  Translate 0 0 {2}
  LightSource "point" "float power" [ {3} ]
AttributeEnd
)", rho, R, d, phi), "<test>"), {});
    RadiosityParams prm;
    prm.max_patches = 1024;
    auto sol = solve_radiosity(s, prm, 2);
    // No side of the sphere's inside is in the system (nothing is inside it).
    EXPECT_LE(sol->stats().unknowns, sol->stats().patches);
    const double cos_alpha = std::sqrt(1 - (R / d) * (R / d));
    const double expected = rho * phi * (1 - cos_alpha) / 2;
    EXPECT_NEAR(reflected_flux(*sol), expected, 2e-3 * expected);
}

// Enclosures of partial curved shapes: a dome (a sphere cut at z = 0) on a round floor (a
// disk), and a closed can (an open cylinder with two disks for lids), each of reflectance
// rho, with a point source inside. Every ray from a surface lands on another, so the
// reflected flux is rho Phi / (1 - rho), whatever the shapes. The shapes are meshed each on
// its own (u, v) grid; where two meet, their chords need not share corners (a dome's rim
// split to another depth than the floor's), and light slipping between them would show here
// (measured: +0.01 % for both).
class RadiosityCurvedEnclosure : public ::testing::TestWithParam<int> {};

TEST_P(RadiosityCurvedEnclosure, ReflectsRhoPhiOverOneMinusRho) {
    const double rho = 0.5, phi = 10000;
    const char* shapes[2] = {
        R"(Shape "sphere" "float radius" [ 2 ] "float zmin" [ 0 ]
Shape "disk" "float radius" [ 2 ]
)",
        R"(Shape "cylinder" "float radius" [ 1 ] "float zmin" [ 0 ] "float zmax" [ 3 ]
Shape "disk" "float radius" [ 1 ]
Shape "disk" "float radius" [ 1 ] "float height" [ 3 ]
)"};
    Scene s = build_scene(parse_pbrt_string(fmt::format(R"(Camera "perspective"
Film "rgb" "integer xresolution" [ 8 ] "integer yresolution" [ 8 ] "string filename" "x.exr"
WorldBegin
Material "diffuse" "spectrum reflectance" [ 360 {0} 830 {0} ]
{1}AttributeBegin
  Translate 0.3 -0.2 0.8
  LightSource "point" "float power" [ {2} ]
AttributeEnd
)", rho, shapes[GetParam()], phi), "<test>"), {});
    RadiosityParams prm;
    prm.max_patches = 2048;
    auto sol = solve_radiosity(s, prm, 2);
    const double expected = rho * phi / (1 - rho);
    EXPECT_NEAR(reflected_flux(*sol), expected, 2e-3 * expected);
}

INSTANTIATE_TEST_SUITE_P(DomeAndCan, RadiosityCurvedEnclosure, ::testing::Values(0, 1));

// Case 5.8 (rho 0.5) with its six faces as instances of one face: the same closed form.
TEST(Radiosity, InstancedCubeKeepsCase5_8) {
    Scene s = build_scene(parse_pbrt_string(R"(Camera "perspective"
Film "rgb" "integer xresolution" [ 8 ] "integer yresolution" [ 8 ] "string filename" "x.exr"
WorldBegin
ObjectBegin "face"
Material "diffuse" "spectrum reflectance" [ 360 0.5 830 0.5 ]
Shape "trianglemesh" "point3 P" [ -2 -2 -2 2 -2 -2 2 2 -2 -2 2 -2 ] "integer indices" [ 0 1 2 0 2 3 ]
ObjectEnd
ObjectInstance "face"
AttributeBegin Rotate 180 1 0 0 ObjectInstance "face" AttributeEnd
AttributeBegin Rotate 90 1 0 0 ObjectInstance "face" AttributeEnd
AttributeBegin Rotate -90 1 0 0 ObjectInstance "face" AttributeEnd
AttributeBegin Rotate 90 0 1 0 ObjectInstance "face" AttributeEnd
AttributeBegin Rotate -90 0 1 0 ObjectInstance "face" AttributeEnd
LightSource "point" "float power" [ 10000 ]
Meter "illuminancegrid" "string name" "floor-indirect" "string component" "indirect" "point3 corner" [ -2 -2 -2 ] "vector3 u" [ 4 0 0 ] "vector3 v" [ 0 4 0 ] "integer resolution" [ 1 1 ] "bool cellaverage" true "normal n" [ 0 0 1 ]
)", "<test>"), {});
    std::string why;
    ASSERT_TRUE(radiosity_models_exactly(s, &why)) << why;
    RadiosityParams prm;
    prm.max_patches = 1024;
    auto sol = solve_radiosity(s, prm, 2);
    EXPECT_TRUE(sol->stats().notes.empty()) << sol->stats().notes.front();
    EXPECT_EQ(sol->stats().diffuse_triangles, 12u);
    const double expected = 0.5 * 10000 / (96 * 0.5);
    EXPECT_NEAR(reflected_flux(*sol), 0.5 * 10000 / 0.5, 2e-3 * 0.5 * 10000 / 0.5);
    MeasureResult r = measure_radiosity(s, *sol, 4e-4);
    const MeterReading& ind = r.readings[0];
    EXPECT_NEAR(ind.avg, expected, 2e-3 * expected + 3 * ind.avg_stderr);
}

// Estimator agreement with curved shapes seen from outside (bench/scenes/curved-room.pbrt,
// also CURVED=1 bench/radiosity.sh's): the occluded room's grey box replaced by a sphere
// resting on the floor (rho 0.8, bright, so that what it reflects counts), a column (an open
// cylinder from floor to ceiling) and a round table top (a disk).
// Radiosity meshes them in their (u, v) parameters; both methods must agree within the
// issue's 1 % per point plus three combined standard errors, beside the sphere and in its
// shadow, on the table, on the floor under it (facing the disk's underside), on the floor by
// the column and just above the sphere. (A meter just under the table facing down reads the
// floor in the table's shadow, where the floor's patches straddle the shadow's edge: +2.5 %
// with the disk and +4 % with a square table of the same area at 1500 patches, a flat-mesh
// limit that this test is not about.)
TEST(Radiosity, CurvedShapesAgreeWithThePathTracer) {
    Scene s = build_scene(
        parse_pbrt_file(std::string(STERADIAN_SOURCE_DIR) + "/bench/scenes/curved-room.pbrt"), {});
    std::string why;
    ASSERT_TRUE(radiosity_models_exactly(s, &why)) << why;
    auto sol = solve_radiosity(s, s.integrator.radiosity, 2);
    EXPECT_TRUE(sol->stats().notes.empty()) << sol->stats().notes.front();
    MeasureResult rad = measure_radiosity(s, *sol, 1e-3);
    MeasureResult path = measure_scene(s, 2e-3);
    expect_agreement(rad, path);
}

}  // namespace
}  // namespace sr::test
