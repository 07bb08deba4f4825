#pragma once
/// pbrt-v4's "curve" shape: cubic Bézier segments of varying width, intersected by Embree's
/// curve primitives (accel/). Every input curve (Bézier or uniform B-spline, degree 2 or 3)
/// is converted to cubic Bézier segments, as pbrt-v4 does, with the conversions below.
///
/// Types, as pbrt-v4 defines them (shapes.cpp, Curve::IntersectRay):
///  - flat: a ribbon that always faces the ray (Embree's FLAT_BEZIER_CURVE);
///  - cylinder: the same ray-facing ribbon, its shading normal bent across the width as a
///    round tube's normal would be (geometry stays flat, as in pbrt-v4);
///  - ribbon: a ribbon oriented by normals given at the segment ends
///    (Embree's NORMAL_ORIENTED_BEZIER_CURVE).
#include <array>
#include <cstdint>
#include <memory>
#include <span>
#include <vector>

#include "steradian/geometry/hit.h"

namespace sr {

enum class CurveType : uint8_t { Flat, Cylinder, Ribbon };

/// A control point and the curve's radius (half its width) there: Embree's RTC_FORMAT_FLOAT4
/// layout of curve vertices.
struct CurvePoint {
    Float x, y, z, r;
};

/// The cubic Bézier control points of segment [cp[0], cp[3]] of a uniform cubic B-spline
/// with control points cp[0..3] (the segment between the knots of cp[1] and cp[2]).
std::array<Point3, 4> cubic_bspline_to_bezier(std::span<const Point3, 4> cp);
/// The quadratic Bézier control points of the segment of a uniform quadratic B-spline with
/// control points cp[0..2].
std::array<Point3, 3> quadratic_bspline_to_bezier(std::span<const Point3, 3> cp);
/// The same quadratic Bézier curve written as a cubic one (degree elevation).
std::array<Point3, 4> elevate_quadratic_bezier(std::span<const Point3, 3> cp);
/// The cubic Bézier curve with control points cp at u in [0, 1], and its derivative.
Point3 cubic_bezier(std::span<const Point3, 4> cp, Float u, Vec3* derivative = nullptr);

/// The spherical linear interpolation of the unit normals n0 and n1 at u (pbrt-v4's ribbon
/// normal along a segment); n0 where they are (nearly) equal.
Normal3 slerp_normal(Normal3 n0, Normal3 n1, Float u);

/// A pbrt-v4 "curve" shape in world space (or in an instance prototype's space).
struct Curves {
    CurveType type = CurveType::Flat;
    /// Four control points per cubic Bézier segment, each with its radius; segment i starts
    /// at cp[4 i]. Widths vary linearly along a segment (pbrt-v4: width0 to width1 over the
    /// whole curve, a linear function written in the Bézier basis).
    std::shared_ptr<std::vector<CurvePoint>> cp;
    std::shared_ptr<std::vector<uint32_t>> first;  ///< 4 i for segment i (Embree's index buffer)
    /// Ribbons: the unit normals at the two ends of each segment (pbrt-v4 slerps between
    /// them), and four per segment for Embree (those slerped at u = 0, 1/3, 2/3, 1), padded
    /// with one element (Embree reads float3 buffers 16 bytes at a time).
    std::shared_ptr<std::vector<Normal3>> end_normals, embree_normals;
    bool flip_normals = false;  ///< reverse_orientation XOR transform swaps handedness

    size_t num_segments() const { return first->size(); }
    /// The control points of segment i (without radii).
    std::array<Point3, 4> segment(size_t i) const;
    /// Fills h for a hit of the ray (o, d) at ray parameter t on segment i at curve
    /// parameter u (Embree's). uv = (u, v) as pbrt-v4: u along the segment, v across the
    /// width in [0, 1], so that the hair material's offset h = 2 v - 1 is the signed distance
    /// from the axis in half-widths, with the sign of pbrt-v4's hair frame (x = dpdu along
    /// the curve, z = ns). ng faces the ray for flat and cylinder curves.
    void fill_hit(uint32_t i, Float u, Point3 o, Vec3 d, Float t, SurfaceHit& h) const;
};

}  // namespace sr
