// Direct light without Monte Carlo (integrators/direct_light.h) against closed forms: the
// quadrature of area lights of uniform luminance L (Lambert's polygon formula, the on-axis
// disk, the sphere), its error estimate (the reading must lie within it), visibility,
// delta lights, and the LM-63 luminous bodies: a box, cylinders, an ellipsoid and vertical
// figures whose intensity in every direction is the file's (far field) and a Lambertian
// box's near field (the polygon formula on its visible faces).
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>

#include "steradian/integrators/direct_light.h"
#include "steradian/integrators/glare.h"
#include "steradian/integrators/measure.h"
#include "steradian/scene/build.h"
#include "steradian/scene/pbrt/parser.h"
#include "support/render_util.h"

namespace sr::test {
namespace {

// Black surfaces (the emitters' own included): no light is scattered, so the readings are
// direct light alone.
const char* kHeader = R"(
Camera "perspective"
Film "rgb" "integer xresolution" [ 8 ] "integer yresolution" [ 8 ] "string filename" "x.exr"
WorldBegin
Material "diffuse" "spectrum reflectance" [ 360 0 830 0 ]
)";

struct V3 {
    double x, y, z;
};
V3 sub(V3 a, V3 b) { return {a.x - b.x, a.y - b.y, a.z - b.z}; }
double dot3(V3 a, V3 b) { return a.x * b.x + a.y * b.y + a.z * b.z; }
V3 cross3(V3 a, V3 b) { return {a.y * b.z - a.z * b.y, a.z * b.x - a.x * b.z, a.x * b.y - a.y * b.x}; }
double len3(V3 a) { return std::sqrt(dot3(a, a)); }

/// Lambert's formula: the illuminance at p (unit normal n) from a convex polygon of uniform
/// luminance L wholly above p's horizon, E = L/2 |sum_i gamma_i n . (R_i x R_i+1)/|R_i x R_i+1||,
/// R_i the directions to the vertices, gamma_i the angle between consecutive ones.
double polygon_illuminance(const std::vector<V3>& poly, V3 p, V3 n, double L) {
    double s = 0;
    for (size_t i = 0; i < poly.size(); ++i) {
        V3 a = sub(poly[i], p), b = sub(poly[(i + 1) % poly.size()], p);
        a = {a.x / len3(a), a.y / len3(a), a.z / len3(a)};
        b = {b.x / len3(b), b.y / len3(b), b.z / len3(b)};
        const V3 c = cross3(a, b);
        const double gamma = std::atan2(len3(c), dot3(a, b));
        s += gamma * dot3(n, c) / len3(c);
    }
    return L / 2 * std::abs(s);
}

class TempDir {
public:
    TempDir() {
        m_path = std::filesystem::temp_directory_path() /
                 fmt::format("steradian-direct-{}", ::testing::UnitTest::GetInstance()->random_seed());
        std::filesystem::create_directories(m_path);
    }
    ~TempDir() { std::filesystem::remove_all(m_path); }
    void write(const std::string& name, const std::string& text) const {
        std::ofstream(m_path / name) << text;
    }
    std::string dir() const { return m_path.string(); }

private:
    std::filesystem::path m_path;
};

/// Every value of the reading lies within its reported error of the expected one (and
/// that error meets the target), and it was computed deterministically.
void expect_within_error(const MeterReading& m, const std::vector<double>& expected, double rel) {
    EXPECT_EQ(m.estimator, "deterministic");
    ASSERT_EQ(m.values.size(), expected.size());
    for (size_t i = 0; i < expected.size(); ++i) {
        SCOPED_TRACE(i);
        EXPECT_TRUE(m.converged[i]);
        EXPECT_LE(m.stderrs[i], rel * expected[i]);
        EXPECT_NEAR(m.values[i], expected[i], m.stderrs[i]);
    }
}

// A 1 x 1 m square of 1000 cd/m^2 at z = 3 facing down; receivers on the floor, on a wall
// and 5 cm under the square's corner (where the integrand is sharply peaked).
TEST(DirectLight, RectangleAgreesWithLambertsPolygonFormula) {
    const std::string s = std::string(kHeader) +
        "AttributeBegin\n AreaLightSource \"diffuse\" \"float scale\" [ 1000 ]\n"
        " Shape \"trianglemesh\" \"point3 P\" [ 1.5 1.5 3  1.5 2.5 3  2.5 2.5 3  2.5 1.5 3 ] "
        "\"integer indices\" [ 0 1 2 0 2 3 ]\nAttributeEnd\n"
        "Meter \"illuminance\" \"point3 p\" [ 2 0.25 0  2 2 0  0 0 0  1.5 1.5 2.95  2.2 2.1 2.5 ] "
        "\"normal n\" [ 0 0 1 ]\n"
        "Meter \"illuminance\" \"point3 p\" [ 2 0 2.75  2 0 0.25 ] \"normal n\" [ 0 1 0 ]\n";
    for (double rel : {1e-3, 1e-5}) {
        SCOPED_TRACE(rel);
        MeasureResult r = measure_string(s, rel);
        const std::vector<V3> sq = {{1.5, 1.5, 3}, {1.5, 2.5, 3}, {2.5, 2.5, 3}, {2.5, 1.5, 3}};
        std::vector<double> floor, wall;
        for (V3 p : {V3{2, 0.25, 0}, V3{2, 2, 0}, V3{0, 0, 0}, V3{1.5, 1.5, 2.95}, V3{2.2, 2.1, 2.5}})
            floor.push_back(polygon_illuminance(sq, p, {0, 0, 1}, 1000));
        for (V3 p : {V3{2, 0, 2.75}, V3{2, 0, 0.25}})
            wall.push_back(polygon_illuminance(sq, p, {0, 1, 0}, 1000));
        expect_within_error(r.readings[0], floor, rel);
        expect_within_error(r.readings[1], wall, rel);
        EXPECT_EQ(r.paths, 0u);
    }
}

// A disk of radius R and luminance L facing a receiver on its axis at distance d:
// E = pi L R^2 / (R^2 + d^2). A sphere of radius R seen from a receiver facing its centre
// at distance d (wholly above the horizon): E = pi L (R / d)^2.
TEST(DirectLight, DiskOnAxisAndSphere) {
    const std::string disk_scene = std::string(kHeader) +
        "AttributeBegin\n Translate 0 0 2\n AreaLightSource \"diffuse\" \"float scale\" [ 500 ] "
        "\"bool twosided\" true\n Shape \"disk\" \"float radius\" 0.4\nAttributeEnd\n"
        "Meter \"illuminance\" \"point3 p\" [ 0 0 0  0 0 1.9  0 0 3 ] \"normal n\" [ 0 0 1  0 0 1  0 0 -1 ]\n";
    auto disk = [](double d) { return kPi * 500 * 0.16 / (0.16 + d * d); };
    expect_within_error(measure_string(disk_scene, 1e-5).readings[0], {disk(2), disk(0.1), disk(1)},
                        1e-5);
    const std::string sphere_scene = std::string(kHeader) +
        "AttributeBegin\n Translate 10 0 0\n AreaLightSource \"diffuse\" \"float scale\" [ 200 ]\n"
        " Shape \"sphere\" \"float radius\" 0.3\nAttributeEnd\n"
        "Meter \"illuminance\" \"point3 p\" [ 8 0 0  10 0 -0.5 ] \"normal n\" [ 1 0 0  0 0 1 ]\n";
    auto sphere = [](double d) { return kPi * 200 * sqr(0.3 / d); };
    expect_within_error(measure_string(sphere_scene, 1e-5).readings[0], {sphere(2), sphere(0.5)},
                        1e-5);
}

// Visibility per node: a point light behind a blocker reads exactly 0; an opaque half-plane
// just below a disk light covers exactly the half x < 0 of it as seen from a point on its
// axis (the half-plane contains the axis' foot), so E is half the on-axis value.
TEST(DirectLight, ShadowsPerNode) {
    const std::string point_scene = std::string(kHeader) +
        "LightSource \"point\" \"point3 from\" [ 5 5 1 ] \"float scale\" 100\n"
        "Shape \"trianglemesh\" \"point3 P\" [ 4 4 0.5  6 4 0.5  6 6 0.5  4 6 0.5 ] "
        "\"integer indices\" [ 0 1 2 0 2 3 ]\n"
        "Meter \"illuminance\" \"point3 p\" [ 5 5 0 ] \"normal n\" [ 0 0 1 ]\n";
    MeasureResult r = measure_string(point_scene, 1e-4);
    EXPECT_EQ(r.readings[0].values[0], 0.0);
    EXPECT_EQ(r.readings[0].stderrs[0], 0.0);
    EXPECT_TRUE(r.readings[0].exact[0]);
    const std::string disk_scene = std::string(kHeader) +
        "AttributeBegin\n Translate 0 0 2\n AreaLightSource \"diffuse\" \"float scale\" [ 500 ] "
        "\"bool twosided\" true\n Shape \"disk\" \"float radius\" 0.4\nAttributeEnd\n"
        "Shape \"trianglemesh\" \"point3 P\" [ -3 -3 1.9  0 -3 1.9  0 3 1.9  -3 3 1.9 ] "
        "\"integer indices\" [ 0 1 2 0 2 3 ]\n"
        "Meter \"illuminance\" \"point3 p\" [ 0 0 0 ] \"normal n\" [ 0 0 1 ]\n";
    r = measure_string(disk_scene, 1e-4);
    const double half = kPi * 500 * 0.16 / (0.16 + 4) / 2;
    const MeterReading& m = r.readings[0];
    EXPECT_NEAR(m.values[0], half, std::max(m.stderrs[0], 1e-4 * half));
    EXPECT_LE(m.stderrs[0], 1e-4 * half);
}

// Delta lights: exact. A point light of intensity I at height h over a receiver tilted by
// theta: E = I cos(theta) / h^2; a spot light inside its inner cone likewise and 0 outside
// its outer cone.
TEST(DirectLight, DeltaLightsAreExact) {
    const std::string s = std::string(kHeader) +
        "LightSource \"point\" \"point3 from\" [ 0 0 2 ] \"float scale\" 100\n"
        "LightSource \"spot\" \"point3 from\" [ 10 0 2 ] \"point3 to\" [ 10 0 0 ] "
        "\"float coneangle\" 20 \"float conedeltaangle\" 5 \"float scale\" 50\n"
        "Meter \"illuminance\" \"point3 p\" [ 0 0 0  0 0 0  10 0 0  10 3 0 ] "
        "\"normal n\" [ 0 0 1  0.6 0 0.8  0 0 1  0 0 1 ]\n";
    MeasureResult r = measure_string(s, 1e-3);
    const MeterReading& m = r.readings[0];
    // The spot is 10 m from the point light, whose light also reaches the spot's points.
    const double from_point_at_10 = 100.0 * 2 / std::pow(104.0, 1.5);
    const double from_point_at_10_3 = 100.0 * 2 / std::pow(113.0, 1.5);
    const std::vector<double> want = {25.0, 25.0 * 0.8,
                                      12.5 + from_point_at_10, from_point_at_10_3};
    for (size_t i = 0; i < want.size(); ++i) {
        SCOPED_TRACE(i);
        EXPECT_TRUE(m.exact[i]);
        EXPECT_EQ(m.stderrs[i], 0.0);
    }
    EXPECT_NEAR(m.values[0], want[0], 1e-6 * want[0]);
    EXPECT_NEAR(m.values[1], want[1], 1e-6 * want[1]);
    EXPECT_NEAR(m.values[2], want[2], 1e-6 * want[2]);
    EXPECT_NEAR(m.values[3], want[3], 1e-6 * want[3]);
}

// ---- LM-63 luminous shapes ----------------------------------------------------------------

/// An IES file (LM-63-2002, Type C, absolute) of width W, length L, height H (signed, m)
/// whose intensity is f(gamma, C) on gamma 0..180 and C 0..90 (quadrant symmetry) in
/// 0.5-degree steps.
std::string ies_of(double w, double l, double h, const std::function<double(double, double)>& f) {
    std::string s = fmt::format("IESNA:LM-63-2002\n[TEST] shape\nTILT=NONE\n1 -1 1 361 181 1 2 {} {} {}\n1 1 0\n",
                                w, l, h);
    for (int i = 0; i <= 360; ++i) s += fmt::format("{} ", 0.5 * i);
    s += "\n";
    for (int j = 0; j <= 180; ++j) s += fmt::format("{} ", 0.5 * j);
    s += "\n";
    for (int j = 0; j <= 180; ++j) {
        for (int i = 0; i <= 360; ++i) s += fmt::format("{:.9g} ", f(radians(0.5 * i), radians(0.5 * j)));
        s += "\n";
    }
    return s;
}

/// The luminaire-frame direction of Type C angles: (sin g cos C, sin g sin C, -cos g).
V3 dir_c(double g, double c) { return {std::sin(g) * std::cos(c), std::sin(g) * std::sin(c), -std::cos(g)}; }

// Far field: the body's intensity in every direction is the file's, whatever its shape: a
// receiver at distance d = 100 m facing the luminaire reads I(w) / d^2 up to the body's
// size over d squared (under 2e-5 here). The distribution: I = 100 + 80 cos(gamma) + 30
// sin(gamma) cos(C), smooth over the quadrant; its bilinear table at 0.5-degree steps is
// within h^2/8 (|I_gg| + |I_CC|) = 1e-3 cd of it (h = 0.0087 rad), under 3e-5 relative.
TEST(LuminousShapes, EveryBodyEmitsTheFilesIntensity) {
    auto I = [](double g, double c) { return 100 + 80 * std::cos(g) + 30 * std::sin(g) * std::cos(c); };
    struct Case {
        const char* name;
        double w, l, h;
    };
    const Case cases[] = {
        {"box", 0.2, 0.28, 0.019},
        {"vertical cylinder", -0.1, -0.1, 0.3},
        {"vertical elliptical cylinder", -0.1, -0.2, 0.3},
        {"horizontal cylinder along", -0.1, 0.4, -0.1},
        {"horizontal cylinder perpendicular", 0.4, -0.12, -0.12},
        {"ellipsoid", -0.1, -0.2, -0.15},
        {"elliptical", -0.1, -0.3, 0},
        {"vertical circle facing horizontal", -0.2, 0, -0.2},
        {"vertical ellipse perpendicular", 0, -0.3, -0.2},
    };
    TempDir t;
    // Directions (gamma, C) in degrees, away from the tabulated kinks of |cos|-like shapes.
    // Not gamma = 0 nor C = 0 or 90, which lie in the plane of a vertical flat figure (it
    // cannot emit along its own plane).
    const double dirs[][2] = {{30, 20}, {45, 45}, {60, 70}, {85, 45}, {120, 10}, {150, 80}};
    for (const Case& c : cases) {
        SCOPED_TRACE(c.name);
        t.write("s.ies", ies_of(c.w, c.l, c.h, I));
        std::string pts, nrm;
        std::vector<double> want;
        for (const auto& d : dirs) {
            const V3 w = dir_c(radians(d[0]), radians(d[1]));
            pts += fmt::format("{} {} {} ", 100 * w.x, 100 * w.y, 100 * w.z);
            nrm += fmt::format("{} {} {} ", -w.x, -w.y, -w.z);
            want.push_back(I(radians(d[0]), radians(d[1])) / 1e4);
        }
        const std::string s = std::string(kHeader) +
                              "LightSource \"goniometric\" \"string filename\" \"s.ies\"\n"
                              "Meter \"illuminance\" \"point3 p\" [ " + pts + "] \"normal n\" [ " +
                              nrm + "]\n";
        MeasureResult r = measure_string(s, 1e-5, t.dir());
        const MeterReading& m = r.readings[0];
        EXPECT_EQ(m.estimator, "deterministic");
        for (size_t i = 0; i < want.size(); ++i) {
            SCOPED_TRACE(i);
            EXPECT_FALSE(m.exact[i]);  // an emitting surface, not the point form
            EXPECT_NEAR(m.values[i], want[i], 5e-5 * want[i] + m.stderrs[i]);
        }
    }
}

// Near field of a Lambertian box: a file whose intensity is L0 P(w), P the box's projected
// area W H |x| + L H |y| + L W |z|, makes every face's radiance L0, so the illuminance at
// any point outside is Lambert's polygon formula summed over the faces it sees. The box of
// the issue (0.019 x 0.20 x 0.28 m: width 0.2, length 0.28, height 0.019) at 0.3 m and 3 m.
// Tolerance: the bilinear table of P (0.5-degree steps) is within 1e-4 of P away from
// its kinks, which lie on the table's nodes.
TEST(LuminousShapes, LambertianBoxNearField) {
    const double W = 0.2, L = 0.28, H = 0.019, L0 = 5000;
    auto I = [&](double g, double c) {
        const V3 w = dir_c(g, c);
        return L0 * (W * H * std::abs(w.x) + L * H * std::abs(w.y) + L * W * std::abs(w.z));
    };
    TempDir t;
    t.write("box.ies", ies_of(W, L, H, I));
    const double hx = L / 2, hy = W / 2, hz = H / 2;
    // Faces as polygons (luminaire frame = world frame here, luminaire at the origin).
    const std::vector<std::vector<V3>> faces = {
        {{-hx, -hy, -hz}, {hx, -hy, -hz}, {hx, hy, -hz}, {-hx, hy, -hz}},  // -z
        {{-hx, -hy, hz}, {hx, -hy, hz}, {hx, hy, hz}, {-hx, hy, hz}},      // +z
        {{hx, -hy, -hz}, {hx, hy, -hz}, {hx, hy, hz}, {hx, -hy, hz}},      // +x
        {{-hx, -hy, -hz}, {-hx, hy, -hz}, {-hx, hy, hz}, {-hx, -hy, hz}},  // -x
        {{-hx, hy, -hz}, {hx, hy, -hz}, {hx, hy, hz}, {-hx, hy, hz}},      // +y
        {{-hx, -hy, -hz}, {hx, -hy, -hz}, {hx, -hy, hz}, {-hx, -hy, hz}},  // -y
    };
    const V3 outward[] = {{0, 0, -1}, {0, 0, 1}, {1, 0, 0}, {-1, 0, 0}, {0, 1, 0}, {0, -1, 0}};
    struct P {
        V3 p, n;
    };
    // Points whose receivers see every visible face wholly above their horizon.
    const P pts[] = {{{0.05, 0.02, -0.3}, {0, 0, 1}},
                     {{0.5, 0.3, -0.2}, {-0.8, -0.48, 0.36}},
                     {{1.0, 0.5, -3}, {0, 0, 1}},
                     {{0, -0.4, -0.05}, {0, 1, 0}}};
    std::string ps, ns;
    std::vector<double> want;
    for (const P& q : pts) {
        const double nl = len3(q.n);
        const V3 n = {q.n.x / nl, q.n.y / nl, q.n.z / nl};
        ps += fmt::format("{} {} {} ", q.p.x, q.p.y, q.p.z);
        ns += fmt::format("{} {} {} ", n.x, n.y, n.z);
        double e = 0;
        for (size_t f = 0; f < 6; ++f) {
            const V3 c = faces[f][0];
            if (dot3(outward[f], sub(q.p, c)) > 0) {
                for (const V3& v : faces[f]) ASSERT_GT(dot3(n, sub(v, q.p)), 0);
                e += polygon_illuminance(faces[f], q.p, n, L0);
            }
        }
        want.push_back(e);
    }
    const std::string s = std::string(kHeader) +
                          "LightSource \"goniometric\" \"string filename\" \"box.ies\"\n"
                          "Meter \"illuminance\" \"point3 p\" [ " + ps + "] \"normal n\" [ " + ns + "]\n";
    MeasureResult r = measure_string(s, 1e-5, t.dir());
    const MeterReading& m = r.readings[0];
    for (size_t i = 0; i < want.size(); ++i) {
        SCOPED_TRACE(i);
        EXPECT_NEAR(m.values[i], want[i], 1e-4 * want[i] + m.stderrs[i]);
    }
    // The same by the path tracer (light sampling of the box's faces and BSDF samples that
    // hit it): within 4 standard errors.
    MeasureOptions o;
    o.rel_error = 1e-3;
    o.threads = 2;
    o.deterministic_direct = false;
    MeasureResult mc = measure(build_scene(parse_pbrt_string(s, "<test>", t.dir()), {}), o);
    for (size_t i = 0; i < want.size(); ++i) {
        SCOPED_TRACE(i);
        EXPECT_EQ(mc.readings[0].estimator, "monte carlo");
        EXPECT_NEAR(mc.readings[0].values[i], want[i], 4 * mc.readings[0].stderrs[i] + 1e-4 * want[i]);
    }
}

// Split: with a scattering room, the direct part is computed and the indirect part sampled;
// the sum agrees with the all-Monte-Carlo reading within their combined standard errors.
TEST(DirectLight, SplitAgreesWithMonteCarlo) {
    const std::string s = std::string(kHeader) +
        "Material \"diffuse\" \"spectrum reflectance\" [ 360 0.5 830 0.5 ]\n"
        "Shape \"trianglemesh\" \"point3 P\" [ -3 -3 0  3 -3 0  3 3 0  -3 3 0 ] \"integer indices\" [ 0 1 2 0 2 3 ]\n"
        "Shape \"trianglemesh\" \"point3 P\" [ 3 -3 0  3 3 0  3 3 3  3 -3 3 ] \"integer indices\" [ 0 1 2 0 2 3 ]\n"
        "LightSource \"point\" \"point3 from\" [ 0 0 2 ] \"float scale\" 100\n"
        "AttributeBegin\n Translate 1 0 2.5\n AreaLightSource \"diffuse\" \"float scale\" [ 300 ]\n"
        " ReverseOrientation\n Shape \"disk\" \"float radius\" 0.3\nAttributeEnd\n"
        "Meter \"illuminance\" \"point3 p\" [ 0 0 0  2 1 0  1 -1 0 ] \"normal n\" [ 0 0 1 ]\n";
    SceneDesc d = parse_pbrt_string(s, "<test>", ".");
    Scene scene = build_scene(d, {});
    ASSERT_TRUE(scene_may_scatter(scene));
    MeasureOptions o;
    o.rel_error = 2e-3;
    o.threads = 2;
    MeasureResult split = measure(scene, o);
    o.deterministic_direct = false;
    MeasureResult mc = measure(scene, o);
    EXPECT_EQ(split.readings[0].estimator, "deterministic + monte carlo indirect");
    for (size_t i = 0; i < 3; ++i) {
        SCOPED_TRACE(i);
        const double a = split.readings[0].values[i], b = mc.readings[0].values[i];
        EXPECT_NEAR(a, b, 4 * std::hypot(split.readings[0].stderrs[i], mc.readings[0].stderrs[i]));
        EXPECT_TRUE(split.readings[0].converged[i]);
    }
}

}  // namespace
}  // namespace sr::test

namespace sr::test {
namespace {

// The shapes' size and orientation (length along C0 = x, width along C90 = y, height along
// z): each body's projected area P(w), which its radiance divides the intensity by, against
// the ideal shape's closed form, integrators/glare.h's luminous_projected_area (itself tested
// against Cauchy's mean-shadow formula in glare_test.cpp): a box exactly (its mesh is the
// box); the 48-sided meshes within 1 - cos(pi / 48) = 0.22 % of the ideal shapes.
TEST(LuminousShapes, ProjectedAreasFollowTheTableOfShapes) {
    struct Case {
        const char* name;
        double w, l, h;
        double tol;
    };
    const Case cases[] = {
        {"box", 0.2, 0.28, 0.019, 1e-6},
        {"vertical elliptical cylinder", -0.1, -0.2, 0.3, 3e-3},
        {"horizontal cylinder along", -0.1, 0.4, -0.1, 3e-3},
        {"horizontal elliptical cylinder perpendicular", 0.4, -0.12, -0.2, 3e-3},
        {"ellipsoid", -0.1, -0.2, -0.15, 5e-3},
        {"elliptical", -0.1, -0.3, 0, 3e-3},
        {"vertical ellipse facing horizontal", -0.2, 0, -0.1, 3e-3},
        {"vertical ellipse perpendicular", 0, -0.3, -0.2, 3e-3},
    };
    TempDir t;
    const double dirs[][3] = {{0, 0, -1}, {1, 0, 0}, {0, 1, 0}, {0.6, 0, 0.8}, {0.48, 0.6, -0.64}, {-0.36, 0.48, 0.8}};
    for (const Case& c : cases) {
        SCOPED_TRACE(c.name);
        t.write("s.ies", ies_of(c.w, c.l, c.h, [](double, double) { return 100.0; }));
        Scene s = build_scene(parse_pbrt_string(std::string(kHeader) +
                                                    "LightSource \"goniometric\" \"string filename\" \"s.ies\"\n",
                                                "<test>", t.dir()),
                              {});
        const DiffuseAreaLight* al = nullptr;
        for (const Light& l : s.lights)
            if ((al = std::get_if<DiffuseAreaLight>(&l))) break;
        ASSERT_NE(al, nullptr);
        ASSERT_TRUE(al->goniometric);
        for (const auto& d : dirs) {
            const Vec3 w{Float(d[0]), Float(d[1]), Float(d[2])};
            const double want = luminous_projected_area(*al->goniometric->profile.data, w);
            if (want < 1e-9) continue;  // edge-on flat figures
            const double got = al->goniometric->projected_area(w);
            EXPECT_NEAR(got, want, c.tol * want) << d[0] << " " << d[1] << " " << d[2];
        }
    }
}

}  // namespace
}  // namespace sr::test
