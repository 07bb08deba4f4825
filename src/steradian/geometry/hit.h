#pragma once
/// Ray-surface intersection records and robust ray spawning.
#include <cstdint>
#include <cstring>
#if defined(__SSE4_1__)
#include <smmintrin.h>
#endif

#include "steradian/core/math.h"

namespace sr {

/// pbrt-style floating-point error bound factor gamma(n) = n u / (1 - n u), u = 2^-24.
constexpr Float gamma_bound(int n) {
    constexpr Float u = std::numeric_limits<Float>::epsilon() * Float(0.5);
    return (n * u) / (1 - n * u);
}

/// A surface point reached by a ray, in world space.
struct SurfaceHit {
    Point3 p;           ///< position
    Vec3 p_error;       ///< conservative absolute error bound of p per axis
    Normal3 ng;         ///< geometric normal, unit, oriented by the shape's orientation rules
    Normal3 ns;         ///< shading normal, unit, in the hemisphere of ng
    Vec3 dpdu;          ///< surface tangent (not normalised), for anisotropic frames
    /// Unit shading tangent: dpdu made perpendicular to ns and normalised, when the shape
    /// knows it in advance (flat triangles); (0, 0, 0) when it is to be computed from dpdu
    /// and ns. Whoever changes ns or dpdu of a hit must reset it to zero.
    Vec3 ss{0, 0, 0};
    Vec3 dpdv{0, 0, 0}; ///< dp/dv of the (u, v) parameterisation (bump mapping)
    Vec3 dndu{0, 0, 0}, dndv{0, 0, 0};  ///< derivatives of the (unnormalised) shading normal
    Point2 uv;          ///< surface parameterisation
    /// Texture footprint: the change of p, u and v from one pixel to the next in x and y
    /// (pbrt-v4's dpdx, dpdy, dudx, ...). All 0 (no filtering: the finest texture detail)
    /// unless the renderer computes them (set_footprint_from_rays, set_uv_differentials);
    /// Scene::intersect sets them to 0.
    Vec3 dpdx{0, 0, 0}, dpdy{0, 0, 0};
    Float dudx = 0, dvdx = 0, dudy = 0, dvdy = 0;
    Vec3 wo;            ///< unit direction towards the ray origin
    Float t = 0;        ///< ray parameter
    int shape = -1;     ///< index into Scene::shapes
    int instance = -1;  ///< index into Scene::instances when the shape is instanced, else -1
    uint32_t prim = 0;  ///< primitive within the shape (triangle index)
    int material = -1;  ///< index into Scene::materials, -1: interface (no scattering)
    int light = -1;     ///< index into Scene::lights if the surface emits, else -1
};

/// The unit shading tangent of a frame around the unit normal ns: dpdu made perpendicular to
/// ns (Gram-Schmidt) and normalised; (0, 0, 0) if dpdu is (nearly) parallel to ns, where the
/// caller chooses an arbitrary tangent. The materials' shading frame and the flat-triangle
/// cache (SurfaceHit::ss) both use it, so a cached tangent equals a computed one.
inline Vec3 shading_tangent(Vec3 dpdu, Normal3 ns) {
    Vec3 s = dpdu - ns * dot(ns, dpdu);
    Float l2 = length_squared(s);
    return l2 > 1e-20f ? s / std::sqrt(l2) : Vec3(0, 0, 0);
}

/// du/dx, dv/dx, du/dy, dv/dy of h from its dpdx, dpdy and the tangents dpdu, dpdv: the
/// least-squares solution of dpdu du + dpdv dv = dp (normal equations), 0 where the tangents
/// are degenerate, clamped to +-1e8 as pbrt-v4 does.
inline void set_uv_differentials(SurfaceHit& h) {
    const Float a00 = dot(h.dpdu, h.dpdu), a01 = dot(h.dpdu, h.dpdv), a11 = dot(h.dpdv, h.dpdv);
    const Float det = a00 * a11 - a01 * a01;
    Float inv = 1 / det;
    if (!std::isfinite(inv)) inv = 0;
    auto solve = [&](Vec3 dp, Float& du, Float& dv) {
        const Float b0 = dot(h.dpdu, dp), b1 = dot(h.dpdv, dp);
        du = (a11 * b0 - a01 * b1) * inv;
        dv = (a00 * b1 - a01 * b0) * inv;
        du = std::isfinite(du) ? std::clamp(du, Float(-1e8), Float(1e8)) : 0;
        dv = std::isfinite(dv) ? std::clamp(dv, Float(-1e8), Float(1e8)) : 0;
    };
    solve(h.dpdx, h.dudx, h.dvdx);
    solve(h.dpdy, h.dudy, h.dvdy);
}

/// Sets h.dpdx, h.dpdy from a camera ray's differentials: rx, ry are the rays through the
/// film positions one pixel over in x and y (the same lens sample), their offsets from
/// `ray` scaled by `scale` (pbrt-v4 scales them by max(1/8, 1/sqrt(spp))); each meets the
/// tangent plane of h (normal ng) and dp is that point minus h.p. Where a differential ray
/// runs parallel to the plane both are 0. Then the uv differentials.
inline void set_footprint_from_rays(SurfaceHit& h, const Ray& ray, const Ray& rx, const Ray& ry,
                                    Float scale) {
    const Vec3 n(h.ng.x, h.ng.y, h.ng.z);
    const Float plane = dot(n, h.p);
    auto meet = [&](const Ray& r, Vec3& dp) {
        const Point3 o = ray.o + (r.o - ray.o) * scale;
        const Vec3 d = ray.d + (r.d - ray.d) * scale;
        const Float den = dot(n, d);
        if (den == 0) return false;
        const Float t = (plane - dot(n, o)) / den;
        dp = o + d * t - h.p;
        return std::isfinite(t) && std::isfinite(length_squared(dp));
    };
    if (!meet(rx, h.dpdx) || !meet(ry, h.dpdy)) h.dpdx = h.dpdy = Vec3(0, 0, 0);
    set_uv_differentials(h);
}

/// Whether v is not (0, 0, 0), as one branch: which component of a tangent is zero varies
/// from surface to surface, and `x != 0 || ...` was three data-dependent branches.
inline bool is_nonzero(Vec3 v) { return (v.x != 0) | (v.y != 0) | (v.z != 0); }

/// The next float above / below v (for finite v; 0 and -0 step to the smallest denormal).
inline Float next_float_up(Float v) {
    if (std::isinf(v) && v > 0) return v;
    if (v == -0.f) v = 0.f;
    uint32_t u;
    std::memcpy(&u, &v, sizeof u);
    u = v >= 0 ? u + 1 : u - 1;
    std::memcpy(&v, &u, sizeof u);
    return v;
}
inline Float next_float_down(Float v) {
    if (std::isinf(v) && v < 0) return v;
    if (v == 0.f) v = -0.f;
    uint32_t u;
    std::memcpy(&u, &v, sizeof u);
    u = v > 0 ? u - 1 : u + 1;
    std::memcpy(&v, &u, sizeof u);
    return v;
}

/// Offsets p along n far enough to escape the error box p_error, on the side of w
/// (Pharr et al., "Physically Based Rendering", 4th ed., sec. 6.8.6): p + d n (or - d n when
/// w points below the surface), d = |n| . p_error, with each component then stepped one float
/// further in the direction of its offset (next_float_up where it is positive, next_float_down
/// where it is negative, unchanged where it is 0). This is that definition, one component at a
/// time; offset_ray_origin computes the same bits faster.
inline Point3 offset_ray_origin_per_component(Point3 p, Vec3 p_error, Normal3 n, Vec3 w) {
    Float d = std::abs(n.x) * p_error.x + std::abs(n.y) * p_error.y + std::abs(n.z) * p_error.z;
    Vec3 offset = n * d;
    if (dot(w, n) < 0) offset = -offset;
    Point3 po = p + offset;
    for (int i = 0; i < 3; ++i) {
        if (offset[i] > 0)
            po[i] = next_float_up(po[i]);
        else if (offset[i] < 0)
            po[i] = next_float_down(po[i]);
    }
    return po;
}

/// offset_ray_origin_per_component's result (bit for bit), for spawning rays.
inline Point3 offset_ray_origin(Point3 p, Vec3 p_error, Normal3 n, Vec3 w) {
#if defined(__SSE4_1__)
    // The three components in one register. Written per component through Point3's
    // operator[], the compiler keeps po in memory and reloads two of the separately stored
    // floats as one 8-byte value: a store-to-load forwarding stall on every spawned ray.
    // Here the step is integer arithmetic on the bits: +1 where po and the offset have the
    // same sign (the magnitude grows), -1 where they differ; from +-0 to the smallest
    // denormal of the offset's sign; an infinity stepped outwards stays infinite.
    Float d = std::abs(n.x) * p_error.x + std::abs(n.y) * p_error.y + std::abs(n.z) * p_error.z;
    if (dot(w, n) < 0) d = -d;
    __m128 off = _mm_mul_ps(_mm_setr_ps(n.x, n.y, n.z, 0), _mm_set1_ps(d));
    __m128 po = _mm_add_ps(_mm_setr_ps(p.x, p.y, p.z, 0), off);
    __m128i bits = _mm_castps_si128(po), off_bits = _mm_castps_si128(off);
    const __m128i sign = _mm_set1_epi32(int32_t(0x80000000u));
    __m128i moving = _mm_castps_si128(
        _mm_or_ps(_mm_cmpgt_ps(off, _mm_setzero_ps()), _mm_cmplt_ps(off, _mm_setzero_ps())));
    __m128i magnitude = _mm_andnot_si128(sign, bits);
    __m128i same = _mm_cmpgt_epi32(_mm_xor_si128(bits, off_bits), _mm_set1_epi32(-1));
    __m128i step = _mm_sub_epi32(_mm_and_si128(same, _mm_set1_epi32(2)), _mm_set1_epi32(1));
    __m128i inf_out = _mm_and_si128(same, _mm_cmpeq_epi32(magnitude, _mm_set1_epi32(0x7f800000)));
    step = _mm_and_si128(_mm_andnot_si128(inf_out, step), moving);
    __m128i stepped = _mm_add_epi32(bits, step);
    __m128i from_zero = _mm_or_si128(_mm_and_si128(off_bits, sign), _mm_set1_epi32(1));
    __m128i at_zero = _mm_and_si128(moving, _mm_cmpeq_epi32(magnitude, _mm_setzero_si128()));
    __m128 r = _mm_castsi128_ps(_mm_blendv_epi8(stepped, from_zero, at_zero));
    alignas(16) Float c[4];
    _mm_store_ps(c, r);
    return {c[0], c[1], c[2]};
#else
    return offset_ray_origin_per_component(p, p_error, n, w);
#endif
}

/// A ray leaving the hit in direction w (any length).
inline Ray spawn_ray(const SurfaceHit& h, Vec3 w) {
    return Ray{offset_ray_origin(h.p, h.p_error, h.ng, w), w, kInfinity};
}

/// A ray from the hit towards point target, stopping just short of it (shadow rays).
inline Ray spawn_ray_to(const SurfaceHit& h, Point3 target) {
    Point3 o = offset_ray_origin(h.p, h.p_error, h.ng, target - h.p);
    Vec3 d = target - o;
    return Ray{o, d, 1 - Float(1e-4)};
}

/// A shadow ray between two surface points, each offset off its own surface.
inline Ray spawn_ray_between(const SurfaceHit& from, Point3 to_p, Vec3 to_err, Normal3 to_n) {
    Point3 o = offset_ray_origin(from.p, from.p_error, from.ng, to_p - from.p);
    Point3 t = offset_ray_origin(to_p, to_err, to_n, o - to_p);
    return Ray{o, t - o, 1 - Float(1e-4)};
}

}  // namespace sr
