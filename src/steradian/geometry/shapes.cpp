#include "steradian/geometry/shapes.h"

#include <cmath>
#include <optional>

#include "steradian/sampling/warp.h"

namespace sr {

namespace {

/// Uniform scale factor of a (near-)similarity transform: |det|^(1/3).
double similarity_scale(const Transform& t) {
    const auto& a = t.matrix().m;
    double det = a[0][0] * (a[1][1] * a[2][2] - a[1][2] * a[2][1]) -
                 a[0][1] * (a[1][0] * a[2][2] - a[1][2] * a[2][0]) +
                 a[0][2] * (a[1][0] * a[2][1] - a[1][1] * a[2][0]);
    return std::cbrt(std::abs(det));
}

/// World-space position and error bound for an object-space point with error err_obj.
void to_world(const Transform& t, Point3 p_obj, Vec3 err_obj, Point3& p, Vec3& err) {
    const auto& a = t.matrix().m;
    Vec3d pw = t.point(Vec3d(p_obj));
    p = Point3(pw);
    for (int i = 0; i < 3; ++i) {
        double e = 0;
        for (int j = 0; j < 3; ++j)
            e += std::abs(a[i][j]) * (err_obj[j] + gamma_bound(3) * std::abs(p_obj[j]));
        e += gamma_bound(3) * std::abs(a[i][3]);
        err[i] = Float(e) + gamma_bound(2) * std::abs(p[i]);
    }
}

}  // namespace

// ---- triangles ------------------------------------------------------------------------

Float TriangleMesh::triangle_area(size_t i) const {
    const auto& P = *p;
    const uint32_t* v = &(*indices)[3 * i];
    return Float(0.5) * length(cross(P[v[1]] - P[v[0]], P[v[2]] - P[v[0]]));
}

namespace {

/// dp/du and dp/dv of a triangle (constant over it), and the uv of barycentrics (b0, b1, b2).
/// Without uv, pbrt-v4's default parameterisation (0,0), (1,0), (1,1) gives uv = (b1 + b2, b2)
/// and dpdu = p1 - p0, dpdv = p2 - p1.
void triangle_tangents(const TriangleMesh& m, const uint32_t* v, Float b0, Float b1, Float b2,
                       Point2& uv_out, Vec3& dpdu, Vec3& dpdv) {
    const auto& P = *m.p;
    Point3 p0 = P[v[0]], p1 = P[v[1]], p2 = P[v[2]];
    if (m.uv && !m.uv->empty()) {
        Point2 uv0 = (*m.uv)[v[0]], uv1 = (*m.uv)[v[1]], uv2 = (*m.uv)[v[2]];
        uv_out = Point2(uv0.x * b0 + uv1.x * b1 + uv2.x * b2, uv0.y * b0 + uv1.y * b1 + uv2.y * b2);
        Vec2 duv02 = uv0 - uv2, duv12 = uv1 - uv2;
        Vec3 dp02 = p0 - p2, dp12 = p1 - p2;
        Float det = duv02.x * duv12.y - duv02.y * duv12.x;
        if (std::abs(det) > 1e-12f) {
            dpdu = (dp02 * duv12.y - dp12 * duv02.y) * (1 / det);
            dpdv = (dp12 * duv02.x - dp02 * duv12.x) * (1 / det);
        } else {
            dpdu = dpdv = Vec3(0, 0, 0);
        }
    } else {
        uv_out = Point2(b1 + b2, b2);
        dpdu = p1 - p0;
        dpdv = p2 - p1;
    }
}

/// Unit geometric normal of a triangle, oriented by the mesh's orientation flag; `twice_area`
/// (if given) receives |(p1 - p0) x (p2 - p0)|.
Normal3 triangle_normal(Point3 p0, Point3 p1, Point3 p2, bool flip, Float* twice_area = nullptr) {
    Vec3 ng = cross(p1 - p0, p2 - p0);
    Float len = length(ng);
    if (twice_area) *twice_area = len;
    ng = len > 0 ? ng / len : Vec3(0, 0, 1);
    return flip ? -ng : ng;
}

/// Whether dp/du or dp/dv is parallel to the normal (or zero), so that the hit's tangents
/// must come from coordinate_system().
bool degenerate_tangents(Vec3 dpdu, Vec3 dpdv, Normal3 ng) {
    return length_squared(cross(dpdu, ng)) == 0 || length_squared(cross(dpdv, ng)) == 0;
}

}  // namespace

void TriangleMesh::cache_flat_frames() {
    if (n && !n->empty()) return;
    const size_t count = num_triangles();
    auto frames = std::make_shared<std::vector<FlatFrame>>(count);
    for (size_t i = 0; i < count; ++i) {
        const uint32_t* v = &(*indices)[3 * i];
        const auto& P = *p;
        FlatFrame& f = (*frames)[i];
        f.n = triangle_normal(P[v[0]], P[v[1]], P[v[2]], flip_normals);
        Point2 uv_unused;
        Vec3 dpdu, dpdv;
        triangle_tangents(*this, v, 1, 0, 0, uv_unused, dpdu, dpdv);
        f.s = degenerate_tangents(dpdu, dpdv, f.n) ? Vec3(0, 0, 0) : shading_tangent(dpdu, f.n);
    }
    flat_frames = std::move(frames);
}

void TriangleMesh::fill_hit(size_t i, Float b1, Float b2, SurfaceHit& h) const {
    const auto& P = *p;
    const uint32_t* v = &(*indices)[3 * i];
    Point3 p0 = P[v[0]], p1 = P[v[1]], p2 = P[v[2]];
    Float b0 = 1 - b1 - b2;
    h.p = p0 * b0 + p1 * b1 + p2 * b2;
    Vec3 abs_sum{std::abs(b0 * p0.x) + std::abs(b1 * p1.x) + std::abs(b2 * p2.x),
                 std::abs(b0 * p0.y) + std::abs(b1 * p1.y) + std::abs(b2 * p2.y),
                 std::abs(b0 * p0.z) + std::abs(b1 * p1.z) + std::abs(b2 * p2.z)};
    h.p_error = abs_sum * gamma_bound(7);
    Vec3 dpdu, dpdv;
    triangle_tangents(*this, v, b0, b1, b2, h.uv, dpdu, dpdv);
    h.dpdu = dpdu;
    h.dpdv = dpdv;
    if (flat_frames) {
        const FlatFrame& f = (*flat_frames)[i];
        if (is_nonzero(f.s)) {
            h.ng = h.ns = f.n;
            h.ss = f.s;
            return;
        }
    }
    h.ss = Vec3(0, 0, 0);
    Normal3 ng = triangle_normal(p0, p1, p2, flip_normals);
    if (degenerate_tangents(dpdu, dpdv, ng)) {
        Vec3 s, t;
        coordinate_system(ng, s, t);
        h.dpdu = s;
        h.dpdv = t;
    }
    if (n && !n->empty()) {
        const Normal3 n0 = (*n)[v[0]], n1 = (*n)[v[1]], n2 = (*n)[v[2]];
        // dn/du, dn/dv of the interpolated normal, by the same linear solve as dp/du, dp/dv.
        if (uv && !uv->empty()) {
            Point2 uv0 = (*uv)[v[0]], uv1 = (*uv)[v[1]], uv2 = (*uv)[v[2]];
            Vec2 duv02 = uv0 - uv2, duv12 = uv1 - uv2;
            Float det = duv02.x * duv12.y - duv02.y * duv12.x;
            if (std::abs(det) > 1e-12f) {
                Vec3 dn02 = n0 - n2, dn12 = n1 - n2;
                h.dndu = (dn02 * duv12.y - dn12 * duv02.y) * (1 / det);
                h.dndv = (dn12 * duv02.x - dn02 * duv12.x) * (1 / det);
            }
        } else {
            h.dndu = n1 - n0;
            h.dndv = n2 - n1;
        }
        Normal3 ns = n0 * b0 + n1 * b1 + n2 * b2;
        Float l2 = length_squared(ns);
        if (l2 > 0) {
            ns = ns / std::sqrt(l2);
            ng = face_forward(ng, ns);
            h.ns = ns;
        } else {
            h.ns = ng;
        }
    } else {
        h.ns = ng;
    }
    h.ng = ng;
}

Triangle TriangleMesh::triangle(size_t i) const {
    const auto& P = *p;
    const uint32_t* v = &(*indices)[3 * i];
    Triangle t;
    t.p0 = P[v[0]];
    t.p1 = P[v[1]];
    t.p2 = P[v[2]];
    Float len;
    t.n = triangle_normal(t.p0, t.p1, t.p2, flip_normals, &len);
    t.inv_area = len > 0 ? 2 / len : 0;
    if (n && !n->empty()) t.shaded_mesh = this;
    t.index = uint32_t(i);
    return t;
}

ShapeSample TriangleMesh::point_at(size_t i, Float b0, Float b1, Float b2) const {
    return triangle(i).point_at(b0, b1, b2);
}

ShapeSample Triangle::point_at(Float b0, Float b1, Float b2) const {
    ShapeSample s;
    s.p = p0 * b0 + p1 * b1 + p2 * b2;
    Vec3 abs_sum{std::abs(b0 * p0.x) + std::abs(b1 * p1.x) + std::abs(b2 * p2.x),
                 std::abs(b0 * p0.y) + std::abs(b1 * p1.y) + std::abs(b2 * p2.y),
                 std::abs(b0 * p0.z) + std::abs(b1 * p1.z) + std::abs(b2 * p2.z)};
    s.p_error = abs_sum * gamma_bound(6);
    s.n = n;
    if (shaded_mesh) {
        // As fill_hit: the geometric normal faces the interpolated shading normal.
        const auto& N = *shaded_mesh->n;
        const uint32_t* v = &(*shaded_mesh->indices)[3 * index];
        Normal3 ns = N[v[0]] * b0 + N[v[1]] * b1 + N[v[2]] * b2;
        if (length_squared(ns) > 0) s.n = face_forward(s.n, ns);
    }
    s.pdf = inv_area;
    return s;
}

ShapeSample TriangleMesh::sample_triangle(size_t i, Point2 u) const {
    auto b = sample_uniform_triangle(u);
    return point_at(i, b[0], b[1], b[2]);
}

namespace {

/// v minus its component along unit w.
Vec3 gram_schmidt(Vec3 v, Vec3 w) { return v - w * dot(v, w); }

/// The spherical triangle with unit vertices a, b, c: its area (the solid angle, by Van
/// Oosterom & Strackee 1983: tan(area / 2) = |a . (b x c)| / (1 + a.b + b.c + c.a)), and
/// cos and sin of its interior angle at a (between the great-circle planes through a),
/// which is all of that angle Arvo's map needs. area = 0 if degenerate.
struct SphericalTriangle {
    Vec3 a, b, c;
    Float area = 0, cos_alpha = 1, sin_alpha = 0;
    SphericalTriangle(Vec3 a_, Vec3 b_, Vec3 c_) : a(a_), b(b_), c(c_) {
        Vec3 n_ab = cross(a, b), n_ac = cross(a, c);
        Float l_ab = length_squared(n_ab), l_ac = length_squared(n_ac);
        if (l_ab == 0 || l_ac == 0) return;
        // The angle between the planes (a, b) and (a, c): cos from the normals' dot product,
        // sin from their cross product, (a x b) x (a x c) = (a . (b x c)) a for unit a, whose
        // length is the triple product that the area needs anyway.
        Float inv_len = 1 / std::sqrt(l_ab * l_ac);
        Float num = std::abs(dot(a, cross(b, c)));
        cos_alpha = clamp(dot(n_ab, n_ac) * inv_len, Float(-1), Float(1));
        sin_alpha = std::min(num * inv_len, Float(1));
        Float den = 1 + dot(a, b) + dot(b, c) + dot(c, a);
        area = 2 * fast_atan2(num, den);
        if (!(area > 0) || sin_alpha == 0) area = 0;
    }
    /// Arvo's (1995) area-preserving map from [0,1)^2 onto the triangle: u.x chooses the
    /// area A' = u.x area of the sub-triangle (a, b, c'), u.y the point on the arc from b
    /// towards c'. (With phi = A' + pi - alpha: sin phi and cos phi expand in A' and alpha.)
    Vec3 sample(Point2 u) const {
        Float s_a, c_a;
        fast_sincos(u.x * area, s_a, c_a);
        // sin(A' + pi) = -sin A', cos(A' + pi) = -cos A'
        Float sin_phi = -s_a * cos_alpha + c_a * sin_alpha;
        Float cos_phi = -c_a * cos_alpha - s_a * sin_alpha;
        Float k1 = cos_phi + cos_alpha;
        Float k2 = sin_phi - sin_alpha * dot(a, b);
        Float cos_bp = (k2 + (k2 * cos_phi - k1 * sin_phi) * cos_alpha) /
                       ((k2 * sin_phi + k1 * cos_phi) * sin_alpha);
        cos_bp = clamp(cos_bp, Float(-1), Float(1));
        Float sin_bp = safe_sqrt(1 - sqr(cos_bp));
        Vec3 cp = a * cos_bp + normalize(gram_schmidt(c, a)) * sin_bp;
        Float cos_theta = 1 - u.y * (1 - dot(cp, b));
        Float sin_theta = safe_sqrt(1 - sqr(cos_theta));
        return b * cos_theta + normalize(gram_schmidt(cp, b)) * sin_theta;
    }
};

bool use_spherical(Float omega) {
    return omega >= TriangleMesh::kMinSphericalSampleArea &&
           omega <= TriangleMesh::kMaxSphericalSampleArea;
}

/// The spherical triangle t subtends at ref when t is to be sampled uniformly in solid angle
/// from there, else none (sample by area). Spherical sampling pays only where t looks large:
/// its solid angle estimated as area |cos| / d^2 at the centroid (one square root, no
/// division) must reach kSphericalSampleEstimate before the exact one is computed, which must
/// lie in [kMinSphericalSampleArea, kMaxSphericalSampleArea]. sample_from and pdf_from both
/// decide here, so their densities agree.
std::optional<SphericalTriangle> spherical_from(const Triangle& t, Point3 ref) {
    Vec3 v = (t.p0 + t.p1 + t.p2) * (Float(1) / 3) - ref;
    // area |n . v| / d^3 < k, squared (no square root on the light sample's chain), in
    // double so that neither side overflows or underflows.
    double d2 = double(length_squared(v)), n_dot = double(dot(t.n, v));
    double k_inv_area = double(TriangleMesh::kSphericalSampleEstimate) * double(t.inv_area);
    if (n_dot * n_dot < k_inv_area * k_inv_area * (d2 * d2 * d2)) return std::nullopt;
    std::optional<SphericalTriangle> st(std::in_place, normalize(t.p0 - ref), normalize(t.p1 - ref),
                                        normalize(t.p2 - ref));
    if (!use_spherical(st->area)) st.reset();
    return st;
}

}  // namespace

Float Triangle::solid_angle(Point3 ref) const {
    return SphericalTriangle(normalize(p0 - ref), normalize(p1 - ref), normalize(p2 - ref)).area;
}

ShapeSample Triangle::sample_from(Point3 ref, Point2 u) const {
    const std::optional<SphericalTriangle> st = spherical_from(*this, ref);
    std::array<Float, 3> b;
    if (!st) {
        b = sample_uniform_triangle(u);
    } else {
        Vec3 w = st->sample(u);
        // Intersect ref + t w with the triangle's plane for barycentrics (Moller-Trumbore).
        Vec3 e1 = p1 - p0, e2 = p2 - p0;
        Vec3 s1 = cross(w, e2);
        Float divisor = dot(s1, e1);
        Float b1 = Float(1) / 3, b2 = Float(1) / 3;
        if (divisor != 0) {
            Vec3 sd = ref - p0;
            b1 = clamp(dot(sd, s1) / divisor, Float(0), Float(1));
            b2 = clamp(dot(w, cross(sd, e1)) / divisor, Float(0), Float(1));
            if (b1 + b2 > 1) {
                Float sum = b1 + b2;
                b1 /= sum;
                b2 /= sum;
            }
        }
        b = {1 - b1 - b2, b1, b2};
    }
    // One result, initialised from point_at and returned, so that it is built in the
    // caller's object: a copy out of a local, written field by field and read back in
    // 16-byte pieces, stalled store-to-load forwarding on every light sample.
    ShapeSample s = point_at(b[0], b[1], b[2]);
    s.pdf = st ? 1 / st->area  // uniform in solid angle
               : area_to_solid_angle_pdf(s.pdf, ref, s.p, s.n);
    return s;
}

bool Triangle::behind(Point3 ref) const {
    if (shaded_mesh) return false;
    return dot(ref - p0, n) < 0;
}

Float Triangle::pdf_from(Point3 ref, Point3 p_light, Normal3 n_light) const {
    const std::optional<SphericalTriangle> st = spherical_from(*this, ref);
    return st ? 1 / st->area : area_to_solid_angle_pdf(inv_area, ref, p_light, n_light);
}

Float TriangleMesh::solid_angle(size_t i, Point3 ref) const { return triangle(i).solid_angle(ref); }

ShapeSample TriangleMesh::sample_triangle_from(size_t i, Point3 ref, Point2 u) const {
    return triangle(i).sample_from(ref, u);
}

bool TriangleMesh::behind_triangle(size_t i, Point3 ref) const { return triangle(i).behind(ref); }

Float TriangleMesh::pdf_triangle_from(size_t i, Point3 ref, Point3 p_light, Normal3 n_light) const {
    return triangle(i).pdf_from(ref, p_light, n_light);
}

// ---- spheres --------------------------------------------------------------------------

bool Sphere::intersect_object(Point3 o, Vec3 d, Float t_max, Float& t_hit, Point3& p_hit,
                              Float t_min) const {
    // Solve |o + t d|^2 = r^2 in double precision, with the numerically stable form.
    Vec3d od(o), dd(d);
    double a = dot(dd, dd);
    double b = 2 * dot(od, dd);
    double c = dot(od, od) - double(radius) * radius;
    // discriminant computed as in Hearn & Baker / pbrt-v4 to avoid cancellation:
    Vec3d v = od - dd * (b / (2 * a));
    double len = length(v);
    double disc = 4 * a * (double(radius) + len) * (double(radius) - len);
    if (disc < 0) return false;
    double root = std::sqrt(disc);
    double q = (b < 0) ? -0.5 * (b - root) : -0.5 * (b + root);
    double t0 = q / a, t1 = c / q;
    if (t0 > t1) std::swap(t0, t1);
    for (double t : {t0, t1}) {
        // Compared as the float returned, so that a caller asking again from t_min = t_hit
        // never gets the same hit back.
        if (!(Float(t) > t_min && Float(t) < t_max)) continue;
        Vec3d ph = od + dd * t;
        ph = ph * (double(radius) / length(ph));
        if (!full()) {
            if (ph.z < z_min || ph.z > z_max) continue;
            double phi = std::atan2(ph.y, ph.x);
            if (phi < 0) phi += 2 * std::numbers::pi;
            if (phi > phi_max) continue;
        }
        t_hit = Float(t);
        p_hit = Point3(ph);
        return true;
    }
    return false;
}

void Sphere::fill_hit(Point3 p_obj, SurfaceHit& h) const {
    Vec3 err_obj = Vec3(std::abs(p_obj.x), std::abs(p_obj.y), std::abs(p_obj.z)) * gamma_bound(5);
    to_world(world_from_object, p_obj, err_obj, h.p, h.p_error);
    Normal3 n = normalize(world_from_object.normal(p_obj));
    if (flip_normals) n = -n;
    h.ng = h.ns = n;
    Float phi = std::atan2(p_obj.y, p_obj.x);
    if (phi < 0) phi += 2 * kPi;
    Float cos_theta = clamp(p_obj.z / radius, Float(-1), Float(1));
    Float theta = safe_acos(cos_theta);
    h.uv = Point2(phi / phi_max, (theta - theta_z_min) / (theta_z_max - theta_z_min));
    Vec3 dpdu_obj(-phi_max * p_obj.y, phi_max * p_obj.x, 0);
    if (length_squared(dpdu_obj) == 0) {
        Vec3 s, t;
        coordinate_system(normalize(Vec3(p_obj)), s, t);
        dpdu_obj = s;
    }
    h.dpdu = world_from_object.vector(dpdu_obj);
    // dp/dv = (theta_max - theta_min) (z cos phi, z sin phi, -r sin theta).
    Float sin_theta = safe_sqrt(1 - sqr(cos_theta));
    Float d_theta = theta_z_max - theta_z_min;
    Vec3 dpdv_obj = Vec3(p_obj.z * std::cos(phi), p_obj.z * std::sin(phi), -radius * sin_theta) * d_theta;
    h.dpdv = world_from_object.vector(dpdv_obj);
    // The outward normal is p / r: dn/du = dp/du / r (flipped with the normal).
    Float k = (flip_normals ? -1 : 1) / radius;
    h.dndu = world_from_object.normal(Normal3(dpdu_obj * k));
    h.dndv = world_from_object.normal(Normal3(dpdv_obj * k));
}

Float Sphere::area() const {
    double s = similarity_scale(world_from_object);
    return Float(double(phi_max) * radius * (z_max - z_min) * s * s);
}

ShapeSample Sphere::sample_area(Point2 u) const {
    ShapeSample ss;
    Point3 p_obj;
    if (full()) {
        p_obj = sample_uniform_sphere(u) * radius;
    } else {
        Float z = lerp(u.x, z_min, z_max);
        Float phi = u.y * phi_max;
        Float rxy = safe_sqrt(sqr(radius) - sqr(z));
        p_obj = Point3(rxy * std::cos(phi), rxy * std::sin(phi), z);
    }
    SurfaceHit h;
    fill_hit(p_obj, h);
    ss.p = h.p;
    ss.p_error = h.p_error;
    ss.n = h.ng;
    ss.pdf = 1 / area();
    return ss;
}

ShapeSample Sphere::sample_from(Point3 ref, Point2 u) const {
    Point3 center = world_from_object.point(Point3(0, 0, 0));
    double s = similarity_scale(world_from_object);
    Float r_world = Float(radius * s);
    Float dc2 = length_squared(ref - center);
    if (!full() || dc2 <= sqr(r_world) * Float(1.0001)) {
        ShapeSample ss = sample_area(u);
        ss.pdf = area_to_solid_angle_pdf(ss.pdf, ref, ss.p, ss.n);
        return ss;
    }
    // Sample the cone of directions subtended by the sphere (uniform in solid angle),
    // then find the point on the sphere (Pharr et al. 4th ed. sec. 6.2.4).
    Float sin2_max = sqr(r_world) / dc2;
    Float sin_max = safe_sqrt(sin2_max);
    Float cos_max = safe_sqrt(1 - sin2_max);
    Float one_minus_cos_max = 1 - cos_max;
    Float cos_t = (cos_max - 1) * u.x + 1;
    Float sin2_t = 1 - sqr(cos_t);
    if (sin2_max < Float(0.00068523)) {  // small cones: Taylor expansion, ~1e-8 accurate
        sin2_t = sin2_max * u.x;
        cos_t = std::sqrt(1 - sin2_t);
        one_minus_cos_max = sin2_max / 2;
    }
    Float cos_alpha = sin2_t / sin_max + cos_t * safe_sqrt(1 - sin2_t / sqr(sin_max));
    Float sin_alpha = safe_sqrt(1 - sqr(cos_alpha));
    Float phi = u.y * 2 * kPi;
    Frame f = Frame::from_z(normalize(center - ref));
    Vec3 w_local = spherical_direction(sin_alpha, cos_alpha, phi);
    Vec3 n_world = f.to_world(Vec3(-w_local.x, -w_local.y, -w_local.z));
    Point3 p = center + n_world * r_world;
    ShapeSample ss;
    ss.p = p;
    ss.p_error = Vec3(std::abs(p.x), std::abs(p.y), std::abs(p.z)) * gamma_bound(5);
    ss.n = flip_normals ? -n_world : n_world;
    ss.pdf = 1 / (2 * kPi * one_minus_cos_max);
    return ss;
}

Float Sphere::pdf_from(Point3 ref, Point3 p, Normal3 n) const {
    Point3 center = world_from_object.point(Point3(0, 0, 0));
    double s = similarity_scale(world_from_object);
    Float r_world = Float(radius * s);
    Float dc2 = length_squared(ref - center);
    if (!full() || dc2 <= sqr(r_world) * Float(1.0001))
        return area_to_solid_angle_pdf(1 / area(), ref, p, n);
    Float sin2_max = sqr(r_world) / dc2;
    Float cos_max = safe_sqrt(1 - sin2_max);
    Float one_minus_cos_max = 1 - cos_max;
    if (sin2_max < Float(0.00068523)) one_minus_cos_max = sin2_max / 2;
    return 1 / (2 * kPi * one_minus_cos_max);
}

// ---- disks ----------------------------------------------------------------------------

bool Disk::intersect_object(Point3 o, Vec3 d, Float t_max, Float& t_hit, Point3& p_hit) const {
    if (d.z == 0) return false;
    Float t = (height - o.z) / d.z;
    if (!(t > 0 && t < t_max)) return false;
    Point3 ph = o + d * t;
    Float dist2 = sqr(ph.x) + sqr(ph.y);
    if (dist2 > sqr(radius) || dist2 < sqr(inner_radius)) return false;
    if (phi_max < 2 * kPi) {
        Float phi = std::atan2(ph.y, ph.x);
        if (phi < 0) phi += 2 * kPi;
        if (phi > phi_max) return false;
    }
    ph.z = height;
    t_hit = t;
    p_hit = ph;
    return true;
}

void Disk::fill_hit(Point3 p_obj, SurfaceHit& h) const {
    to_world(world_from_object, p_obj, Vec3(0, 0, 0), h.p, h.p_error);
    Normal3 n = normalize(world_from_object.normal(Normal3(0, 0, 1)));
    if (flip_normals) n = -n;
    h.ng = h.ns = n;
    Float dist = std::sqrt(sqr(p_obj.x) + sqr(p_obj.y));
    Float phi = std::atan2(p_obj.y, p_obj.x);
    if (phi < 0) phi += 2 * kPi;
    h.uv = Point2(phi / phi_max, (radius - dist) / (radius - inner_radius));
    Vec3 dpdu_obj(-phi_max * p_obj.y, phi_max * p_obj.x, 0);
    if (length_squared(dpdu_obj) == 0) dpdu_obj = Vec3(1, 0, 0);
    h.dpdu = world_from_object.vector(dpdu_obj);
    // v runs inwards from the rim: dp/dv = (x, y, 0) (inner - outer radius) / dist.
    Vec3 dpdv_obj = dist > 0 ? Vec3(p_obj.x, p_obj.y, 0) * ((inner_radius - radius) / dist)
                             : Vec3(0, -(radius - inner_radius), 0);
    h.dpdv = world_from_object.vector(dpdv_obj);
}

bool Cylinder::intersect_object(Point3 o, Vec3 d, Float t_max, Float& t_hit, Point3& p_hit,
                                Float t_min) const {
    // x^2 + y^2 = r^2 along o + t d, in double, with the cancellation-free discriminant of
    // the sphere's (the distance of the line from the axis, not b^2 - 4ac).
    const double ox = o.x, oy = o.y, dx = d.x, dy = d.y;
    const double a = dx * dx + dy * dy;
    if (a == 0) return false;  // parallel to the axis
    const double b = 2 * (dx * ox + dy * oy);
    const double c = ox * ox + oy * oy - double(radius) * radius;
    const double fx = ox - b / (2 * a) * dx, fy = oy - b / (2 * a) * dy;
    const double len = std::sqrt(fx * fx + fy * fy);
    const double disc = 4 * a * (double(radius) + len) * (double(radius) - len);
    if (disc < 0) return false;
    const double root = std::sqrt(disc);
    const double q = (b < 0) ? -0.5 * (b - root) : -0.5 * (b + root);
    double t0 = q / a, t1 = q != 0 ? c / q : t0;
    if (t0 > t1) std::swap(t0, t1);
    for (double t : {t0, t1}) {
        // Compared as the float returned (see Sphere::intersect_object).
        if (!(Float(t) > t_min && Float(t) < t_max)) continue;
        const double px = ox + t * dx, py = oy + t * dy, pz = double(o.z) + t * double(d.z);
        if (pz < z_min || pz > z_max) continue;
        double phi = std::atan2(py, px);
        if (phi < 0) phi += 2 * std::numbers::pi;
        if (phi > phi_max) continue;
        // On the surface: the hit's distance from the axis is the radius, up to rounding.
        const double k = double(radius) / std::sqrt(px * px + py * py);
        t_hit = Float(t);
        p_hit = Point3(Float(px * k), Float(py * k), Float(pz));
        return true;
    }
    return false;
}

void Cylinder::fill_hit(Point3 p_obj, SurfaceHit& h) const {
    const Vec3 err_obj = Vec3(std::abs(p_obj.x), std::abs(p_obj.y), 0) * gamma_bound(3);
    to_world(world_from_object, p_obj, err_obj, h.p, h.p_error);
    Normal3 n = normalize(world_from_object.normal(Normal3(p_obj.x, p_obj.y, 0)));
    if (flip_normals) n = -n;
    h.ng = h.ns = n;
    Float phi = std::atan2(p_obj.y, p_obj.x);
    if (phi < 0) phi += 2 * kPi;
    h.uv = Point2(phi / phi_max, (p_obj.z - z_min) / (z_max - z_min));
    const Vec3 dpdu_obj(-phi_max * p_obj.y, phi_max * p_obj.x, 0);
    const Vec3 dpdv_obj(0, 0, z_max - z_min);
    h.dpdu = world_from_object.vector(dpdu_obj);
    h.dpdv = world_from_object.vector(dpdv_obj);
    // The outward normal is (x, y, 0) / r: dn/du = dp/du / r, dn/dv = 0.
    const Float k = (flip_normals ? -1 : 1) / radius;
    h.dndu = world_from_object.normal(Normal3(dpdu_obj * k));
    h.dndv = Normal3(0, 0, 0);
}

Float Cylinder::area() const {
    const double s = similarity_scale(world_from_object);
    return Float(double(z_max - z_min) * radius * phi_max * s * s);
}

Float Disk::area() const {
    double s = similarity_scale(world_from_object);
    return Float(double(phi_max) * 0.5 * (sqr(double(radius)) - sqr(double(inner_radius))) * s * s);
}

ShapeSample Disk::sample_area(Point2 u) const {
    ShapeSample ss;
    Point3 p_obj;
    if (inner_radius == 0 && phi_max >= 2 * kPi) {
        Point2 pd = sample_uniform_disk_concentric(u);
        p_obj = Point3(pd.x * radius, pd.y * radius, height);
    } else {
        Float r = std::sqrt(lerp(u.x, sqr(inner_radius), sqr(radius)));
        Float phi = u.y * phi_max;
        p_obj = Point3(r * std::cos(phi), r * std::sin(phi), height);
    }
    SurfaceHit h;
    fill_hit(p_obj, h);
    ss.p = h.p;
    ss.p_error = h.p_error;
    ss.n = h.ng;
    ss.pdf = 1 / area();
    return ss;
}

}  // namespace sr
