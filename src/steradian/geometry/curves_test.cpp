#include "steradian/geometry/curves.h"

#include <gtest/gtest.h>

#include <cmath>
#include <string>

#include "steradian/core/error.h"
#include "steradian/sampling/rng.h"
#include "steradian/sampling/warp.h"
#include "steradian/scene/build.h"
#include "steradian/scene/pbrt/parser.h"
#include "steradian/scene/scene.h"

namespace sr {
namespace {

// The uniform B-spline bases (de Boor; e.g. Farin, "Curves and Surfaces for CAGD", ch. 8):
// a segment of a uniform cubic B-spline is sum_k N_k(t) p_k over four control points with
// N_0 = (1 - t)^3 / 6, N_1 = (3 t^3 - 6 t^2 + 4) / 6, N_2 = (-3 t^3 + 3 t^2 + 3 t + 1) / 6,
// N_3 = t^3 / 6; a quadratic one over three with (1 - t)^2 / 2, (-2 t^2 + 2 t + 1) / 2, t^2 / 2.
Point3 cubic_bspline(const Point3 p[4], double t) {
    const double n[4] = {std::pow(1 - t, 3) / 6, (3 * t * t * t - 6 * t * t + 4) / 6,
                         (-3 * t * t * t + 3 * t * t + 3 * t + 1) / 6, t * t * t / 6};
    Point3 r(0, 0, 0);
    for (int k = 0; k < 4; ++k) r = r + p[k] * Float(n[k]);
    return r;
}

Point3 quadratic_bspline(const Point3 p[3], double t) {
    const double n[3] = {(1 - t) * (1 - t) / 2, (-2 * t * t + 2 * t + 1) / 2, t * t / 2};
    return p[0] * Float(n[0]) + p[1] * Float(n[1]) + p[2] * Float(n[2]);
}

Point3 quadratic_bezier(const Point3 p[3], double t) {
    return p[0] * Float((1 - t) * (1 - t)) + p[1] * Float(2 * t * (1 - t)) + p[2] * Float(t * t);
}

TEST(Curves, BsplineToBezierReproducesTheBsplineBasis) {
    const Point3 p[4] = {{0.3f, -1, 2}, {1.7f, 0.4f, -0.5f}, {2.2f, 2.5f, 1}, {4, 1.5f, 3}};
    const auto cubic = cubic_bspline_to_bezier(std::span<const Point3, 4>(p, 4));
    const auto quad = quadratic_bspline_to_bezier(std::span<const Point3, 3>(p, 3));
    const auto elevated = elevate_quadratic_bezier(quad);
    for (int i = 0; i <= 20; ++i) {
        const double t = i / 20.0;
        const Point3 want = cubic_bspline(p, t), got = cubic_bezier(cubic, Float(t));
        EXPECT_LT(length(got - want), 1e-5f) << "cubic, t = " << t;
        const Point3 want2 = quadratic_bspline(p, t);
        EXPECT_LT(length(quadratic_bezier(quad.data(), t) - want2), 1e-5f) << "quadratic, t = " << t;
        EXPECT_LT(length(cubic_bezier(elevated, Float(t)) - want2), 1e-5f) << "elevated, t = " << t;
    }
    // The derivative of the Bernstein form against a central difference of the B-spline.
    Vec3 d;
    cubic_bezier(cubic, 0.4f, &d);
    const Vec3 fd = (cubic_bspline(p, 0.4 + 1e-3) - cubic_bspline(p, 0.4 - 1e-3)) / 2e-3f;
    EXPECT_LT(length(d - fd), 2e-3f * length(fd));
}

Scene scene_of(const std::string& world) {
    set_warnings_quiet(true);
    Scene s = build_scene(parse_pbrt_string("WorldBegin\n" + world, "t.pbrt"));
    set_warnings_quiet(false);
    return s;
}

std::string build_error(const std::string& world) {
    set_warnings_quiet(true);
    std::string msg;
    try {
        build_scene(parse_pbrt_string("WorldBegin\n" + world, "t.pbrt"));
    } catch (const Error& e) {
        msg = e.what();
    }
    set_warnings_quiet(false);
    return msg;
}

TEST(Curves, RayHitsAStraightCurveWithinItsWidthAtItsDistance) {
    // A straight cubic Bézier along x from -1 to 1 (evenly spaced control points: u = (x + 1)
    // / 2), width 0.2 tapering to 0: radius 0.05 (1 - u) ... 0.1 at u = 0.
    for (const char* type : {"flat", "cylinder"}) {
        Scene s = scene_of(std::string("Shape \"curve\" \"string type\" \"") + type +
                           "\" \"point3 P\" [-1 0 0  -0.3333333 0 0  0.3333333 0 0  1 0 0] "
                           "\"float width0\" 0.2 \"float width1\" 0");
        for (Float x : {-0.5f, 0.f, 0.3f, 0.8f}) {
            const Float u = (x + 1) / 2, r = Float(0.1) * (1 - u);
            for (Float frac : {-0.97f, -0.5f, 0.f, 0.4f, 0.97f, -1.03f, 1.03f, 1.5f}) {
                const Float y = frac * r;
                SurfaceHit h;
                const Ray ray{Point3(x, y, 5), Vec3(0, 0, -1), kInfinity};
                const bool hit = s.intersect(ray, h);
                ASSERT_EQ(hit, std::abs(frac) < 1) << type << " x = " << x << " y = " << y;
                if (!hit) continue;
                // The ray-facing ribbon contains the axis: the hit is at z = 0.
                EXPECT_NEAR(h.t, 5, 1e-4) << type;
                EXPECT_NEAR(h.uv.x, u, 1e-3) << type;
                // v across the width: |2 v - 1| is the offset in half-widths.
                EXPECT_NEAR(std::abs(2 * h.uv.y - 1), std::abs(frac), 2e-3) << type;
                EXPECT_NEAR(h.ng.z, 1, 1e-5) << type << ": ng faces the ray";
                EXPECT_NEAR(std::abs(normalize(h.dpdu).x), 1, 1e-5) << type;
                // Flat: the shading normal is the ribbon's; cylinder: a round tube's normal at
                // the offset, whose component towards the viewer is sqrt(1 - offset^2).
                const Float want_nz = std::string(type) == "flat" ? 1 : std::sqrt(1 - frac * frac);
                EXPECT_NEAR(h.ns.z, want_nz, 2e-3) << type << " frac " << frac;
                EXPECT_NEAR(length(h.ns), 1, 1e-5);
            }
        }
    }
}

TEST(Curves, RibbonsAndBsplinesAndErrors) {
    // A ribbon in the plane y = 0 (normals +y) seen along -y at 60 degrees: the ribbon's width
    // w is seen foreshortened, so a ray hits within w/2 of the axis in the ribbon's plane.
    Scene s = scene_of(
        "Shape \"curve\" \"string type\" \"ribbon\" \"point3 P\" [-1 0 0 -0.3 0 0 0.3 0 0 1 0 0] "
        "\"normal N\" [0 1 0  0 1 0] \"float width\" 0.2");
    const Vec3 d = normalize(Vec3(0, -0.5f, -std::sqrt(3.f) / 2));  // 60 degrees from -y
    for (Float z : {-0.095f, 0.05f, 0.105f}) {
        SurfaceHit h;
        const Point3 target(0.1f, 0, z);
        const bool hit = s.intersect(Ray{target - d * 4, d, kInfinity}, h);
        EXPECT_EQ(hit, std::abs(z) < 0.1f) << z;
        if (hit) {
            EXPECT_NEAR(h.t, 4, 1e-3);
            EXPECT_NEAR(std::abs(h.ng.y), 1, 1e-5);
        }
    }
    // A degree-2 B-spline with 4 points: 2 segments, from the midpoint of P0 P1 to that of P2 P3.
    Scene b = scene_of(
        "Shape \"curve\" \"string basis\" \"bspline\" \"integer degree\" 2 \"point3 P\" "
        "[0 0 0  2 0 0  4 0 0  6 0 0] \"float width\" 0.1");
    SurfaceHit h;
    EXPECT_FALSE(b.intersect(Ray{Point3(0.9f, 0, 1), Vec3(0, 0, -1), kInfinity}, h));
    EXPECT_TRUE(b.intersect(Ray{Point3(1.1f, 0, 1), Vec3(0, 0, -1), kInfinity}, h));
    EXPECT_TRUE(b.intersect(Ray{Point3(4.9f, 0, 1), Vec3(0, 0, -1), kInfinity}, h));
    EXPECT_FALSE(b.intersect(Ray{Point3(5.1f, 0, 1), Vec3(0, 0, -1), kInfinity}, h));

    EXPECT_EQ(build_error("Shape \"curve\" \"point3 P\" [0 0 0 1 0 0 2 0 0 3 0 0 4 0 0]"),
              "t.pbrt:2:15: Shape \"curve\": a degree-3 Bézier curve needs 4 + 3 n control "
              "points (n >= 0), \"P\" has 5");
    EXPECT_EQ(build_error("Shape \"curve\" \"integer degree\" 4 \"point3 P\" [0 0 0 1 0 0]"),
              "t.pbrt:2:15: Shape \"curve\": \"degree\" must be 2 or 3, is 4");
    EXPECT_EQ(build_error("Shape \"curve\" \"string type\" \"ribbon\" \"point3 P\" "
                          "[0 0 0 1 0 0 2 0 0 3 0 0]"),
              "t.pbrt:2:1: Shape \"curve\": a ribbon with 1 segments needs 2 normals \"N\", "
              "has 0");
    EXPECT_EQ(build_error("Shape \"curve\" \"string type\" \"round\""),
              "t.pbrt:2:15: Shape \"curve\": \"type\" must be \"flat\", \"cylinder\" or "
              "\"ribbon\", is \"round\"");
    EXPECT_EQ(build_error("Shape \"curve\" \"float width\" -1 \"point3 P\" [0 0 0 1 0 0 2 0 0 3 0 0]"),
              "t.pbrt:2:15: Shape \"curve\": \"width\" must be a finite width >= 0, is -1");
    EXPECT_NE(build_error("AreaLightSource \"diffuse\"\nShape \"curve\" \"point3 P\" "
                          "[0 0 0 1 0 0 2 0 0 3 0 0]")
                  .find("t.pbrt:3:1: an emitting curve (area light) is not supported"),
              std::string::npos);
}

/// The fraction of rays from uniform points under a screen of parallel curves (along x, at
/// z = 0, spaced d apart in y, width w) that the screen blocks, with its standard error.
struct Blocked {
    double fraction, se;
};

Blocked blocked_fraction(const Scene& s, Float d, int periods, Float height, int n,
                         auto&& direction) {
    Pcg32 rng(7);
    int blocked = 0;
    for (int i = 0; i < n; ++i) {
        // Origins over whole periods in y, in the middle part of the screen in x.
        const Point3 o(rng.next_float() - Float(0.5), (rng.next_float() - Float(0.5)) * d * periods,
                       -height);
        const Vec3 dir = direction(rng);
        blocked += s.occluded(Ray{o, dir * (2 * height / dir.z), 1});
    }
    const double p = double(blocked) / n;
    return {p, std::sqrt(std::max(p * (1 - p), 1e-12) / n)};
}

TEST(Curves, AScreenOfThinCurvesBlocksItsProjectedCoverage) {
    // 201 curves along x (x from -50 to 50) at y = k d, width w: a ray perpendicular to the
    // screen is blocked with probability w / d. Flat curves face every ray, so a ray tilted
    // by theta across the curves sees them w wide but spaced d cos(theta) apart: w / (d cos);
    // ribbons lying in the screen (normals +z) are foreshortened as their spacing is: w / d
    // from every direction, so they block the fraction w / d of a uniform (cosine-weighted)
    // light too.
    const Float w = 0.005f, d = 0.02f;
    const int count = 201, periods = 100;
    auto screen = [&](const char* type) {
        std::string text;
        for (int k = -count / 2; k <= count / 2; ++k) {
            const std::string y = std::to_string(k * d);
            text += std::string("Shape \"curve\" \"string type\" \"") + type + "\" \"float width\" " +
                    std::to_string(w) + " \"point3 P\" [-50 " + y + " 0  -20 " + y + " 0  20 " + y +
                    " 0  50 " + y + " 0]" +
                    (std::string(type) == "ribbon" ? " \"normal N\" [0 0 1 0 0 1]" : "") + "\n";
        }
        return scene_of(text);
    };
    const int n = 40000;
    const Scene flat = screen("flat"), ribbon = screen("ribbon");
    auto straight = [](Pcg32&) { return Vec3(0, 0, 1); };
    const Float theta = radians(50);
    auto tilted = [&](Pcg32&) { return Vec3(0, std::sin(theta), std::cos(theta)); };
    auto uniform = [](Pcg32& rng) {
        return sample_cosine_hemisphere(Point2(rng.next_float(), rng.next_float()));
    };
    struct Case {
        const char* what;
        Blocked b;
        double want;
    };
    const Float h = 0.01f;  // height of the origins under the screen
    const Case cases[] = {
        {"flat, perpendicular", blocked_fraction(flat, d, periods, h, n, straight), w / d},
        {"flat, 50 degrees", blocked_fraction(flat, d, periods, h, n, tilted),
         w / (d * std::cos(theta))},
        {"ribbon, perpendicular", blocked_fraction(ribbon, d, periods, h, n, straight), w / d},
        {"ribbon, 50 degrees", blocked_fraction(ribbon, d, periods, h, n, tilted), w / d},
        {"ribbon, uniform light", blocked_fraction(ribbon, d, periods, h, n, uniform), w / d},
    };
    // Bonferroni over 5 cases at 1e-4: |z| < 4.4.
    for (const Case& c : cases)
        EXPECT_LT(std::abs(c.b.fraction - c.want), 4.4 * c.b.se)
            << c.what << ": blocked " << c.b.fraction << " +- " << c.b.se << ", want " << c.want;
}

}  // namespace
}  // namespace sr
