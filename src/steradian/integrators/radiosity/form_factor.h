#pragma once
/// Form factors for the radiosity pass (docs/radiosity.md): the analytic form factor from a
/// differential area to a polygon (Lambert's contour integral; Baum, Rushmeier and Winget
/// 1989, "Improving radiosity solutions through the use of analytically determined
/// form-factors", eq. 1), and triangle quadrature rules to integrate it over a receiving
/// patch. All in double precision: the radiosity solve amplifies a form factor's error by up
/// to 1 / (1 - rho).
#include <array>
#include <cmath>
#include <functional>

#include "steradian/core/math.h"

namespace sr::radiosity {

struct DVec3 {
    double x = 0, y = 0, z = 0;
    DVec3() = default;
    DVec3(double x_, double y_, double z_) : x(x_), y(y_), z(z_) {}
    explicit DVec3(Vec3 v) : x(v.x), y(v.y), z(v.z) {}
    DVec3 operator+(DVec3 o) const { return {x + o.x, y + o.y, z + o.z}; }
    DVec3 operator-(DVec3 o) const { return {x - o.x, y - o.y, z - o.z}; }
    DVec3 operator*(double s) const { return {x * s, y * s, z * s}; }
    Vec3 f() const { return Vec3(Float(x), Float(y), Float(z)); }
};
inline double ddot(DVec3 a, DVec3 b) { return a.x * b.x + a.y * b.y + a.z * b.z; }
inline DVec3 dcross(DVec3 a, DVec3 b) {
    return {a.y * b.z - a.z * b.y, a.z * b.x - a.x * b.z, a.x * b.y - a.y * b.x};
}
inline double dlength(DVec3 a) { return std::sqrt(ddot(a, a)); }

/// Form factor from a differential area at x (unit normal n) to the convex polygon v[0..n-1]
/// (at most 8 vertices), counting only the part of the polygon in front of x (the polygon is
/// clipped to the half-space n . (p - x) >= 0 first). Independent of the polygon's winding.
/// F = (1 / 2 pi) |sum_k gamma_k n . (R_k x R_k+1) / |R_k x R_k+1||, R_k = v_k - x, gamma_k
/// the angle between R_k and R_k+1.
double point_to_polygon(DVec3 x, DVec3 n, const DVec3* v, int count);

/// A low-discrepancy point set in [0,1)^2: the R2 sequence (Roberts 2018) shifted by a hash
/// of `key` (deterministic sample points for visibility and direct light).
Point2 r2(uint64_t i, uint64_t key);

/// A quadrature rule on a triangle: barycentric points (b0, b1, b2) and weights summing to 1.
struct TriangleRule {
    int count = 0;
    std::array<std::array<double, 3>, 7> b{};
    std::array<double, 7> w{};
};
/// The centroid rule (degree 1), the three-point rule of degree 2 (Strang and Fix 1973) and
/// the seven-point rule of degree 5 (Radon 1948; Stroud 1971, T2:5-1).
const TriangleRule& triangle_rule(int degree);

/// A triangular patch side: vertices, centroid, unit normal of the side, area, longest edge.
struct PatchGeom {
    std::array<DVec3, 3> v;
    DVec3 c, n;
    double area = 0, diam = 0;
};
PatchGeom make_patch(DVec3 a, DVec3 b, DVec3 c, bool flip = false);

/// Whether each of the two patch sides has a vertex of the other more than eps in front.
bool facing(const PatchGeom& a, const PatchGeom& b, double eps);

/// Visibility between two points (true: unoccluded); null: everything is visible.
using Visibility = std::function<bool(DVec3 from, DVec3 to)>;
/// Visibility between up to 8 pairs of points at once (from[i] and to[i], i < n): the bits
/// of the pairs that see each other. Traced as one packet: coherent rays between two
/// patches cost much less so than one by one.
using VisibilityBatch = std::function<unsigned(const DVec3* from, const DVec3* to, int n)>;

/// The exchange A_a F_ab = A_b F_ba of two facing patch sides: the point-to-polygon form
/// factor to the larger patch, integrated over the smaller (the receiver) by an adaptive
/// quadrature: a (sub-)triangle larger than its distance to the other patch is split in four,
/// down to 6 levels; the others take the degree-2 rule when their size is under 0.3 of that
/// distance and the degree-5 rule else. Visibility: a receiver far from the source (size
/// under 0.3 of the distance) casts one ray between the centroids; a nearer one, a ray from
/// each quadrature point to a point of the source (all from points offset by eps along the
/// normals). `rays` (if set) is increased by the rays cast. `receiver`
/// 0 or 1 forces a or b to be the receiver (tests). `max_level` replaces the 6 levels (a
/// coarser quadrature for exchanges whose accuracy matters less).
double exchange(const PatchGeom& a, const PatchGeom& b, double eps, const Visibility& visible,
                uint64_t* rays = nullptr, int receiver = -1, int max_level = 6);

}  // namespace sr::radiosity
