#include "steradian/bsdf/ward.h"

#include <cmath>

#include "steradian/sampling/warp.h"

namespace sr {

namespace {

/// Mirrors a lower-side configuration to the upper side (the lobe is two-sided).
Vec3 upper(Vec3 w, Float side) { return {w.x, w.y, w.z * side}; }

struct Choice {
    Float diffuse = 0, specular = 0;
};
Choice choice(const WardLobe& l) {
    Float d = std::max(Float(0), l.rho_d.average()), s = std::max(Float(0), l.rho_s.average());
    Float total = d + s;
    if (!(total > 0)) return {};
    return {d / total, s / total};
}

}  // namespace

Float WardLobe::specular(Vec3 wo, Vec3 wi) const {
    Vec3 h = wo + wi;
    if (!(h.z > 0)) return 0;
    Float hz2 = h.z * h.z;
    Float ex = std::exp(-(sqr(h.x / alpha_x) + sqr(h.y / alpha_y)) / hz2);
    if (ex == 0) return 0;  // also where hz2^2 underflows: no 0 / 0
    return ex * (length_squared(h) / hz2) / (kPi * alpha_x * alpha_y * hz2);
}

Float WardLobe::half_vector_pdf(Vec3 m) const {
    if (!(m.z > 0)) return 0;
    Float cos2 = m.z * m.z;
    Float ex = std::exp(-(sqr(m.x / alpha_x) + sqr(m.y / alpha_y)) / cos2);
    if (ex == 0) return 0;  // also where cos^3 underflows: no 0 / 0
    return ex / (kPi * alpha_x * alpha_y * cos2 * m.z);
}

SampledSpectrum WardLobe::f(Vec3 wo, Vec3 wi, TransportMode) const {
    if (!same_hemisphere(wo, wi)) return SampledSpectrum(0);
    Float side = wo.z < 0 ? Float(-1) : Float(1);
    return rho_d * kInvPi + rho_s * specular(upper(wo, side), upper(wi, side));
}

Float WardLobe::pdf(Vec3 wo, Vec3 wi, TransportMode) const {
    if (!same_hemisphere(wo, wi)) return 0;
    Float side = wo.z < 0 ? Float(-1) : Float(1);
    Vec3 o = upper(wo, side), i = upper(wi, side);
    Choice p = choice(*this);
    Float pdf = p.diffuse * cosine_hemisphere_pdf(i.z);
    if (p.specular > 0) {
        Vec3 h = o + i;
        if (length_squared(h) > 0) {
            Vec3 m = normalize(h);
            Float om = dot(o, m);
            if (om > 0) pdf += p.specular * half_vector_pdf(m) / (4 * om);
        }
    }
    return pdf;
}

std::optional<BsdfSample> WardLobe::sample(Vec3 wo, Float uc, Point2 u, TransportMode mode) const {
    if (wo.z == 0) return std::nullopt;
    Float side = wo.z < 0 ? Float(-1) : Float(1);
    Vec3 o = upper(wo, side);
    Choice p = choice(*this);
    if (!(p.diffuse + p.specular > 0)) return std::nullopt;
    Vec3 i;
    Float pdf_sa;
    uint8_t fl;
    if (uc < p.diffuse) {
        i = sample_cosine_hemisphere(u);
        pdf_sa = p.diffuse * cosine_hemisphere_pdf(i.z);
        if (p.specular > 0) {
            Vec3 m = normalize(o + i);
            Float om = dot(o, m);
            if (om > 0) pdf_sa += p.specular * half_vector_pdf(m) / (4 * om);
        }
        fl = kLobeReflection | kLobeDiffuse;
    } else {
        // Walter 2005: tan phi_m = (alpha_y / alpha_x) tan(2 pi u.x) in the quadrant of
        // 2 pi u.x, i.e. (cos, sin) phi_m along (alpha_x cos 2 pi u.x, alpha_y sin 2 pi u.x);
        // then tan^2 theta_m given phi_m.
        Float a = 2 * kPi * u.x;
        Float vx = alpha_x * std::cos(a), vy = alpha_y * std::sin(a);
        Float inv_len = 1 / std::sqrt(vx * vx + vy * vy);
        Float cp = vx * inv_len, sp = vy * inv_len;
        Float q = sqr(cp / alpha_x) + sqr(sp / alpha_y);
        Float e = -std::log1p(-u.y);  // tan^2 theta_m * q, exponential with mean 1
        Float tan_t = std::sqrt(e / q);
        Float cos_t = 1 / std::sqrt(1 + tan_t * tan_t);
        Float sin_t = tan_t * cos_t;
        Vec3 m(sin_t * cp, sin_t * sp, cos_t);
        Float om = dot(o, m);
        if (!(om > 0)) return std::nullopt;
        i = 2 * om * m - o;
        if (!(i.z > 0)) return std::nullopt;
        // p_m from the sampling variables: exp(-e) / (pi ax ay cos^3), times the Jacobian.
        Float pm = std::exp(-e) / (kPi * alpha_x * alpha_y * cos_t * cos_t * cos_t);
        pdf_sa = p.specular * pm / (4 * om) + p.diffuse * cosine_hemisphere_pdf(i.z);
        fl = kLobeReflection | kLobeGlossy;
    }
    if (!(pdf_sa > 0) || !(i.z > 0)) return std::nullopt;
    Vec3 wi = upper(i, side);
    return BsdfSample{f(wo, wi, mode), wi, pdf_sa, fl, 1};
}

}  // namespace sr
