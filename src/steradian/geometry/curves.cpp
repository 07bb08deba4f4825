#include "steradian/geometry/curves.h"

namespace sr {

std::array<Point3, 4> cubic_bspline_to_bezier(std::span<const Point3, 4> p) {
    // The uniform cubic B-spline segment written in the Bernstein basis: its ends are the
    // averages (p0 + 4 p1 + p2) / 6 and (p1 + 4 p2 + p3) / 6, its inner Bézier points divide
    // p1 p2 in thirds.
    return {(p[0] + p[1] * 4 + p[2]) / 6, (p[1] * 2 + p[2]) / 3, (p[1] + p[2] * 2) / 3,
            (p[1] + p[2] * 4 + p[3]) / 6};
}

std::array<Point3, 3> quadratic_bspline_to_bezier(std::span<const Point3, 3> p) {
    return {(p[0] + p[1]) / 2, p[1], (p[1] + p[2]) / 2};
}

std::array<Point3, 4> elevate_quadratic_bezier(std::span<const Point3, 3> p) {
    return {p[0], p[0] / 3 + p[1] * (Float(2) / 3), p[1] * (Float(2) / 3) + p[2] / 3, p[2]};
}

Point3 cubic_bezier(std::span<const Point3, 4> cp, Float u, Vec3* derivative) {
    // de Casteljau.
    const Point3 a = lerp(u, cp[0], cp[1]), b = lerp(u, cp[1], cp[2]), c = lerp(u, cp[2], cp[3]);
    const Point3 d = lerp(u, a, b), e = lerp(u, b, c);
    if (derivative) *derivative = (e - d) * 3;
    return lerp(u, d, e);
}

Normal3 slerp_normal(Normal3 n0, Normal3 n1, Float u) {
    const Float angle = std::acos(clamp(dot(n0, n1), Float(-1), Float(1)));
    if (!(angle > 1e-6f)) return n0;
    return (n0 * std::sin((1 - u) * angle) + n1 * std::sin(u * angle)) / std::sin(angle);
}

std::array<Point3, 4> Curves::segment(size_t i) const {
    std::array<Point3, 4> p;
    for (int k = 0; k < 4; ++k) {
        const CurvePoint& c = (*cp)[4 * i + k];
        p[k] = Point3(c.x, c.y, c.z);
    }
    return p;
}

namespace {

/// A unit vector perpendicular to the unit vector x, from v (made perpendicular to x), or
/// an arbitrary one if v is (nearly) parallel to x.
Vec3 perpendicular(Vec3 v, Vec3 x) {
    Vec3 w = v - x * dot(v, x);
    Float l2 = length_squared(w);
    if (l2 > 1e-12f) return w / std::sqrt(l2);
    Vec3 s, t;
    coordinate_system(x, s, t);
    return s;
}

}  // namespace

void Curves::fill_hit(uint32_t i, Float u, Point3 o, Vec3 d, Float t, SurfaceHit& h) const {
    u = clamp(u, Float(0), Float(1));
    const std::array<Point3, 4> p = segment(i);
    Vec3 dpdu;
    const Point3 c = cubic_bezier(p, u, &dpdu);
    const Float r = lerp(u, (*cp)[4 * i].r, (*cp)[4 * i + 3].r);
    if (!(length_squared(dpdu) > 0)) dpdu = p[3] - p[0];  // a degenerate end
    if (!(length_squared(dpdu) > 0)) dpdu = Vec3(1, 0, 0);
    const Vec3 x = normalize(dpdu);
    const Point3 ph = o + d * t;
    // The ribbon that faces the ray: its normal is -d made perpendicular to the tangent, its
    // width runs along e = x cross n_face.
    const Vec3 n_face = perpendicular(-d, x);
    const Vec3 e = cross(x, n_face);
    Normal3 ng = n_face, ns = n_face;
    Vec3 across = e;  // the direction of the width in the surface
    Float hr;         // signed offset from the axis along e, in half-widths
    if (type == CurveType::Ribbon) {
        // pbrt-v4's slerp between the end normals (Curve::RecursiveIntersect).
        const Normal3 n = slerp_normal((*end_normals)[2 * i], (*end_normals)[2 * i + 1], u);
        ng = ns = perpendicular(n, x);
        if (flip_normals) ng = ns = -ng;
        across = cross(x, ng);
        // pbrt-v4 measures v in the ray's projection: the offset across the projected width.
        const Float s = dot(ph - c, across);
        hr = r > 0 ? (dot(across, e) < 0 ? -s : s) / r : 0;
    } else {
        hr = r > 0 ? dot(ph - c, e) / r : 0;
    }
    hr = clamp(hr, Float(-1), Float(1));
    if (type == CurveType::Cylinder) {
        // The normal of a round tube at the point offset hr r from its axis (pbrt-v4 turns
        // its normal by 90 degrees times the offset instead; see docs/pbrt-support.md).
        ns = normalize(n_face * std::sqrt(std::max(Float(0), 1 - hr * hr)) + e * hr);
    }
    h.p = ph;
    // pbrt-v4's error bound for curves: the width in every axis. It keeps a ray that leaves
    // the ribbon from meeting the same ribbon where it left it.
    h.p_error = Vec3(2 * r, 2 * r, 2 * r);
    h.ng = ng;
    h.ns = ns;
    h.dpdu = dpdu;
    h.dpdv = across * (-2 * r);  // v grows against `across` (h = 2 v - 1 = -offset)
    h.dndu = h.dndv = h.ss = Vec3(0, 0, 0);
    // h = -hr: the hair model's azimuthal offset is measured against x cross wo (see
    // bsdf/hair.h), which is -e for the ray-facing ribbon.
    h.uv = Point2(u, Float(0.5) * (1 - hr));
}

}  // namespace sr
