#include "steradian/geometry/shapes.h"

#include <gtest/gtest.h>

#include <cmath>
#include <functional>
#include <memory>
#include <numbers>
#include <vector>

#include "steradian/sampling/rng.h"
#include "steradian/sampling/stats.h"
#include "steradian/sampling/warp.h"

namespace sr {
namespace {

constexpr double kPiD = std::numbers::pi;
// About a dozen statistical tests (chi-square and z-tests) in this file share a 1% family
// level (Sidak). Fixed seeds: a pass is reproducible.
const double kAlpha = sidak_alpha(0.01, 12);

// ---- helpers ------------------------------------------------------------------------------

/// A mesh as the scene builder makes it: positions padded with one extra element.
TriangleMesh make_mesh(std::vector<Point3> p, std::vector<uint32_t> idx,
                       std::vector<Normal3> n = {}) {
    TriangleMesh m;
    p.push_back(Point3(0, 0, 0));
    m.p = std::make_shared<std::vector<Point3>>(std::move(p));
    m.n = std::make_shared<std::vector<Normal3>>(std::move(n));
    m.uv = std::make_shared<std::vector<Point2>>();
    m.indices = std::make_shared<std::vector<uint32_t>>(std::move(idx));
    return m;
}

Sphere make_sphere(Float radius, const Transform& world_from_object = Transform()) {
    Sphere s;
    s.world_from_object = world_from_object;
    s.radius = radius;
    s.z_min = -radius;
    s.z_max = radius;
    return s;
}

void set_z_range(Sphere& s, Float z0, Float z1) {
    s.z_min = z0;
    s.z_max = z1;
    s.theta_z_min = std::acos(z0 / s.radius);
    s.theta_z_max = std::acos(z1 / s.radius);
}

/// The nearer root of |o + t d|^2 = r^2 with t > 0, in double (textbook quadratic), or -1.
double analytic_hit(Vec3d o, Vec3d d, double r, bool far = false) {
    double a = dot(d, d), b = 2 * dot(o, d), c = dot(o, o) - r * r;
    double disc = b * b - 4 * a * c;
    if (disc < 0) return -1;
    double t0 = (-b - std::sqrt(disc)) / (2 * a), t1 = (-b + std::sqrt(disc)) / (2 * a);
    if (far) return t1 > 0 ? t1 : -1;
    if (t0 > 0) return t0;
    return t1 > 0 ? t1 : -1;
}

/// The first intersection of a world-space ray with a sphere, as a filled hit.
bool first_hit(const Sphere& s, const Transform& object_from_world, Point3 o, Vec3 d,
               SurfaceHit& h) {
    Float t;
    Point3 p_obj;
    if (!s.intersect_object(object_from_world.point(o), object_from_world.vector(d), kInfinity, t,
                            p_obj))
        return false;
    s.fill_hit(p_obj, h);
    return true;
}

/// Barycentrics (b0, b1, b2) of a point in the plane of a triangle.
std::array<double, 3> barycentrics(Vec3d p, Vec3d p0, Vec3d p1, Vec3d p2) {
    Vec3d e1 = p1 - p0, e2 = p2 - p0, v = p - p0;
    double d00 = dot(e1, e1), d01 = dot(e1, e2), d11 = dot(e2, e2);
    double d20 = dot(v, e1), d21 = dot(v, e2);
    double den = d00 * d11 - d01 * d01;
    double b1 = (d11 * d20 - d01 * d21) / den, b2 = (d00 * d21 - d01 * d20) / den;
    return {1 - b1 - b2, b1, b2};
}

/// Mean and standard error of a sample.
struct MeanSe {
    double mean, se;
};
MeanSe mean_se(const std::vector<double>& v) {
    double s = 0, s2 = 0;
    for (double x : v) {
        s += x;
        s2 += x * x;
    }
    double n = double(v.size()), m = s / n;
    return {m, std::sqrt(std::max(0.0, s2 / n - m * m) / (n - 1))};
}

/// Chi-square p-value of 2D samples in [0,1)^2 against the uniform density, na x nb cells.
double uniform_chi2_p(const std::vector<Vec2d>& pts, int na, int nb) {
    std::vector<double> obs(size_t(na * nb), 0.0), exp(obs.size(), double(pts.size()) / (na * nb));
    for (Vec2d p : pts) {
        int i = std::clamp(int(std::floor(p.x * na)), 0, na - 1);
        int j = std::clamp(int(std::floor(p.y * nb)), 0, nb - 1);
        obs[size_t(j * na + i)] += 1;
    }
    return chi2_test(obs, exp).p_value;
}

double azimuth01(double x, double y) {
    double phi = std::atan2(y, x);
    if (phi < 0) phi += 2 * kPiD;
    return phi / (2 * kPiD);
}

// ---- sphere intersection ---------------------------------------------------------------------

TEST(Sphere, RaysFromOutsideHitAtTheAnalyticDistance) {
    Sphere s = make_sphere(2);
    Float t;
    Point3 p;
    ASSERT_TRUE(s.intersect_object({0, 0, -5}, {0, 0, 1}, kInfinity, t, p));
    EXPECT_NEAR(t, 3, 1e-6);
    EXPECT_NEAR(p.z, -2, 1e-6);
    // A non-unit direction scales t.
    ASSERT_TRUE(s.intersect_object({0, 0, -5}, {0, 0, 2}, kInfinity, t, p));
    EXPECT_NEAR(t, 1.5, 1e-6);
    // Impact parameter b: t = 5 - sqrt(r^2 - b^2).
    for (double b : {0.5, 1.0, 1.9, 1.999}) {
        ASSERT_TRUE(s.intersect_object({Float(b), 0, -5}, {0, 0, 1}, kInfinity, t, p)) << b;
        EXPECT_NEAR(t, 5 - std::sqrt(4 - b * b), 1e-5) << b;
    }
    // Random rays aimed near the sphere from random points outside.
    Pcg32 rng(1, 2);
    int hits = 0;
    for (int k = 0; k < 2000; ++k) {
        Vec3 o = sample_uniform_sphere({rng.next_float(), rng.next_float()}) *
                 (2.5f + 6 * rng.next_float());
        Vec3 target = sample_uniform_sphere({rng.next_float(), rng.next_float()}) * 2.4f;
        Vec3 d = (target - o) * (0.5f + rng.next_float());
        double ta = analytic_hit(Vec3d(o), Vec3d(d), 2);
        bool hit = s.intersect_object(o, d, kInfinity, t, p);
        // Grazing rays (within float error of tangency) may go either way.
        double b2 = length_squared(cross(Vec3d(o), normalize(Vec3d(d))));
        if (std::abs(std::sqrt(b2) - 2) < 1e-4) continue;
        ASSERT_EQ(hit, ta > 0) << "ray " << k;
        if (!hit) continue;
        ++hits;
        EXPECT_NEAR(t, ta, 1e-5 * ta) << "ray " << k;
        EXPECT_NEAR(length(p), 2, 1e-5);
        Point3 pa = o + d * Float(ta);
        EXPECT_NEAR(distance(p, pa), 0, 1e-4);
    }
    EXPECT_GT(hits, 500);  // both outcomes exercised
    EXPECT_LT(hits, 1900);
}

TEST(Sphere, RaysFromInsideHitTheFarSide) {
    Sphere s = make_sphere(2);
    Float t;
    Point3 p;
    ASSERT_TRUE(s.intersect_object({0, 0, 0.5f}, {1, 0, 0}, kInfinity, t, p));
    EXPECT_NEAR(t, std::sqrt(3.75), 1e-6);
    EXPECT_NEAR(p.x, std::sqrt(3.75), 1e-6);
    EXPECT_NEAR(p.z, 0.5, 1e-6);
    Pcg32 rng(3, 4);
    for (int k = 0; k < 500; ++k) {
        Vec3 o = sample_uniform_sphere({rng.next_float(), rng.next_float()}) * (1.9f * rng.next_float());
        Vec3 d = sample_uniform_sphere({rng.next_float(), rng.next_float()});
        ASSERT_TRUE(s.intersect_object(o, d, kInfinity, t, p));
        EXPECT_NEAR(t, analytic_hit(Vec3d(o), Vec3d(d), 2, true), 1e-5);
        EXPECT_GT(dot(p, d), 0);  // the far side, ahead of the ray
    }
}

TEST(Sphere, MissesAndTmax) {
    Sphere s = make_sphere(2);
    Float t;
    Point3 p;
    EXPECT_FALSE(s.intersect_object({2.002f, 0, -5}, {0, 0, 1}, kInfinity, t, p));  // passes by
    EXPECT_FALSE(s.intersect_object({0, 0, -5}, {0, 0, -1}, kInfinity, t, p));      // away
    EXPECT_FALSE(s.intersect_object({0, 0, 5}, {0, 0, 1}, kInfinity, t, p));        // behind
    EXPECT_FALSE(s.intersect_object({0, 0, -5}, {0, 0, 1}, 2.9f, t, p));            // t_max < 3
    EXPECT_TRUE(s.intersect_object({0, 0, -5}, {0, 0, 1}, 3.1f, t, p));
    EXPECT_TRUE(s.intersect_object({1.998f, 0, -5}, {0, 0, 1}, kInfinity, t, p));   // just hits
}

TEST(Sphere, PartialSpheresRejectTheCutParts) {
    Float t;
    Point3 p;
    Sphere cap = make_sphere(2);
    set_z_range(cap, -2, 1);  // top cap above z = 1 removed
    EXPECT_FALSE(cap.full());
    // Down the z axis: the top (z = 2) is cut, the bottom (z = -2) remains.
    ASSERT_TRUE(cap.intersect_object({0, 0, 5}, {0, 0, -1}, kInfinity, t, p));
    EXPECT_NEAR(t, 7, 1e-5);
    EXPECT_NEAR(p.z, -2, 1e-5);
    // A horizontal ray at z = 0.5 is below the cut: first hit at x = -sqrt(3.75).
    ASSERT_TRUE(cap.intersect_object({-5, 0, 0.5f}, {1, 0, 0}, kInfinity, t, p));
    EXPECT_NEAR(p.x, -std::sqrt(3.75), 1e-5);
    // At z = 1.5 both hits are cut.
    EXPECT_FALSE(cap.intersect_object({-5, 0, 1.5f}, {1, 0, 0}, kInfinity, t, p));

    Sphere band = make_sphere(2);
    set_z_range(band, -1, 1);  // both poles removed: the z axis passes through
    EXPECT_FALSE(band.intersect_object({0, 0, 5}, {0, 0, -1}, kInfinity, t, p));

    Sphere half = make_sphere(2);
    half.phi_max = kPi;  // y >= 0 only
    // Along +y from y = -5: the hit at (0, -2, 0) has phi = 3 pi / 2 > phi_max: the far one.
    ASSERT_TRUE(half.intersect_object({0, -5, 0}, {0, 1, 0}, kInfinity, t, p));
    EXPECT_NEAR(t, 7, 1e-5);
    EXPECT_NEAR(p.y, 2, 1e-5);
    ASSERT_TRUE(half.intersect_object({0, 5, 0}, {0, -1, 0}, kInfinity, t, p));
    EXPECT_NEAR(t, 3, 1e-5);
    // Every accepted hit lies in the kept part.
    Pcg32 rng(5, 6);
    Sphere part = make_sphere(1.5f);
    set_z_range(part, -0.5f, 1.2f);
    part.phi_max = Float(1.3 * kPiD);
    int n_hits = 0;
    for (int k = 0; k < 2000; ++k) {
        Vec3 o = sample_uniform_sphere({rng.next_float(), rng.next_float()}) * 4.0f;
        Vec3 d = normalize(sample_uniform_sphere({rng.next_float(), rng.next_float()}) * 1.4f - o);
        if (!part.intersect_object(o, d, kInfinity, t, p)) continue;
        ++n_hits;
        EXPECT_GE(p.z, -0.5f - 1e-5f);
        EXPECT_LE(p.z, 1.2f + 1e-5f);
        EXPECT_LE(azimuth01(p.x, p.y) * 2 * kPiD, 1.3 * kPiD + 1e-5);
    }
    EXPECT_GT(n_hits, 300);
}

TEST(Sphere, HitNormalsAndTangents) {
    // Sphere of radius 1 scaled by 2 and moved to c: the normal is (p - c) / 2, outward, and
    // flipped by flip_normals; dpdu is perpendicular to it.
    Transform x = Transform::translate({1, -1, 3}) * Transform::scale({2, 2, 2});
    Sphere s = make_sphere(1, x);
    Pcg32 rng(7, 7);
    for (int k = 0; k < 100; ++k) {
        Point3 po = sample_uniform_sphere({rng.next_float(), rng.next_float()});
        SurfaceHit h;
        s.fill_hit(po, h);
        Vec3 expected = (h.p - Point3(1, -1, 3)) / 2;
        EXPECT_NEAR(length(h.p - Point3(1, -1, 3)), 2, 1e-5);
        EXPECT_NEAR(h.ng.x, expected.x, 1e-5);
        EXPECT_NEAR(h.ng.y, expected.y, 1e-5);
        EXPECT_NEAR(h.ng.z, expected.z, 1e-5);
        EXPECT_NEAR(dot(h.ng, normalize(h.dpdu)), 0, 1e-5);
        s.flip_normals = true;
        SurfaceHit hf;
        s.fill_hit(po, hf);
        s.flip_normals = false;
        EXPECT_NEAR(dot(hf.ng, h.ng), -1, 1e-6);
    }
}

// ---- areas --------------------------------------------------------------------------------------

TEST(Shapes, AreasMatchClosedForms) {
    // Full sphere: 4 pi r^2, scaled by s^2 under a uniform scale (and unchanged by rotation
    // and translation).
    Transform x = Transform::translate({3, 1, 2}) * Transform::rotate(40, {1, 1, 0}) *
                  Transform::scale({3, 3, 3});
    EXPECT_NEAR(make_sphere(2, x).area(), 4 * kPiD * 4 * 9, 1e-4 * 4 * kPiD * 36);
    EXPECT_NEAR(make_sphere(2).area(), 16 * kPiD, 1e-5);
    // Partial sphere (Archimedes' hat-box theorem): phi_max r (z_max - z_min).
    Sphere p = make_sphere(2, Transform::scale({0.5, 0.5, 0.5}));
    set_z_range(p, -1, 1.5f);
    p.phi_max = kPiOver2;
    EXPECT_NEAR(p.area(), kPiD / 2 * 2 * 2.5 * 0.25, 1e-5);
    // Disk: phi_max / 2 (r^2 - ri^2), times s^2.
    Disk d;
    d.radius = 2;
    d.inner_radius = 0.5f;
    d.world_from_object = Transform::rotate(70, {0, 1, 0}) * Transform::scale({2, 2, 2});
    EXPECT_NEAR(d.area(), kPiD * (4 - 0.25) * 4, 1e-4);
    d.phi_max = kPi;
    EXPECT_NEAR(d.area(), kPiD / 2 * (4 - 0.25) * 4, 1e-4);
    // Triangle with legs 3 and 4 (area 6), rotated and moved.
    Transform r = Transform::translate({1, 2, 3}) * Transform::rotate(33, {1, -2, 0.5});
    TriangleMesh m = make_mesh({r.point(Point3(0, 0, 0)), r.point(Point3(3, 0, 0)),
                                r.point(Point3(0, 4, 0))},
                               {0, 1, 2});
    EXPECT_NEAR(m.triangle_area(0), 6, 1e-5);
    EXPECT_EQ(m.num_triangles(), 1u);
    EXPECT_EQ(m.num_vertices(), 3u);
}

// ---- triangle sampling ------------------------------------------------------------------------

TEST(TriangleMesh, SampleTriangleIsUniformByArea) {
    // A skinny, tilted triangle of area 6 (legs 3 and 4 before a rotation). Subdividing each
    // edge into n parts splits it into n^2 congruent sub-triangles of equal area: under a
    // uniform density each holds 1/n^2 of the samples.
    Transform r = Transform::translate({-1, 0.5, 2}) * Transform::rotate(57, {0.3, 1, -0.4});
    Vec3d q0(r.point(Point3(0, 0, 0))), q1(r.point(Point3(3, 0, 0))), q2(r.point(Point3(0, 4, 0)));
    TriangleMesh m = make_mesh({Point3(q0), Point3(q1), Point3(q2)}, {0, 1, 2});
    const int n = 9, n_samples = 200000;
    std::vector<double> obs(size_t(2 * n * n), 0.0), expected(obs.size(), 0.0);
    // Cell (i, j, up/down) with i, j the integer parts of n b1, n b2.
    for (int i = 0; i < n; ++i)
        for (int j = 0; i + j < n; ++j) {
            expected[size_t(2 * (i * n + j))] = double(n_samples) / (n * n);
            if (i + j < n - 1) expected[size_t(2 * (i * n + j) + 1)] = double(n_samples) / (n * n);
        }
    Vec3d normal = normalize(cross(q1 - q0, q2 - q0));
    Pcg32 rng(11, 12);
    for (int k = 0; k < n_samples; ++k) {
        ShapeSample s = m.sample_triangle(0, {rng.next_float(), rng.next_float()});
        ASSERT_NEAR(s.pdf, 1.0 / 6, 1e-6);
        ASSERT_NEAR(dot(Vec3d(s.p) - q0, normal), 0, 1e-5);  // in the plane
        ASSERT_NEAR(dot(Vec3d(s.n), normal), 1, 1e-5);
        auto b = barycentrics(Vec3d(s.p), q0, q1, q2);
        for (double bi : b) ASSERT_TRUE(bi > -1e-5 && bi < 1 + 1e-5) << bi;
        double x = std::clamp(b[1], 0.0, 1.0) * n, y = std::clamp(b[2], 0.0, 1.0) * n;
        int i = std::min(int(x), n - 1), j = std::min(int(y), n - 1);
        bool down = (x - i) + (y - j) >= 1;
        if (i + j > n - 1 || (i + j == n - 1 && down)) {  // round-off across the b0 = 0 edge
            j = n - 1 - i;
            down = false;
        }
        obs[size_t(2 * (i * n + j) + (down ? 1 : 0))] += 1;
    }
    // Drop the structurally empty slots.
    std::vector<double> o2, e2;
    for (size_t c = 0; c < obs.size(); ++c)
        if (expected[c] > 0) {
            o2.push_back(obs[c]);
            e2.push_back(expected[c]);
        }
    ASSERT_EQ(int(e2.size()), n * n);
    Chi2Result res = chi2_test(o2, e2);
    EXPECT_GT(res.p_value, kAlpha) << "chi2 " << res.statistic << " dof " << res.dof;
}

TEST(TriangleMesh, SampleNormalsFollowOrientation) {
    TriangleMesh m = make_mesh({{0, 0, 0}, {1, 0, 0}, {0, 1, 0}}, {0, 1, 2});
    ShapeSample s = m.sample_triangle(0, {0.3f, 0.6f});
    EXPECT_NEAR(s.n.z, 1, 1e-6);  // (p1 - p0) x (p2 - p0) = +z
    EXPECT_NEAR(s.pdf, 2, 1e-6);  // area 1/2
    m.flip_normals = true;
    EXPECT_NEAR(m.sample_triangle(0, {0.3f, 0.6f}).n.z, -1, 1e-6);
    // With per-vertex normals the geometric normal faces them.
    TriangleMesh mn = make_mesh({{0, 0, 0}, {1, 0, 0}, {0, 1, 0}}, {0, 1, 2},
                                {{0, 0, -1}, {0, 0.1f, -1}, {0.1f, 0, -1}});
    EXPECT_NEAR(mn.sample_triangle(0, {0.3f, 0.6f}).n.z, -1, 1e-6);
    // fill_hit agrees with sample_triangle on the normal and the point.
    SurfaceHit h;
    m.flip_normals = false;
    m.fill_hit(0, 0.25f, 0.5f, h);
    EXPECT_NEAR(h.p.x, 0.25, 1e-6);
    EXPECT_NEAR(h.p.y, 0.5, 1e-6);
    EXPECT_NEAR(h.ng.z, 1, 1e-6);
}

// The per-triangle cache of flat meshes (normal and shading tangent) changes no hit: the same
// point, normals, uv and dp/du, dp/dv as computed per hit, and a tangent that is the unit
// Gram-Schmidt of dp/du against the normal (so orthogonal to it). For the default uv, uv
// given per vertex, either orientation, and a triangle whose uv are degenerate (its
// tangents come from the fallback, so it is not cached).
TEST(TriangleMesh, CachedFlatFramesGiveTheSameHits) {
    for (bool flip : {false, true}) {
        for (int uv_kind = 0; uv_kind < 3; ++uv_kind) {
            TriangleMesh m = make_mesh({{0, 0, 0}, {2, 0, 1}, {0, 3, 1}, {1, 1, 3}}, {0, 1, 2, 1, 3, 2});
            m.flip_normals = flip;
            if (uv_kind == 1)
                *m.uv = {{0, 0}, {1, 0.2f}, {0.3f, 1}, {1, 1}};
            else if (uv_kind == 2)
                *m.uv = {{0, 0}, {0, 0}, {0, 0}, {0, 0}};  // det = 0: dp/du = dp/dv = 0
            TriangleMesh cached = m;
            cached.cache_flat_frames();
            ASSERT_TRUE(cached.flat_frames);
            for (size_t tri = 0; tri < 2; ++tri) {
                SurfaceHit a, b;
                m.fill_hit(tri, 0.2f, 0.3f, a);
                cached.fill_hit(tri, 0.2f, 0.3f, b);
                EXPECT_EQ(a.p, b.p);
                EXPECT_EQ(a.p_error, b.p_error);
                EXPECT_EQ(a.uv, b.uv);
                EXPECT_EQ(a.dpdu, b.dpdu);
                EXPECT_EQ(a.dpdv, b.dpdv);
                for (int c = 0; c < 3; ++c) {
                    EXPECT_NEAR(a.ng[c], b.ng[c], 1e-6f);
                    EXPECT_NEAR(a.ns[c], b.ns[c], 1e-6f);
                }
                EXPECT_FALSE(is_nonzero(a.ss));  // without the cache: computed by the material
                if (uv_kind == 2) {
                    EXPECT_FALSE(is_nonzero(b.ss));
                    continue;
                }
                ASSERT_TRUE(is_nonzero(b.ss));
                EXPECT_NEAR(length(b.ss), 1, 1e-6f);
                EXPECT_NEAR(dot(b.ss, b.ns), 0, 1e-6f);
                Vec3 gs = normalize(b.dpdu - b.ns * dot(b.ns, b.dpdu));
                for (int c = 0; c < 3; ++c) EXPECT_NEAR(b.ss[c], gs[c], 1e-6f);
            }
        }
    }
    // Meshes with vertex normals are not cached (their frame varies over the triangle).
    TriangleMesh mn = make_mesh({{0, 0, 0}, {1, 0, 0}, {0, 1, 0}}, {0, 1, 2},
                                {{0, 0, 1}, {0, 0.1f, 1}, {0.1f, 0, 1}});
    mn.cache_flat_frames();
    EXPECT_FALSE(mn.flat_frames);
}

// ---- sphere and disk area sampling --------------------------------------------------------------

TEST(TriangleMesh, BehindTriangleFollowsTheSampledNormal) {
    // behind_triangle(ref) must say "behind" exactly when the normal that point_at reports
    // faces away from ref, for both orientations.
    Pcg32 rng(3, 4);
    for (bool flip : {false, true}) {
        TriangleMesh m = make_mesh({{0, 0, 0}, {2, 0, 1}, {0, 3, 1}}, {0, 1, 2});
        m.flip_normals = flip;
        ShapeSample c = m.point_at(0, Float(1) / 3, Float(1) / 3, Float(1) / 3);
        for (int k = 0; k < 1000; ++k) {
            Point3 ref(8 * rng.next_float() - 4, 8 * rng.next_float() - 4, 8 * rng.next_float() - 4);
            Float side = dot(ref - c.p, c.n);
            if (std::abs(side) < 1e-3f) continue;
            EXPECT_EQ(m.behind_triangle(0, ref), side < 0) << "flip " << flip;
        }
    }
    // With vertex normals the orientation may vary over the triangle: never "behind".
    TriangleMesh mn = make_mesh({{0, 0, 0}, {1, 0, 0}, {0, 1, 0}}, {0, 1, 2},
                                {{0, 0, 1}, {0, 0, 1}, {0, 0, 1}});
    EXPECT_FALSE(mn.behind_triangle(0, Point3(0.2f, 0.2f, -5)));
}

TEST(Shapes, SphereAndDiskAreaSamplingIsUniform) {
    // Uniform by area: on a sphere z and phi are uniform (Archimedes), on a disk r^2 and phi.
    const int n = 100000;
    Pcg32 rng(13, 14);
    {
        Transform x = Transform::translate({0, 0, 1}) * Transform::scale({1.5, 1.5, 1.5});
        Sphere s = make_sphere(2, x);
        std::vector<Vec2d> pts;
        for (int k = 0; k < n; ++k) {
            ShapeSample ss = s.sample_area({rng.next_float(), rng.next_float()});
            ASSERT_NEAR(ss.pdf, 1 / (4 * kPiD * 9), 1e-7);
            Vec3d q = (Vec3d(ss.p) - Vec3d(0, 0, 1)) / 3.0;
            ASSERT_NEAR(length(q), 1, 1e-5);
            ASSERT_NEAR(dot(Vec3d(ss.n), q), 1, 1e-5);
            pts.push_back({(q.z + 1) / 2, azimuth01(q.x, q.y)});
        }
        EXPECT_GT(uniform_chi2_p(pts, 10, 10), kAlpha) << "full sphere";
    }
    {
        Sphere s = make_sphere(1);
        set_z_range(s, -0.3f, 0.8f);
        s.phi_max = Float(1.5 * kPiD);
        std::vector<Vec2d> pts;
        for (int k = 0; k < n; ++k) {
            ShapeSample ss = s.sample_area({rng.next_float(), rng.next_float()});
            ASSERT_NEAR(ss.pdf, 1 / (1.5 * kPiD * 1.1), 1e-5);
            ASSERT_GE(ss.p.z, -0.3f - 1e-6f);
            ASSERT_LE(ss.p.z, 0.8f + 1e-6f);
            pts.push_back({(ss.p.z + 0.3) / 1.1, azimuth01(ss.p.x, ss.p.y) / 0.75});
        }
        EXPECT_GT(uniform_chi2_p(pts, 10, 10), kAlpha) << "partial sphere";
    }
    for (int variant = 0; variant < 2; ++variant) {
        Disk d;
        d.radius = 2;
        d.height = 0.5f;
        if (variant == 1) {
            d.inner_radius = 0.7f;
            d.phi_max = Float(1.2 * kPiD);
        }
        double ri2 = sqr(double(d.inner_radius));
        double area = double(d.phi_max) / 2 * (4 - ri2);
        std::vector<Vec2d> pts;
        for (int k = 0; k < n; ++k) {
            ShapeSample ss = d.sample_area({rng.next_float(), rng.next_float()});
            ASSERT_NEAR(ss.pdf, 1 / area, 1e-6);
            ASSERT_NEAR(ss.p.z, 0.5, 1e-6);
            ASSERT_NEAR(ss.n.z, 1, 1e-6);
            double r2 = sqr(double(ss.p.x)) + sqr(double(ss.p.y));
            pts.push_back({(r2 - ri2) / (4 - ri2), azimuth01(ss.p.x, ss.p.y) * 2 * kPiD / d.phi_max});
        }
        EXPECT_GT(uniform_chi2_p(pts, 10, 10), kAlpha) << "disk variant " << variant;
    }
}

// ---- disk intersection ----------------------------------------------------------------------

TEST(Disk, IntersectionRespectsRadiiAndPhiMax) {
    Disk d;
    d.height = 0.5f;
    d.radius = 2;
    d.inner_radius = 0.5f;
    d.phi_max = kPi;  // y >= 0
    Float t;
    Point3 p;
    ASSERT_TRUE(d.intersect_object({1, 1, 3}, {0, 0, -1}, kInfinity, t, p));
    EXPECT_NEAR(t, 2.5, 1e-6);
    EXPECT_EQ(p.z, 0.5f);
    ASSERT_TRUE(d.intersect_object({1, 1, -1}, {0, 0, 2}, kInfinity, t, p));  // from below
    EXPECT_NEAR(t, 0.75, 1e-6);
    EXPECT_FALSE(d.intersect_object({0.2f, 0.2f, 3}, {0, 0, -1}, kInfinity, t, p));  // hole
    EXPECT_FALSE(d.intersect_object({1, -1, 3}, {0, 0, -1}, kInfinity, t, p));       // phi cut
    EXPECT_FALSE(d.intersect_object({2.1f, 0.1f, 3}, {0, 0, -1}, kInfinity, t, p));  // outside
    EXPECT_FALSE(d.intersect_object({1, 1, 0.5f}, {1, 0, 0}, kInfinity, t, p));      // parallel
    EXPECT_FALSE(d.intersect_object({1, 1, 3}, {0, 0, 1}, kInfinity, t, p));         // away
    EXPECT_FALSE(d.intersect_object({1, 1, 3}, {0, 0, -1}, 2.4f, t, p));             // t_max
    // Oblique: from (0, 0, 2.5) towards (1.5, 1, 0.5): t = 1 for that direction vector.
    ASSERT_TRUE(d.intersect_object({0, 0, 2.5f}, {1.5f, 1, -2}, kInfinity, t, p));
    EXPECT_NEAR(t, 1, 1e-6);
    EXPECT_NEAR(p.x, 1.5, 1e-6);
    EXPECT_NEAR(p.y, 1, 1e-6);
}

// ---- sphere sampling by solid angle ------------------------------------------------------------

TEST(Sphere, SampleFromOutsideCoversTheVisibleCapUniformlyInSolidAngle) {
    // Radius 2 scaled by 0.4: world radius 0.8, centre c; references at several distances
    // (the last one in the small-cone branch, sin^2 theta_max < sin^2 1.5 deg).
    Point3 c(1, -2, 0.5f);
    Sphere s = make_sphere(2, Transform::translate(Vec3d(c)) * Transform::scale({0.4, 0.4, 0.4}));
    const double r = 0.8;
    for (double dist : {0.85, 1.2, 3.0, 40.0}) {
        Vec3d axis = normalize(Vec3d(0.3, -0.5, 0.8));
        Point3 ref = Point3(Vec3d(c) + axis * dist);
        double sin2 = r * r / (dist * dist);
        double one_minus_cos = dist > 30 ? sin2 / 2 + sin2 * sin2 / 8 : 1 - std::sqrt(1 - sin2);
        double pdf = 1 / (2 * kPiD * one_minus_cos);
        Frame f = Frame::from_z(Vec3(-axis));  // cone axis: from ref towards c
        Pcg32 rng(17, uint64_t(dist * 100));
        const int n = 50000;
        std::vector<Vec2d> pts;
        for (int k = 0; k < n; ++k) {
            ShapeSample ss = s.sample_from(ref, {rng.next_float(), rng.next_float()});
            // On the sphere, on the visible cap, with the cone's constant pdf.
            ASSERT_NEAR(distance(Vec3d(ss.p), Vec3d(c)), r, 2e-5 * (1 + dist));
            ASSERT_NEAR(dot(Vec3d(ss.n), (Vec3d(ss.p) - Vec3d(c)) / r), 1, 1e-4);
            ASSERT_GT(dot(Vec3d(ss.n), Vec3d(ref) - Vec3d(ss.p)), -1e-4 * dist) << "hidden side";
            ASSERT_NEAR(ss.pdf / pdf, 1, 2e-4) << "dist " << dist;
            EXPECT_NEAR(s.pdf_from(ref, ss.p, ss.n) / pdf, 1, 2e-4);
            // The direction is uniform in the cone: (1 - cos) / (1 - cos_max) and phi uniform.
            Vec3d w = Vec3d(f.to_local(normalize(ss.p - ref)));
            double omc = (w.x * w.x + w.y * w.y) / (1 + w.z);
            ASSERT_LE(omc / one_minus_cos, 1 + 1e-3);
            pts.push_back({omc / one_minus_cos, azimuth01(w.x, w.y)});
        }
        EXPECT_GT(uniform_chi2_p(pts, 10, 10), kAlpha) << "dist " << dist;
    }
}

/// Integral over all directions from ref of the solid-angle pdf of the sphere point each
/// direction sees first: 1 for any correct density over the visible points. Monte Carlo with
/// uniform directions; returns the z-test p-value against 1 (the estimate in *mean_out).
double pdf_integral_p(const Sphere& s, Point3 ref, int n, uint64_t seed, double* mean_out) {
    Transform object_from_world = s.world_from_object.inverse();
    Pcg32 rng(seed, 3);
    std::vector<double> v;
    v.reserve(n);
    int hits = 0;
    for (int k = 0; k < n; ++k) {
        Vec3 w = sample_uniform_sphere({rng.next_float(), rng.next_float()});
        SurfaceHit h;
        double pdf = 0;
        if (first_hit(s, object_from_world, ref, w, h)) {
            pdf = s.pdf_from(ref, h.p, h.ng);
            ++hits;
        }
        v.push_back(pdf / uniform_sphere_pdf());
    }
    EXPECT_GT(hits, n / 20);  // the sphere covers a good part of the view
    MeanSe m = mean_se(v);
    *mean_out = m.mean;
    return z_test_p(m.mean, 1, m.se);
}

TEST(Sphere, SolidAnglePdfIntegratesToOne) {
    Transform x = Transform::translate({0.5, 0, -1}) * Transform::scale({1.5, 1.5, 1.5});
    Sphere s = make_sphere(1, x);
    double mean = 0;
    // Outside (cone sampling): the pdf is nonzero on the cone only.
    EXPECT_GT(pdf_integral_p(s, Point3(0.5f, 3, -1), 200000, 1, &mean), kAlpha) << mean;
    // Inside (area sampling converted to solid angle): every direction sees one point.
    EXPECT_GT(pdf_integral_p(s, Point3(1, 0.3f, -0.5f), 200000, 2, &mean), kAlpha) << mean;
    // A partial sphere seen from inside its ball (area sampling of the part; each of its
    // points is seen once, and from inside no point is seen edge-on).
    Sphere part = make_sphere(1, x);
    set_z_range(part, -0.6f, 0.9f);
    part.phi_max = Float(1.6 * kPiD);
    EXPECT_GT(pdf_integral_p(part, Point3(0.2f, 0.5f, -0.4f), 200000, 3, &mean), kAlpha) << mean;
}

TEST(Shapes, AreaToSolidAnglePdfIsDistanceSquaredOverCosine) {
    // A point 2 away along +z whose normal is tilted 60 degrees from the line of sight:
    // pdf_sa = pdf_area * 4 / cos 60.
    Normal3 n(std::sin(radians(60)), 0, -std::cos(radians(60)));
    EXPECT_NEAR(area_to_solid_angle_pdf(0.25f, {0, 0, 0}, {0, 0, 2}, n), 0.25 * 4 / 0.5, 1e-5);
    EXPECT_NEAR(area_to_solid_angle_pdf(0.25f, {0, 0, 0}, {0, 0, 2}, -n), 0.25 * 4 / 0.5, 1e-5);
    EXPECT_EQ(area_to_solid_angle_pdf(1, {0, 0, 0}, {0, 0, 2}, {1, 0, 0}), 0);  // edge-on
    EXPECT_EQ(area_to_solid_angle_pdf(1, {1, 1, 1}, {1, 1, 1}, {0, 0, 1}), 0);  // coincident
}

}  // namespace
}  // namespace sr
