#pragma once
/// Warps from the unit square [0,1)^2 (or [0,1)) to common domains, each with its density
/// and, where the map is a bijection, its inverse (invert(sample(u)) == u), which
/// - lets tests check round trips and Jacobians, and
/// - lets later code (e.g. path guiding, sample-space MIS) map points back to primary space.
///
/// Measures: directional densities are pdf_sa (per steradian) on the unit sphere; disk and
/// triangle densities are pdf_area in the map's own parametrization (unit disk: per unit
/// area; triangle: per unit area of the barycentric triangle b0 + b1 <= 1, area 1/2).
/// Directions are in a local frame with z as the pole (normal); phi is measured from +x
/// towards +y.
#include <array>
#include <cmath>

#include "steradian/core/math.h"

namespace sr {

namespace detail {
/// Azimuth of (x, y) in [0, 2 pi) mapped to [0, 1) (1 itself is clamped to kOneMinusEpsilon).
inline Float azimuth_to_unit(Float x, Float y) {
    Float phi = std::atan2(y, x);
    if (phi < 0) phi += 2 * kPi;
    return std::min(phi * kInv2Pi, kOneMinusEpsilon);
}
}  // namespace detail

// ---- disk ------------------------------------------------------------------------------------

/// Uniform point on the unit disk by the concentric map of Shirley & Chiu 1997, "A
/// Low Distortion Map Between Disk and Square", JGT 2(3): concentric squares go to concentric
/// circles, so strata stay compact. Density: uniform_disk_pdf() = 1/pi per unit area.
inline Point2 sample_uniform_disk_concentric(Point2 u) {
    Float ox = 2 * u.x - 1, oy = 2 * u.y - 1;
    if (ox == 0 && oy == 0) return {0, 0};
    // The angle is theta = phi (|ox| > |oy|: radius ox) or pi/2 - phi (radius oy), with
    // |phi| <= pi/4. Written with selects, not branches: which case applies is a coin toss
    // for every sample, and a mispredicted branch cost more than both selects.
    const bool x_major = std::abs(ox) > std::abs(oy);
    Float r = x_major ? ox : oy, q = x_major ? oy : ox;
    Float s, c;
    sincos_pi4(kPiOver4 * (q / r), s, c);
    Float rc = r * c, rs = r * s;
    return {x_major ? rc : rs, x_major ? rs : rc};
}

/// Inverse of sample_uniform_disk_concentric: a point of the unit disk back to [0,1)^2.
/// Each quarter-plane wedge (|ox| >= |oy|, ox > 0 etc.) is undone by its own formula.
inline Point2 invert_uniform_disk_concentric(Point2 p) {
    Float rho = std::sqrt(p.x * p.x + p.y * p.y);
    Float phi = std::atan2(p.y, p.x);
    if (phi < -kPiOver4) phi += 2 * kPi;  // phi in [-pi/4, 7 pi/4)
    Float ox, oy;
    if (phi < kPiOver4) {  // right wedge: r = ox > 0, theta = phi
        ox = rho;
        oy = rho * (phi / kPiOver4);
    } else if (phi < 3 * kPiOver4) {  // top wedge: r = oy > 0
        oy = rho;
        ox = rho * ((kPiOver2 - phi) / kPiOver4);
    } else if (phi < 5 * kPiOver4) {  // left wedge: r = ox < 0, theta = phi - pi
        ox = -rho;
        oy = -rho * ((phi - kPi) / kPiOver4);
    } else {  // bottom wedge: r = oy < 0, theta = phi - pi
        oy = -rho;
        ox = -rho * ((3 * kPiOver2 - phi) / kPiOver4);
    }
    return {std::min((ox + 1) / 2, kOneMinusEpsilon), std::min((oy + 1) / 2, kOneMinusEpsilon)};
}

/// Uniform point on the unit disk in polar form: r = sqrt(u.x), phi = 2 pi u.y. Density 1/pi
/// per unit area (distorts strata more than the concentric map).
inline Point2 sample_uniform_disk_polar(Point2 u) {
    Float r = std::sqrt(u.x);
    Float theta = 2 * kPi * u.y;
    return {r * std::cos(theta), r * std::sin(theta)};
}

/// Inverse of sample_uniform_disk_polar.
inline Point2 invert_uniform_disk_polar(Point2 p) {
    return {std::min(p.x * p.x + p.y * p.y, kOneMinusEpsilon), detail::azimuth_to_unit(p.x, p.y)};
}

/// pdf_area of both uniform disk maps on the unit disk: 1/pi.
constexpr Float uniform_disk_pdf() { return kInvPi; }

// ---- hemisphere and sphere -------------------------------------------------------------------

/// Uniform direction on the hemisphere z >= 0: cos(theta) = u.x, phi = 2 pi u.y.
inline Vec3 sample_uniform_hemisphere(Point2 u) {
    Float z = u.x;
    Float r = safe_sqrt(1 - z * z);
    Float phi = 2 * kPi * u.y;
    return {r * std::cos(phi), r * std::sin(phi), z};
}

/// pdf_sa of sample_uniform_hemisphere: 1 / (2 pi) sr^-1 (on z >= 0).
constexpr Float uniform_hemisphere_pdf() { return kInv2Pi; }

/// Inverse of sample_uniform_hemisphere for a unit w with w.z >= 0.
inline Point2 invert_uniform_hemisphere(Vec3 w) {
    return {std::min(w.z, kOneMinusEpsilon), detail::azimuth_to_unit(w.x, w.y)};
}

/// Cosine-weighted direction on the hemisphere z >= 0 by Malley's method: a uniform
/// (concentric) disk point lifted to the hemisphere (Pharr, Jakob, Humphreys, "Physically Based
/// Rendering", 4th ed., Sec. A.5.3). Density cosine_hemisphere_pdf(w.z) = cos(theta)/pi.
inline Vec3 sample_cosine_hemisphere(Point2 u) {
    Point2 d = sample_uniform_disk_concentric(u);
    Float z = safe_sqrt(1 - d.x * d.x - d.y * d.y);
    return {d.x, d.y, z};
}

/// pdf_sa of sample_cosine_hemisphere: cos(theta)/pi sr^-1; 0 below the horizon.
constexpr Float cosine_hemisphere_pdf(Float cos_theta) {
    return cos_theta > 0 ? cos_theta * kInvPi : Float(0);
}

/// Inverse of sample_cosine_hemisphere (projects w onto the disk and inverts the disk map).
inline Point2 invert_cosine_hemisphere(Vec3 w) {
    return invert_uniform_disk_concentric({w.x, w.y});
}

/// Uniform direction on the unit sphere: cos(theta) = 1 - 2 u.x, phi = 2 pi u.y.
inline Vec3 sample_uniform_sphere(Point2 u) {
    Float z = 1 - 2 * u.x;
    Float r = safe_sqrt(1 - z * z);
    Float phi = 2 * kPi * u.y;
    return {r * std::cos(phi), r * std::sin(phi), z};
}

/// pdf_sa of sample_uniform_sphere: 1 / (4 pi) sr^-1.
constexpr Float uniform_sphere_pdf() { return kInv4Pi; }

/// Inverse of sample_uniform_sphere for a unit w.
inline Point2 invert_uniform_sphere(Vec3 w) {
    return {clamp((1 - w.z) / 2, Float(0), kOneMinusEpsilon), detail::azimuth_to_unit(w.x, w.y)};
}

/// Uniform direction in the cone of half-angle theta_max around +z (cos_theta_max < 1):
/// 1 - cos(theta) = u.x (1 - cos_theta_max), phi = 2 pi u.y. The sine is formed from
/// 1 - cos(theta) to stay accurate for narrow cones.
inline Vec3 sample_uniform_cone(Point2 u, Float cos_theta_max) {
    Float one_minus_cos = u.x * (1 - cos_theta_max);
    Float cos_t = 1 - one_minus_cos;
    Float sin_t = safe_sqrt(one_minus_cos * (2 - one_minus_cos));
    Float phi = 2 * kPi * u.y;
    return {sin_t * std::cos(phi), sin_t * std::sin(phi), cos_t};
}

/// pdf_sa of sample_uniform_cone: 1 / (2 pi (1 - cos_theta_max)) sr^-1 inside the cone, i.e.
/// one over the cone's solid angle. Infinite for a degenerate cone (cos_theta_max == 1).
inline Float uniform_cone_pdf(Float cos_theta_max) { return 1 / (2 * kPi * (1 - cos_theta_max)); }

/// Inverse of sample_uniform_cone for a unit w inside the cone; 1 - cos(theta) is computed as
/// sin^2 / (1 + cos) to keep precision near the axis.
inline Point2 invert_uniform_cone(Vec3 w, Float cos_theta_max) {
    Float one_minus_cos = (w.x * w.x + w.y * w.y) / (1 + w.z);
    return {clamp(one_minus_cos / (1 - cos_theta_max), Float(0), kOneMinusEpsilon),
            detail::azimuth_to_unit(w.x, w.y)};
}

// ---- triangle --------------------------------------------------------------------------------

/// Uniform barycentrics (b0, b1, b2) on a triangle by the area-preserving low-distortion map of
/// Heitz 2019, "A Low-Distortion Map Between Triangle and Square" (Eq. 6): the square is split
/// along its diagonal and each half is sheared onto half of the triangle, so b0 + b1 =
/// max(u.x, u.y). The Jacobian is the constant 1/2: the density is 2 per unit barycentric area,
/// i.e. 1/A per unit area of a triangle of area A.
inline std::array<Float, 3> sample_uniform_triangle(Point2 u) {
    // u.y > u.x: b0 = u.x / 2, b1 = u.y - b0; else b1 = u.y / 2, b0 = u.x - b1. Both are
    // b = u - min(u.x, u.y) / 2 (exactly: v - v / 2 = v / 2 in floating point), which needs no
    // branch on a case that is a coin toss per sample.
    Float half = std::min(u.x, u.y) / 2;
    Float b0 = u.x - half, b1 = u.y - half;
    return {b0, b1, 1 - b0 - b1};
}

/// Inverse of sample_uniform_triangle (only b0 and b1 are read).
inline Point2 invert_uniform_triangle(const std::array<Float, 3>& b) {
    Point2 u = b[1] > b[0] ? Point2{2 * b[0], b[0] + b[1]} : Point2{b[0] + b[1], 2 * b[1]};
    return {std::min(u.x, kOneMinusEpsilon), std::min(u.y, kOneMinusEpsilon)};
}

// ---- 1D and bilinear -------------------------------------------------------------------------

/// pdf on [0, 1] proportional to the line through (0, a) and (1, b), a, b >= 0, a + b > 0:
/// 2 lerp(x, a, b) / (a + b); 0 outside [0, 1].
inline Float linear_pdf(Float x, Float a, Float b) {
    if (x < 0 || x > 1) return 0;
    return 2 * lerp(x, a, b) / (a + b);
}

/// Samples linear_pdf by inverting its CDF F(x) = x (a (2 - x) + b x) / (a + b), written
/// as x = u (a + b) / (a + sqrt(lerp(u, a^2, b^2))) to avoid cancellation when a ~ b.
inline Float sample_linear(Float u, Float a, Float b) {
    if (u == 0 && a == 0) return 0;
    Float x = u * (a + b) / (a + std::sqrt(lerp(u, a * a, b * b)));
    return std::min(x, kOneMinusEpsilon);
}

/// The CDF of linear_pdf: the inverse of sample_linear.
inline Float invert_linear(Float x, Float a, Float b) {
    return x * (a * (2 - x) + b * x) / (a + b);
}

/// pdf on [0,1]^2 proportional to the bilinear interpolation of corner values
/// w = {f(0,0), f(1,0), f(0,1), f(1,1)} (non-negative, not all zero), per unit area.
inline Float bilinear_pdf(Point2 p, const std::array<Float, 4>& w) {
    if (p.x < 0 || p.x > 1 || p.y < 0 || p.y > 1) return 0;
    Float sum = w[0] + w[1] + w[2] + w[3];
    if (sum == 0) return 1;
    return 4 *
           ((1 - p.x) * (1 - p.y) * w[0] + p.x * (1 - p.y) * w[1] + (1 - p.x) * p.y * w[2] +
            p.x * p.y * w[3]) /
           sum;
}

/// Samples bilinear_pdf: y from its linear marginal, then x from the linear conditional.
inline Point2 sample_bilinear(Point2 u, const std::array<Float, 4>& w) {
    Float y = sample_linear(u.y, w[0] + w[1], w[2] + w[3]);
    Float x = sample_linear(u.x, lerp(y, w[0], w[2]), lerp(y, w[1], w[3]));
    return {x, y};
}

/// Inverse of sample_bilinear.
inline Point2 invert_bilinear(Point2 p, const std::array<Float, 4>& w) {
    return {invert_linear(p.x, lerp(p.y, w[0], w[2]), lerp(p.y, w[1], w[3])),
            invert_linear(p.y, w[0] + w[1], w[2] + w[3])};
}

/// Exponential distribution with rate a > 0 on [0, inf): pdf a exp(-a x) (e.g. free-flight
/// distances with extinction coefficient a, in inverse length units).
inline Float sample_exponential(Float u, Float a) { return -std::log1p(-u) / a; }
inline Float exponential_pdf(Float x, Float a) { return x < 0 ? 0 : a * std::exp(-a * x); }
inline Float invert_exponential(Float x, Float a) { return -std::expm1(-a * x); }

/// Tent (triangle) distribution on [-r, r]: pdf (r - |x|) / r^2 (e.g. the triangle filter).
inline Float sample_tent(Float u, Float r) {
    if (u < Float(0.5)) return r * (std::sqrt(2 * u) - 1);
    return r * (1 - std::sqrt(2 - 2 * u));
}
inline Float tent_pdf(Float x, Float r) {
    return std::abs(x) >= r ? Float(0) : (r - std::abs(x)) / (r * r);
}
inline Float invert_tent(Float x, Float r) {
    Float t = x / r;
    return t < 0 ? sqr(1 + t) / 2 : 1 - sqr(1 - t) / 2;
}

/// Clarberg's equal-area octahedral map ("Fast equal-area mapping of the (hemi)sphere using
/// SIMD", JGT 13(3), 2008), as pbrt-v4 uses for environment and goniometric images: the unit
/// square [0,1]^2 onto the unit sphere, each region of the square covering a solid angle
/// 4 pi times its area. The upper hemisphere (z >= 0) is the diamond |u'| + |v'| <= 1 of
/// (u', v') = 2 (u, v) - 1; the lower one the four corners, folded over the diamond's edges.
inline Vec3 equal_area_square_to_sphere(Point2 p) {
    Float u = 2 * p.x - 1, v = 2 * p.y - 1;
    Float au = std::abs(u), av = std::abs(v);
    Float signed_d = 1 - (au + av);  // > 0 inside the diamond (upper hemisphere)
    Float r = 1 - std::abs(signed_d);
    // Angle within the quadrant, 0 on the u axis, pi/2 on the v axis.
    Float phi = (r == 0 ? 1 : (av - au) / r + 1) * (kPi / 4);
    Float z = std::copysign(1 - r * r, signed_d);
    Float k = r * std::sqrt(std::max(Float(0), 2 - r * r));
    return {std::copysign(std::cos(phi) * k, u), std::copysign(std::sin(phi) * k, v), z};
}

/// Inverse of equal_area_square_to_sphere for a unit vector.
inline Point2 equal_area_sphere_to_square(Vec3 w) {
    Float ax = std::abs(w.x), ay = std::abs(w.y), az = std::min(std::abs(w.z), Float(1));
    Float r = std::sqrt(1 - az);
    Float phi = std::atan2(ay, ax);  // [0, pi/2]
    Float v = r * phi * (2 / kPi), u = r - v;  // upper hemisphere: u' + v' = r
    if (w.z < 0) {                              // fold across the diamond's edge
        Float t = u;
        u = 1 - v;
        v = 1 - t;
    }
    u = std::copysign(u, w.x);
    v = std::copysign(v, w.y);
    return {(u + 1) / 2, (v + 1) / 2};
}

}  // namespace sr
