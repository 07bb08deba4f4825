#pragma once
/// 4x4 affine/projective transforms in double precision (scene building), applied to
/// Float points, vectors and normals.
#include <array>
#include <optional>

#include "steradian/core/math.h"

namespace sr {

struct Matrix4 {
    std::array<std::array<double, 4>, 4> m{};
    static Matrix4 identity();
    /// Row-major construction: m[row][col].
    static Matrix4 from_rows(const std::array<double, 16>& v);
    Matrix4 operator*(const Matrix4& o) const;
    Matrix4 transposed() const;
    /// Inverse by Gauss-Jordan with partial pivoting; empty when singular.
    std::optional<Matrix4> inverse() const;
    bool operator==(const Matrix4&) const = default;
    bool is_identity() const;
};

/// A transform and its inverse. Points map with the full matrix (homogeneous divide),
/// vectors with the upper 3x3, normals with the inverse transpose.
class Transform {
public:
    Transform() : m_m(Matrix4::identity()), m_inv(Matrix4::identity()) {}
    Transform(const Matrix4& m, const Matrix4& inv) : m_m(m), m_inv(inv) {}
    /// Throws sr::Error if m is singular.
    explicit Transform(const Matrix4& m);

    static Transform translate(Vec3d d);
    static Transform scale(Vec3d s);
    /// Rotation by theta_deg degrees about axis (right-handed, as pbrt's Rotate).
    static Transform rotate(double theta_deg, Vec3d axis);
    /// pbrt's LookAt: the camera-from-world... returns world-from-camera's inverse, i.e.
    /// the matrix that maps world space to camera space (camera at origin looking down +z).
    static Transform look_at(Vec3d pos, Vec3d look, Vec3d up);
    /// Perspective projection with pbrt's conventions (fov in degrees, z mapped to [0,1]).
    static Transform perspective(double fov_deg, double znear, double zfar);
    static Transform orthographic(double znear, double zfar);

    const Matrix4& matrix() const { return m_m; }
    const Matrix4& inverse_matrix() const { return m_inv; }
    Transform inverse() const { return {m_inv, m_m}; }
    Transform operator*(const Transform& o) const { return {m_m * o.m_m, o.m_inv * m_inv}; }
    bool operator==(const Transform& o) const { return m_m == o.m_m; }
    bool is_identity() const { return m_m.is_identity(); }
    /// Every entry of the matrix and of its inverse is finite.
    bool is_finite() const;
    /// True if the transform flips handedness (negative determinant of the 3x3 part).
    bool swaps_handedness() const;

    Vec3d point(Vec3d p) const;
    Vec3d vector(Vec3d v) const;
    Vec3d normal(Vec3d n) const;
    Point3 point(Point3 p) const { return Point3(point(Vec3d(p))); }
    Vec3 vector(Vec3 v) const { return Vec3(vector(Vec3d(v))); }
    Normal3 normal(Normal3 n) const { return Normal3(normal(Vec3d(n))); }

private:
    Matrix4 m_m, m_inv;
};

}  // namespace sr
