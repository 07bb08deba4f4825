#include "steradian/core/transform.h"

#include <gtest/gtest.h>

#include <cmath>
#include <numbers>

#include "steradian/core/error.h"
#include "steradian/core/math.h"
#include "steradian/sampling/rng.h"
#include "steradian/sampling/warp.h"

namespace sr {
namespace {

constexpr double kPiD = std::numbers::pi;

void expect_vec_near(Vec3d a, Vec3d b, double tol, const char* what = "") {
    EXPECT_NEAR(a.x, b.x, tol) << what;
    EXPECT_NEAR(a.y, b.y, tol) << what;
    EXPECT_NEAR(a.z, b.z, tol) << what;
}

void expect_matrix_near(const Matrix4& a, const Matrix4& b, double tol) {
    for (int i = 0; i < 4; ++i)
        for (int j = 0; j < 4; ++j) EXPECT_NEAR(a.m[i][j], b.m[i][j], tol) << "entry " << i << j;
}

Vec3d random_unit(Pcg32& rng) {
    return Vec3d(sample_uniform_sphere({rng.next_float(), rng.next_float()}));
}

/// 3x3 determinant of the linear part.
double det3(const Matrix4& m) {
    const auto& a = m.m;
    return a[0][0] * (a[1][1] * a[2][2] - a[1][2] * a[2][1]) -
           a[0][1] * (a[1][0] * a[2][2] - a[1][2] * a[2][0]) +
           a[0][2] * (a[1][0] * a[2][1] - a[1][1] * a[2][0]);
}

// ---- Matrix4 ------------------------------------------------------------------------------

TEST(Matrix4, InverseOfRandomWellConditionedMatricesIsTwoSided) {
    // M = 4 I + E with |E_ij| <= 1 is strictly diagonally dominant (hence invertible, with a
    // condition number of a few): M M^-1 = M^-1 M = I to double round-off.
    Pcg32 rng(7, 1234);
    for (int trial = 0; trial < 200; ++trial) {
        Matrix4 m;
        for (int i = 0; i < 4; ++i)
            for (int j = 0; j < 4; ++j)
                m.m[i][j] = (i == j ? 4.0 : 0.0) + 2.0 * rng.next_float() - 1.0;
        // Row swaps make partial pivoting do work.
        if (trial % 2) std::swap(m.m[0], m.m[3]);
        auto inv = m.inverse();
        ASSERT_TRUE(inv.has_value());
        expect_matrix_near(m * *inv, Matrix4::identity(), 1e-12);
        expect_matrix_near(*inv * m, Matrix4::identity(), 1e-12);
    }
}

TEST(Matrix4, InverseOfKnownMatrix) {
    // A hand-inverted matrix: upper triangular with unit diagonal, [[1,2],[0,1]]^-1 =
    // [[1,-2],[0,1]] in each 2x2 block, plus a diagonal scale.
    Matrix4 m = Matrix4::from_rows({1, 2, 0, 0, 0, 1, 0, 0, 0, 0, 2, 0, 0, 0, 0, 0.5});
    Matrix4 expected = Matrix4::from_rows({1, -2, 0, 0, 0, 1, 0, 0, 0, 0, 0.5, 0, 0, 0, 0, 2});
    auto inv = m.inverse();
    ASSERT_TRUE(inv.has_value());
    expect_matrix_near(*inv, expected, 1e-15);
}

TEST(Matrix4, SingularMatrixHasNoInverse) {
    // Third row = first + second: rank 3.
    Matrix4 m = Matrix4::from_rows({1, 2, 3, 4, 0, 1, 1, 0, 1, 3, 4, 4, 0, 0, 0, 1});
    EXPECT_FALSE(m.inverse().has_value());
    EXPECT_THROW(Transform{m}, Error);
    EXPECT_THROW(Transform::scale({1, 0, 1}), Error);
}

TEST(Matrix4, ProductAndTranspose) {
    Matrix4 a = Matrix4::from_rows({1, 2, 3, 4, 5, 6, 7, 8, 9, 10, 11, 12, 13, 14, 15, 16});
    // (A A^T)_00 = 1 + 4 + 9 + 16 = 30, (A A^T)_01 = 5 + 12 + 21 + 32 = 70.
    Matrix4 p = a * a.transposed();
    EXPECT_EQ(p.m[0][0], 30);
    EXPECT_EQ(p.m[0][1], 70);
    EXPECT_EQ(p.m[1][0], 70);
    EXPECT_EQ(a.transposed().m[0][3], 13);
    EXPECT_TRUE(Matrix4::identity().is_identity());
    EXPECT_FALSE(a.is_identity());
}

// ---- translate / scale / composition ------------------------------------------------------

TEST(Transform, TranslateMovesPointsNotVectors) {
    Transform t = Transform::translate({1, -2, 3});
    expect_vec_near(t.point(Vec3d(1, 1, 1)), Vec3d(2, -1, 4), 0);
    expect_vec_near(t.vector(Vec3d(1, 1, 1)), Vec3d(1, 1, 1), 0);
    expect_vec_near(t.normal(Vec3d(0, 0, 1)), Vec3d(0, 0, 1), 0);
    expect_vec_near(t.inverse().point(Vec3d(2, -1, 4)), Vec3d(1, 1, 1), 0);
}

TEST(Transform, CompositionAppliesRightFactorFirst) {
    // T * S: scale first, then translate.
    Transform ts = Transform::translate({1, 0, 0}) * Transform::scale({2, 2, 2});
    expect_vec_near(ts.point(Vec3d(1, 1, 1)), Vec3d(3, 2, 2), 1e-15);
    // The stored inverse is the inverse of the product.
    expect_matrix_near(ts.matrix() * ts.inverse_matrix(), Matrix4::identity(), 1e-15);
    expect_vec_near(ts.inverse().point(Vec3d(3, 2, 2)), Vec3d(1, 1, 1), 1e-15);
}

// ---- rotate -------------------------------------------------------------------------------

TEST(Transform, Rotate90AboutAxesFollowsRightHandRule) {
    const double tol = 1e-15;
    // About +z: x -> y, y -> -x (counter-clockwise seen from +z looking down).
    Transform rz = Transform::rotate(90, {0, 0, 1});
    expect_vec_near(rz.vector(Vec3d(1, 0, 0)), Vec3d(0, 1, 0), tol, "Rz x");
    expect_vec_near(rz.vector(Vec3d(0, 1, 0)), Vec3d(-1, 0, 0), tol, "Rz y");
    expect_vec_near(rz.vector(Vec3d(0, 0, 1)), Vec3d(0, 0, 1), tol, "Rz z");
    // About +x: y -> z, z -> -y.
    Transform rx = Transform::rotate(90, {1, 0, 0});
    expect_vec_near(rx.vector(Vec3d(0, 1, 0)), Vec3d(0, 0, 1), tol, "Rx y");
    expect_vec_near(rx.vector(Vec3d(0, 0, 1)), Vec3d(0, -1, 0), tol, "Rx z");
    expect_vec_near(rx.vector(Vec3d(1, 0, 0)), Vec3d(1, 0, 0), tol, "Rx x");
    // About +y: z -> x, x -> -z.
    Transform ry = Transform::rotate(90, {0, 1, 0});
    expect_vec_near(ry.vector(Vec3d(0, 0, 1)), Vec3d(1, 0, 0), tol, "Ry z");
    expect_vec_near(ry.vector(Vec3d(1, 0, 0)), Vec3d(0, 0, -1), tol, "Ry x");
    // The axis need not be unit length.
    Transform rz5 = Transform::rotate(90, {0, 0, 5});
    expect_vec_near(rz5.vector(Vec3d(1, 0, 0)), Vec3d(0, 1, 0), tol, "Rz (|axis| = 5)");
    // A negative angle rotates the other way.
    expect_vec_near(Transform::rotate(-90, {0, 0, 1}).vector(Vec3d(1, 0, 0)), Vec3d(0, -1, 0), tol);
}

TEST(Transform, RotationAboutArbitraryAxisIsOrthonormalAndRightHanded) {
    Pcg32 rng(11, 99);
    for (int trial = 0; trial < 200; ++trial) {
        Vec3d axis = random_unit(rng) * (0.1 + 3.0 * rng.next_float());
        double theta = -180.0 + 360.0 * rng.next_float();
        Transform r = Transform::rotate(theta, axis);
        // R^-1 = R^T, R R^T = I, det R = +1.
        expect_matrix_near(r.inverse_matrix(), r.matrix().transposed(), 1e-15);
        expect_matrix_near(r.matrix() * r.matrix().transposed(), Matrix4::identity(), 1e-14);
        EXPECT_NEAR(det3(r.matrix()), 1.0, 1e-14);
        EXPECT_FALSE(r.swaps_handedness());
        // The axis is fixed; lengths are preserved.
        Vec3d a = normalize(axis);
        expect_vec_near(r.vector(a), a, 1e-14, "axis fixed");
        Vec3d v = random_unit(rng) * 2.5;
        EXPECT_NEAR(length(r.vector(v)), length(v), 1e-14);
        // The component perpendicular to the axis turns by theta, counter-clockwise about a:
        // cos = (vp . Rvp) / |vp|^2, sin = a . (vp x Rvp) / |vp|^2.
        Vec3d vp = v - a * dot(v, a);
        Vec3d rvp = r.vector(vp);
        double l2 = length_squared(vp);
        if (l2 < 1e-6) continue;
        double th = theta * kPiD / 180;
        EXPECT_NEAR(dot(vp, rvp) / l2, std::cos(th), 1e-12);
        EXPECT_NEAR(dot(a, cross(vp, rvp)) / l2, std::sin(th), 1e-12);
    }
}

// ---- look_at -------------------------------------------------------------------------------

TEST(Transform, LookAtMapsEyeToOriginAndViewDirectionToPlusZ) {
    Pcg32 rng(3, 5);
    for (int trial = 0; trial < 100; ++trial) {
        Vec3d pos(10.0 * rng.next_float() - 5, 10.0 * rng.next_float() - 5,
                  10.0 * rng.next_float() - 5);
        Vec3d dir = normalize(random_unit(rng));  // unit in double precision
        double dist = 0.5 + 4.0 * rng.next_float();
        Vec3d look = pos + dir * dist;
        Vec3d up = random_unit(rng);
        if (length(cross(up, dir)) < 0.1) continue;
        Transform cam_from_world = Transform::look_at(pos, look, up);
        expect_vec_near(cam_from_world.point(pos), Vec3d(0, 0, 0), 1e-12, "eye");
        expect_vec_near(cam_from_world.point(look), Vec3d(0, 0, dist), 1e-12, "look");
        // up lies in the camera's y-z half plane with y > 0.
        Vec3d up_c = cam_from_world.vector(up);
        EXPECT_NEAR(up_c.x, 0, 1e-12);
        EXPECT_GT(up_c.y, 0);
        // A rigid motion: orthonormal, no change of handedness, lengths kept.
        expect_matrix_near(cam_from_world.matrix() * cam_from_world.inverse_matrix(),
                           Matrix4::identity(), 1e-12);
        EXPECT_NEAR(det3(cam_from_world.matrix()), 1.0, 1e-12);
        EXPECT_NEAR(length(cam_from_world.vector(up)), length(up), 1e-12);
    }
}

TEST(Transform, LookAtMatchesHandDerivedMatrix) {
    // Eye (1, 2, 3) looking down -x with up +z. pbrt's LookAt: dir = (-1, 0, 0),
    // right = up x dir = z x (-x) = (0, -1, 0), new up = dir x right = (-x) x (-y) = (0, 0, 1).
    // camera-from-world has rows right, up, dir and translation -R pos:
    //   x_c = -(y - 2), y_c = z - 3, z_c = -(x - 1).
    Transform t = Transform::look_at({1, 2, 3}, {-4, 2, 3}, {0, 0, 1});
    Matrix4 expected = Matrix4::from_rows({0, -1, 0, 2, 0, 0, 1, -3, -1, 0, 0, 1, 0, 0, 0, 1});
    expect_matrix_near(t.matrix(), expected, 1e-15);
    // The identity case: eye at the origin looking down +z with up +y.
    expect_matrix_near(Transform::look_at({0, 0, 0}, {0, 0, 1}, {0, 1, 0}).matrix(),
                       Matrix4::identity(), 1e-15);
}

TEST(Transform, LookAtRejectsDegenerateInput) {
    EXPECT_THROW(Transform::look_at({1, 1, 1}, {1, 1, 1}, {0, 1, 0}), Error);
    EXPECT_THROW(Transform::look_at({0, 0, 0}, {0, 2, 0}, {0, 1, 0}), Error);
}

// ---- perspective / orthographic -------------------------------------------------------------

TEST(Transform, PerspectiveMapsFrustumEdgesToPlusMinusOne) {
    const double n = 0.1, f = 100;
    for (double fov : {30.0, 60.0, 90.0, 120.0}) {
        Transform p = Transform::perspective(fov, n, f);
        double tan_half = std::tan(fov * kPiD / 360);
        for (double z : {0.1, 1.0, 7.5, 100.0}) {
            double e = z * tan_half;  // half-width of the frustum at depth z
            expect_vec_near(p.point(Vec3d(e, 0, z)), Vec3d(1, 0, (z - n) * f / (z * (f - n))),
                            1e-12, "right edge");
            EXPECT_NEAR(p.point(Vec3d(-e, 0, z)).x, -1, 1e-12);
            EXPECT_NEAR(p.point(Vec3d(0, e, z)).y, 1, 1e-12);
            EXPECT_NEAR(p.point(Vec3d(0, -e, z)).y, -1, 1e-12);
            // The corner direction at half the angle's tangent lands at 0.5.
            EXPECT_NEAR(p.point(Vec3d(0.5 * e, -0.5 * e, z)).x, 0.5, 1e-12);
            EXPECT_NEAR(p.point(Vec3d(0.5 * e, -0.5 * e, z)).y, -0.5, 1e-12);
        }
        // Near plane -> z = 0, far plane -> z = 1.
        EXPECT_NEAR(p.point(Vec3d(0, 0, n)).z, 0, 1e-12);
        EXPECT_NEAR(p.point(Vec3d(0, 0, f)).z, 1, 1e-12);
    }
}

TEST(Transform, OrthographicMapsDepthRangeToUnitInterval) {
    Transform o = Transform::orthographic(2, 10);
    expect_vec_near(o.point(Vec3d(0.3, -0.7, 2)), Vec3d(0.3, -0.7, 0), 1e-15);
    expect_vec_near(o.point(Vec3d(0.3, -0.7, 10)), Vec3d(0.3, -0.7, 1), 1e-15);
    expect_vec_near(o.point(Vec3d(0, 0, 6)), Vec3d(0, 0, 0.5), 1e-15);
}

// ---- normals, handedness ----------------------------------------------------------------------

TEST(Transform, NormalsStayPerpendicularUnderNonUniformScale) {
    // Plane x + y = 0: normal (1, 1, 0), tangent (1, -1, 0). Under Scale(4, 1, 1) the tangent
    // maps to (4, -1, 0); the vector map would take the normal to (4, 1, 0), which is not
    // perpendicular (dot 15); the inverse transpose gives (1/4, 1, 0) (dot 0).
    Transform s = Transform::scale({4, 1, 1});
    Vec3d n(1, 1, 0), t(1, -1, 0);
    EXPECT_NEAR(dot(s.vector(n), s.vector(t)), 15, 1e-12);  // the wrong way, for contrast
    expect_vec_near(s.normal(n), Vec3d(0.25, 1, 0), 1e-15);
    EXPECT_NEAR(dot(s.normal(n), s.vector(t)), 0, 1e-15);

    // Random non-uniform, sheared transforms and random tangent planes.
    Pcg32 rng(17, 4);
    for (int trial = 0; trial < 200; ++trial) {
        Transform x = Transform::rotate(360.0 * rng.next_float(), random_unit(rng)) *
                      Transform::scale({0.2 + 3.0 * rng.next_float(), 0.2 + 3.0 * rng.next_float(),
                                        -(0.2 + 3.0 * rng.next_float())}) *
                      Transform::rotate(360.0 * rng.next_float(), random_unit(rng)) *
                      Transform::translate({1, 2, 3});
        Vec3d nn = random_unit(rng);
        Vec3d t1 = normalize(cross(nn, random_unit(rng)));
        Vec3d t2 = cross(nn, t1);
        Vec3d nw = normalize(x.normal(nn));
        EXPECT_NEAR(dot(nw, normalize(x.vector(t1))), 0, 1e-12);
        EXPECT_NEAR(dot(nw, normalize(x.vector(t2))), 0, 1e-12);
    }
}

TEST(Transform, SwapsHandednessIsTheSignOfTheDeterminant) {
    EXPECT_TRUE(Transform::scale({-1, 1, 1}).swaps_handedness());
    EXPECT_TRUE(Transform::scale({-1, -1, -1}).swaps_handedness());
    EXPECT_FALSE(Transform::scale({-1, -1, 1}).swaps_handedness());
    EXPECT_FALSE(Transform::scale({2, 3, 4}).swaps_handedness());
    EXPECT_FALSE(Transform().swaps_handedness());
    EXPECT_FALSE(Transform::translate({-1, -1, -1}).swaps_handedness());
    EXPECT_TRUE((Transform::rotate(33, {1, 2, 3}) * Transform::scale({1, 1, -2})).swaps_handedness());
    // A mirror reverses the orientation of a cross product: M(a) x M(b) = -M(a x b).
    Transform m = Transform::scale({-1, 1, 1});
    Vec3d a(1, 2, 3), b(-2, 0.5, 1);
    expect_vec_near(cross(m.vector(a), m.vector(b)), -1.0 * m.normal(cross(a, b)), 1e-14);
}

// ---- coordinate_system / Frame -------------------------------------------------------------------

void expect_orthonormal_right_handed(Vec3 s, Vec3 t, Vec3 n) {
    EXPECT_NEAR(length(s), 1, 1e-6);
    EXPECT_NEAR(length(t), 1, 1e-6);
    EXPECT_NEAR(dot(s, t), 0, 1e-6);
    EXPECT_NEAR(dot(s, n), 0, 1e-6);
    EXPECT_NEAR(dot(t, n), 0, 1e-6);
    Vec3 c = cross(s, t);  // right-handed: s x t = n
    EXPECT_NEAR(c.x, n.x, 1e-6);
    EXPECT_NEAR(c.y, n.y, 1e-6);
    EXPECT_NEAR(c.z, n.z, 1e-6);
}

TEST(CoordinateSystem, OrthonormalRightHandedBasisForAnyUnitVector) {
    // Includes the poles and directions just off -z, where a naive formula divides by ~0.
    std::vector<Vec3> ns = {{0, 0, 1}, {0, 0, -1}, {1, 0, 0}, {0, 1, 0}, {0, -1, 0}};
    ns.push_back(normalize(Vec3(1e-4f, 2e-4f, -1)));
    ns.push_back(normalize(Vec3(-1e-7f, 0, -1)));
    Pcg32 rng(23, 8);
    for (int i = 0; i < 1000; ++i) ns.push_back(sample_uniform_sphere({rng.next_float(), rng.next_float()}));
    for (Vec3 n : ns) {
        Vec3 s, t;
        coordinate_system(n, s, t);
        expect_orthonormal_right_handed(s, t, n);
    }
}

TEST(Frame, RoundTripsAndMapsNormalToZ) {
    Pcg32 rng(29, 2);
    for (int i = 0; i < 500; ++i) {
        Vec3 n = sample_uniform_sphere({rng.next_float(), rng.next_float()});
        Frame f = Frame::from_z(n);
        expect_orthonormal_right_handed(f.s, f.t, f.n);
        Vec3 nl = f.to_local(n);
        EXPECT_NEAR(nl.x, 0, 1e-6);
        EXPECT_NEAR(nl.y, 0, 1e-6);
        EXPECT_NEAR(nl.z, 1, 1e-6);
        Vec3 v(4 * rng.next_float() - 2, 4 * rng.next_float() - 2, 4 * rng.next_float() - 2);
        Vec3 back = f.to_world(f.to_local(v));
        EXPECT_NEAR(back.x, v.x, 1e-5);
        EXPECT_NEAR(back.y, v.y, 1e-5);
        EXPECT_NEAR(back.z, v.z, 1e-5);
        Vec3 back2 = f.to_local(f.to_world(v));
        EXPECT_NEAR(back2.x, v.x, 1e-5);
        EXPECT_NEAR(back2.y, v.y, 1e-5);
        EXPECT_NEAR(back2.z, v.z, 1e-5);
        // Lengths and dot products are preserved.
        Vec3 w(rng.next_float(), -rng.next_float(), 0.5f);
        EXPECT_NEAR(dot(f.to_local(v), f.to_local(w)), dot(v, w), 1e-5);
    }
}

TEST(Math, SphericalDirectionAndLocalTrigonometry) {
    // theta = 60 deg, phi = 30 deg: (sin60 cos30, sin60 sin30, cos60) = (3/4, sqrt(3)/4, 1/2).
    Float th = radians(60), ph = radians(30);
    Vec3 w = spherical_direction(std::sin(th), std::cos(th), ph);
    EXPECT_NEAR(w.x, 0.75, 1e-6);
    EXPECT_NEAR(w.y, std::sqrt(3.0) / 4, 1e-6);
    EXPECT_NEAR(w.z, 0.5, 1e-6);
    EXPECT_NEAR(cos_theta(w), 0.5, 1e-6);
    EXPECT_NEAR(sin2_theta(w), 0.75, 1e-6);
    EXPECT_NEAR(tan2_theta(w), 3, 1e-5);
    EXPECT_NEAR(cos_phi(w), std::cos(ph), 1e-6);
    EXPECT_NEAR(sin_phi(w), std::sin(ph), 1e-6);
    EXPECT_TRUE(same_hemisphere(w, Vec3(0, 0, 1)));
    EXPECT_FALSE(same_hemisphere(w, Vec3(0, 0, -1)));
    Vec3 ff = face_forward(Vec3(0, 0, 1), Vec3(0.1f, 0, -1));
    EXPECT_EQ(ff.z, -1);
}

}  // namespace
}  // namespace sr
