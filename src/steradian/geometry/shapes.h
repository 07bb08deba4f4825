#pragma once
/// Runtime shapes: triangle meshes (Embree triangles, shared buffers), exact spheres and
/// disks (Embree user geometry). Shapes are a std::variant of plain structs; each
/// alternative satisfies the ShapeLike concept below.
#include <concepts>
#include <memory>
#include <variant>
#include <vector>

#include "steradian/core/transform.h"
#include "steradian/geometry/hit.h"

namespace sr {

/// A point sampled on a shape's surface.
struct ShapeSample {
    Point3 p;
    Vec3 p_error;
    Normal3 n;          ///< unit surface normal at p (oriented as the shape's ng)
    Float pdf = 0;      ///< pdf_area (per unit area) or pdf_sa (per solid angle), as stated
};

struct TriangleMesh;

/// One triangle of a mesh with what sampling it from a point needs, computed once: its
/// vertices, its oriented unit geometric normal and its area. Area lights keep one per
/// emitting triangle, so that a light sample does not go through the mesh's index buffer
/// or recompute the normal. The functions give the same values as the TriangleMesh
/// functions of the same names (which use them).
struct Triangle {
    Point3 p0, p1, p2;
    Normal3 n{0, 0, 1};  ///< unit geometric normal, oriented as point_at's (unless shaded)
    Float inv_area = 0;  ///< 1 / area (0 for a degenerate triangle)
    /// Set when the mesh has vertex normals: the normal of a point then depends on the
    /// point (it faces the interpolated shading normal), so point_at reads the mesh's
    /// normals of triangle `index`.
    const TriangleMesh* shaded_mesh = nullptr;
    uint32_t index = 0;

    /// As TriangleMesh::point_at for this triangle.
    ShapeSample point_at(Float b0, Float b1, Float b2) const;
    ShapeSample sample_from(Point3 ref, Point2 u) const;
    bool behind(Point3 ref) const;
    Float pdf_from(Point3 ref, Point3 p_light, Normal3 n_light) const;
    Float solid_angle(Point3 ref) const;
};

/// Triangle mesh in world space (or in an instance prototype's space).
struct TriangleMesh {
    /// Vertex positions, padded with one extra element so Embree may read 16 bytes.
    std::shared_ptr<std::vector<Point3>> p;
    std::shared_ptr<std::vector<Normal3>> n;   ///< per-vertex normals or empty
    std::shared_ptr<std::vector<Point2>> uv;   ///< per-vertex uv or empty
    std::shared_ptr<std::vector<uint32_t>> indices;  ///< 3 per triangle
    bool flip_normals = false;  ///< reverse_orientation XOR transform swaps handedness
    /// A flat triangle's (no vertex normals) geometric normal and unit shading tangent,
    /// which fill_hit would otherwise compute on every hit (a cross product, two square
    /// roots and two divisions on the path's critical chain). s = (0, 0, 0) marks a
    /// triangle whose tangent needs fill_hit's fallback (degenerate dp/du or dp/dv).
    struct FlatFrame {
        Normal3 n;
        Vec3 s;
    };
    /// One per triangle, or empty (meshes with vertex normals); see cache_flat_frames().
    std::shared_ptr<std::vector<FlatFrame>> flat_frames;
    /// Fills flat_frames when the mesh has no vertex normals (24 bytes per triangle); the
    /// hits it gives equal those computed without it.
    void cache_flat_frames();
    size_t num_triangles() const { return indices->size() / 3; }
    size_t num_vertices() const { return p->size() - 1; }
    /// Area of triangle i.
    Float triangle_area(size_t i) const;
    /// Triangle i with its normal and area (see Triangle).
    Triangle triangle(size_t i) const;
    /// The point of triangle i at barycentrics (b0, b1, b2), with its error bound and
    /// geometric normal; pdf = 1 / area (pdf_area).
    ShapeSample point_at(size_t i, Float b0, Float b1, Float b2) const;
    /// Uniformly samples a point on triangle i by area; pdf_area = 1 / area.
    ShapeSample sample_triangle(size_t i, Point2 u) const;
    /// Solid angle (sr) that triangle i subtends at ref (Van Oosterom & Strackee 1983).
    Float solid_angle(size_t i, Point3 ref) const;
    /// Samples triangle i as seen from ref: uniformly in solid angle when the triangle is
    /// large as seen from ref (area |cos| / d^2 at its centroid at least
    /// kSphericalSampleEstimate) and subtends between kMinSphericalSampleArea and
    /// kMaxSphericalSampleArea sr (Arvo 1995, "Stratified Sampling of Spherical Triangles"; the
    /// solid angle by Van Oosterom and Strackee 1983), else uniformly by area. pdf: pdf_sa.
    ShapeSample sample_triangle_from(size_t i, Point3 ref, Point2 u) const;
    /// True if ref lies strictly behind the plane of triangle i, seen from the side its
    /// geometric normal (point_at's, orientation included) points to; for meshes with vertex
    /// normals, whose orientation may vary over a triangle, always false.
    bool behind_triangle(size_t i, Point3 ref) const;
    /// pdf_sa of sample_triangle_from choosing point p (normal n) on triangle i from ref.
    Float pdf_triangle_from(size_t i, Point3 ref, Point3 p_light, Normal3 n_light) const;
    /// Below this solid angle, area sampling is as good and cheaper; above the upper bound
    /// (near a hemisphere) spherical sampling loses precision (pbrt-v4 uses the same bounds).
    static constexpr Float kMinSphericalSampleArea = 3e-4f;
    static constexpr Float kMaxSphericalSampleArea = 6.22f;
    /// Spherical sampling removes the variation of the area-to-solid-angle Jacobian d^2 / cos
    /// over the triangle, which matters only where the triangle looks large; elsewhere it
    /// runs about four times the instructions of area sampling (square roots, divisions, an
    /// arctangent for the solid angle, the sine and cosine of Arvo's map, a ray-plane
    /// intersection) for little gain. Below this estimated solid angle (sr), a triangle is
    /// sampled by area. Measured on the Cornell box at 64 spp: 11 % less CPU time per image,
    /// RMSE against pbrt-v4's 1024-spp render 0.01048 -> 0.01057 (pbrt-v4's own: 0.01103).
    /// Cycles makes the same choice with a different test (the longest edge against the
    /// distance to the triangle's plane).
    static constexpr Float kSphericalSampleEstimate = 0.1f;
    /// Fills the hit for triangle i at barycentrics (b1, b2) (Embree's u, v).
    void fill_hit(size_t i, Float b1, Float b2, SurfaceHit& h) const;
};

/// Sphere of radius r centred at the origin of its object space; partial spheres by
/// z range and phi_max as in pbrt-v4.
struct Sphere {
    Transform world_from_object;
    Float radius = 1;
    Float z_min = -1, z_max = 1, theta_z_min = 0, theta_z_max = kPi, phi_max = 2 * kPi;
    bool flip_normals = false;  ///< reverse_orientation XOR transform swaps handedness
    bool full() const { return phi_max >= 2 * kPi && z_min <= -radius && z_max >= radius; }
    /// Object-space intersection: nearest t in (t_min, t_max) of a ray given in object space.
    bool intersect_object(Point3 o, Vec3 d, Float t_max, Float& t_hit, Point3& p_hit,
                          Float t_min = 0) const;
    void fill_hit(Point3 p_obj, SurfaceHit& h) const;
    Float area() const;  ///< world-space area (exact for rigid transforms and uniform scale)
    /// Uniform by area (object space, mapped to world); pdf_area.
    ShapeSample sample_area(Point2 u) const;
    /// Sampled as seen from ref: by solid angle of the visible cap when ref is outside
    /// (pdf_sa), else by area converted to solid angle.
    ShapeSample sample_from(Point3 ref, Point2 u) const;
    /// pdf_sa of sample_from(ref, .) choosing direction wi that hits the sphere at p.
    Float pdf_from(Point3 ref, Point3 p, Normal3 n) const;
};

/// Disk in the plane z = height of object space, normal +z, with inner radius and phi_max.
struct Disk {
    Transform world_from_object;
    Float height = 0, radius = 1, inner_radius = 0, phi_max = 2 * kPi;
    bool flip_normals = false;
    bool intersect_object(Point3 o, Vec3 d, Float t_max, Float& t_hit, Point3& p_hit) const;
    void fill_hit(Point3 p_obj, SurfaceHit& h) const;
    Float area() const;
    ShapeSample sample_area(Point2 u) const;
};

/// pbrt-v4's cylinder: x^2 + y^2 = r^2 in object space for z in [z_min, z_max] and
/// phi = atan2(y, x) in [0, phi_max]; open at both ends; normal outwards (x, y, 0) / r;
/// u = phi / phi_max, v = (z - z_min) / (z_max - z_min).
struct Cylinder {
    Transform world_from_object;
    Float radius = 1, z_min = -1, z_max = 1, phi_max = 2 * kPi;
    bool flip_normals = false;
    /// Object-space intersection: nearest t in (t_min, t_max) (either wall, inside or out).
    bool intersect_object(Point3 o, Vec3 d, Float t_max, Float& t_hit, Point3& p_hit,
                          Float t_min = 0) const;
    void fill_hit(Point3 p_obj, SurfaceHit& h) const;
    Float area() const;
};

/// Converts an area-measure sample to solid angle as seen from ref (pdf_sa), 0 if the
/// sample is edge-on or coincides with ref.
inline Float area_to_solid_angle_pdf(Float pdf_area, Point3 ref, Point3 p, Normal3 n) {
    Vec3 d = p - ref;
    Float dist2 = length_squared(d);
    if (dist2 == 0) return 0;
    // pdf_area d^2 / |cos| with |cos| = |n . d| / |d|: one division (the square root runs
    // beside the dot product).
    Float n_dot = absdot(n, d);
    if (n_dot == 0) return 0;
    return pdf_area * dist2 * std::sqrt(dist2) / n_dot;
}

}  // namespace sr
