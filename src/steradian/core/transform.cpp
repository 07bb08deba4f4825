#include "steradian/core/transform.h"

#include <cmath>

#include "steradian/core/error.h"

namespace sr {

Matrix4 Matrix4::identity() {
    Matrix4 r;
    for (int i = 0; i < 4; ++i) r.m[i][i] = 1;
    return r;
}

Matrix4 Matrix4::from_rows(const std::array<double, 16>& v) {
    Matrix4 r;
    for (int i = 0; i < 4; ++i)
        for (int j = 0; j < 4; ++j) r.m[i][j] = v[4 * i + j];
    return r;
}

Matrix4 Matrix4::operator*(const Matrix4& o) const {
    Matrix4 r;
    for (int i = 0; i < 4; ++i)
        for (int j = 0; j < 4; ++j) {
            double s = 0;
            for (int k = 0; k < 4; ++k) s += m[i][k] * o.m[k][j];
            r.m[i][j] = s;
        }
    return r;
}

Matrix4 Matrix4::transposed() const {
    Matrix4 r;
    for (int i = 0; i < 4; ++i)
        for (int j = 0; j < 4; ++j) r.m[i][j] = m[j][i];
    return r;
}

bool Matrix4::is_identity() const { return *this == identity(); }

std::optional<Matrix4> Matrix4::inverse() const {
    double a[4][8];
    for (int i = 0; i < 4; ++i)
        for (int j = 0; j < 4; ++j) {
            a[i][j] = m[i][j];
            a[i][j + 4] = i == j ? 1.0 : 0.0;
        }
    for (int c = 0; c < 4; ++c) {
        int piv = c;
        for (int r = c + 1; r < 4; ++r)
            if (std::abs(a[r][c]) > std::abs(a[piv][c])) piv = r;
        if (std::abs(a[piv][c]) < 1e-300) return std::nullopt;
        if (piv != c)
            for (int j = 0; j < 8; ++j) std::swap(a[c][j], a[piv][j]);
        double inv = 1.0 / a[c][c];
        for (int j = 0; j < 8; ++j) a[c][j] *= inv;
        for (int r = 0; r < 4; ++r) {
            if (r == c || a[r][c] == 0) continue;
            double f = a[r][c];
            for (int j = 0; j < 8; ++j) a[r][j] -= f * a[c][j];
        }
    }
    Matrix4 r;
    for (int i = 0; i < 4; ++i)
        for (int j = 0; j < 4; ++j) r.m[i][j] = a[i][j + 4];
    return r;
}

Transform::Transform(const Matrix4& m) : m_m(m) {
    auto inv = m.inverse();
    if (!inv) throw Error("singular transformation matrix");
    m_inv = *inv;
}

Transform Transform::translate(Vec3d d) {
    Matrix4 m = Matrix4::identity(), inv = Matrix4::identity();
    m.m[0][3] = d.x; m.m[1][3] = d.y; m.m[2][3] = d.z;
    inv.m[0][3] = -d.x; inv.m[1][3] = -d.y; inv.m[2][3] = -d.z;
    return {m, inv};
}

Transform Transform::scale(Vec3d s) {
    Matrix4 m = Matrix4::identity();
    m.m[0][0] = s.x; m.m[1][1] = s.y; m.m[2][2] = s.z;
    return Transform(m);
}

Transform Transform::rotate(double theta_deg, Vec3d axis) {
    Vec3d a = normalize(axis);
    double th = theta_deg * std::numbers::pi / 180.0;
    double s = std::sin(th), c = std::cos(th);
    Matrix4 m = Matrix4::identity();
    m.m[0][0] = a.x * a.x + (1 - a.x * a.x) * c;
    m.m[0][1] = a.x * a.y * (1 - c) - a.z * s;
    m.m[0][2] = a.x * a.z * (1 - c) + a.y * s;
    m.m[1][0] = a.x * a.y * (1 - c) + a.z * s;
    m.m[1][1] = a.y * a.y + (1 - a.y * a.y) * c;
    m.m[1][2] = a.y * a.z * (1 - c) - a.x * s;
    m.m[2][0] = a.x * a.z * (1 - c) - a.y * s;
    m.m[2][1] = a.y * a.z * (1 - c) + a.x * s;
    m.m[2][2] = a.z * a.z + (1 - a.z * a.z) * c;
    return {m, m.transposed()};
}

bool Transform::is_finite() const {
    for (int i = 0; i < 4; ++i)
        for (int j = 0; j < 4; ++j)
            if (!std::isfinite(m_m.m[i][j]) || !std::isfinite(m_inv.m[i][j])) return false;
    return true;
}

Transform Transform::look_at(Vec3d pos, Vec3d look, Vec3d up) {
    // Written as !(x > 0) so that NaN and infinite inputs are errors too (a zero up vector
    // used to give a NaN transform, and an abort inside Embree at the first ray).
    Vec3d dir = look - pos;
    if (!(length(dir) > 0) || !std::isfinite(length(dir)))
        throw Error("LookAt: eye and look-at points coincide or are not finite");
    dir = normalize(dir);
    if (!(length(up) > 0) || !std::isfinite(length(up)))
        throw Error("LookAt: the up vector is zero or not finite");
    Vec3d upn = normalize(up);
    Vec3d right = cross(upn, dir);
    if (!(length(right) > 0)) throw Error("LookAt: up vector is parallel to the viewing direction");
    right = normalize(right);
    Vec3d new_up = cross(dir, right);
    // world-from-camera: columns right, up, dir, pos
    Matrix4 wc = Matrix4::identity();
    for (int i = 0; i < 3; ++i) {
        wc.m[i][0] = right[i];
        wc.m[i][1] = new_up[i];
        wc.m[i][2] = dir[i];
        wc.m[i][3] = pos[i];
    }
    Matrix4 cw = *wc.inverse();
    return {cw, wc};
}

Transform Transform::perspective(double fov_deg, double n, double f) {
    Matrix4 persp = Matrix4::from_rows({1, 0, 0, 0, 0, 1, 0, 0, 0, 0, f / (f - n), -f * n / (f - n),
                                        0, 0, 1, 0});
    double inv_tan = 1.0 / std::tan(fov_deg * std::numbers::pi / 360.0);
    return scale({inv_tan, inv_tan, 1}) * Transform(persp);
}

Transform Transform::orthographic(double n, double f) {
    return scale({1, 1, 1 / (f - n)}) * translate({0, 0, -n});
}

bool Transform::swaps_handedness() const {
    const auto& a = m_m.m;
    double det = a[0][0] * (a[1][1] * a[2][2] - a[1][2] * a[2][1]) -
                 a[0][1] * (a[1][0] * a[2][2] - a[1][2] * a[2][0]) +
                 a[0][2] * (a[1][0] * a[2][1] - a[1][1] * a[2][0]);
    return det < 0;
}

Vec3d Transform::point(Vec3d p) const {
    const auto& a = m_m.m;
    double x = a[0][0] * p.x + a[0][1] * p.y + a[0][2] * p.z + a[0][3];
    double y = a[1][0] * p.x + a[1][1] * p.y + a[1][2] * p.z + a[1][3];
    double z = a[2][0] * p.x + a[2][1] * p.y + a[2][2] * p.z + a[2][3];
    double w = a[3][0] * p.x + a[3][1] * p.y + a[3][2] * p.z + a[3][3];
    return w == 1 ? Vec3d(x, y, z) : Vec3d(x, y, z) / w;
}

Vec3d Transform::vector(Vec3d v) const {
    const auto& a = m_m.m;
    return {a[0][0] * v.x + a[0][1] * v.y + a[0][2] * v.z,
            a[1][0] * v.x + a[1][1] * v.y + a[1][2] * v.z,
            a[2][0] * v.x + a[2][1] * v.y + a[2][2] * v.z};
}

Vec3d Transform::normal(Vec3d n) const {
    const auto& a = m_inv.m;  // transpose of the inverse
    return {a[0][0] * n.x + a[1][0] * n.y + a[2][0] * n.z,
            a[0][1] * n.x + a[1][1] * n.y + a[2][1] * n.z,
            a[0][2] * n.x + a[1][2] * n.y + a[2][2] * n.z};
}

}  // namespace sr
