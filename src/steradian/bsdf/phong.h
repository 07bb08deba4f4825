#pragma once
/// The energy-normalised, reciprocal Phong BRDF (a steradian extension; pbrt-v4 has none):
///
///   f(wo, wi) = kd / pi + ks (n + 2) / (2 pi) max(0, cos alpha)^n,
///   cos alpha = wi . reflect(wo) = -wo.x wi.x - wo.y wi.y + wo.z wi.z,
///
/// alpha the angle between wi and the mirror direction of wo. cos alpha is symmetric in wo and
/// wi, so f is reciprocal; the original Phong term ks cos^n(alpha) / cos(theta_i) is not.
/// The factor (n + 2) / (2 pi) is the one that makes the specular albedo at normal incidence
/// exactly ks: int_H cos^n(theta) cos(theta) dw = 2 pi / (n + 2). Away from normal
/// incidence the horizon clips the lobe and the albedo is lower, so kd + ks <= 1 bounds the
/// albedo by 1 at every incidence. This is the form of R. R. Lewis, "Making Shaders More
/// Physically Plausible" (Computer Graphics Forum 13(2), 1994) and of E. P. Lafortune and
/// Y. D. Willems, "Using the Modified Phong Reflectance Model for Physically Based Rendering"
/// (Report CW 197, K.U. Leuven, 1994). kd + ks <= 1 is the material's responsibility.
///
/// Sampling: a cosine-weighted direction (diffuse) or a direction about reflect(wo) with
/// density (n + 1) / (2 pi) cos^n(alpha) (specular; a direction below the horizon is a failed
/// sample). With absorb = false the two are chosen with probabilities proportional to the
/// wavelength-averaged kd and ks; with absorb = true (Lafortune and Willems' scheme) with
/// probabilities avg(kd) and avg(ks) themselves, the rest 1 - avg(kd) - avg(ks) being an
/// absorption (no sample): the sampling weights are then close to 1 and the walk ends with the
/// probability that the surface absorbs. pdf() is the exact mixture density either way (a
/// sub-density when absorbing). Both sides of the surface reflect (wo.z < 0 mirrors the
/// configuration). TransportMode does not matter: the BRDF is symmetric.
#include <algorithm>
#include <cmath>

#include "steradian/bsdf/bxdf_common.h"
#include "steradian/bsdf/cosine_lobe.h"
#include "steradian/sampling/warp.h"

namespace sr {

struct PhongLobe {
    SampledSpectrum kd;   ///< diffuse albedo, in [0, 1]
    SampledSpectrum ks;   ///< specular albedo at normal incidence, kd + ks <= 1
    Float exponent = 1;   ///< Phong exponent n >= 0 (larger: narrower highlight)
    bool absorb = false;  ///< sampling may absorb (Lafortune-Willems), see the header comment

    /// cos alpha: wi against the mirror direction of wo (symmetric in the two).
    static Float cos_alpha(Vec3 wo, Vec3 wi) { return wo.z * wi.z - wo.x * wi.x - wo.y * wi.y; }

    /// BSDF value (1/sr, no cosine); zero unless wo and wi are on the same side.
    SampledSpectrum f(Vec3 wo, Vec3 wi, TransportMode) const {
        if (!same_hemisphere(wo, wi)) return SampledSpectrum(0);
        SampledSpectrum v = kd * kInvPi;
        Float c = cos_alpha(wo, wi);
        if (c > 0) v += ks * ((exponent + 2) * kInv2Pi * std::pow(c, exponent));
        return v;
    }

    /// Probabilities of the diffuse and the specular strategy (their sum is 1, or at most 1
    /// with absorb).
    struct Choice {
        Float diffuse = 0, specular = 0;
    };
    Choice choice() const {
        Float d = std::max(Float(0), kd.average()), s = std::max(Float(0), ks.average());
        Float total = d + s;
        if (total <= 0) return {};
        if (absorb && total <= 1) return {d, s};
        return {d / total, s / total};
    }

    /// uc < P_diffuse: cosine-weighted direction on wo's side; uc < P_diffuse + P_specular:
    /// the cos^n lobe about reflect(wo); otherwise (absorb only) empty. Also empty when the
    /// specular direction falls below the surface or wo is grazing.
    std::optional<BsdfSample> sample(Vec3 wo, Float uc, Point2 u, TransportMode mode) const {
        if (wo.z == 0) return std::nullopt;
        Choice p = choice();
        Vec3 wi;
        Float pdf_chosen;  // the chosen strategy's own density, from its sampling variables
        uint8_t fl;
        if (uc < p.diffuse) {
            wi = sample_cosine_hemisphere(u);
            pdf_chosen = p.diffuse * cosine_hemisphere_pdf(wi.z);
            if (wo.z < 0) wi.z = -wi.z;
            fl = kLobeReflection | kLobeDiffuse;
        } else if (uc < p.diffuse + p.specular) {
            Vec3 local = sample_cosine_power(u, exponent);
            Vec3 r(-wo.x, -wo.y, wo.z);
            wi = Frame::from_z(r).to_world(local);
            pdf_chosen = p.specular * cosine_power_pdf(local.z, exponent);
            fl = kLobeReflection | kLobeGlossy;
        } else {
            return std::nullopt;
        }
        if (!same_hemisphere(wo, wi)) return std::nullopt;
        // Add the density of the strategy not taken (evaluated at wi).
        Float pdf_sa = pdf_chosen;
        if (fl & kLobeDiffuse)
            pdf_sa += p.specular * cosine_power_pdf(cos_alpha(wo, wi), exponent);
        else
            pdf_sa += p.diffuse * cosine_hemisphere_pdf(std::abs(wi.z));
        if (!(pdf_sa > 0)) return std::nullopt;
        return BsdfSample{f(wo, wi, mode), wi, pdf_sa, fl, 1};
    }

    /// Solid-angle pdf of sample() producing wi: P_d |cos theta_i| / pi +
    /// P_s (n + 1) / (2 pi) max(0, cos alpha)^n on wo's side, 0 on the other.
    Float pdf(Vec3 wo, Vec3 wi, TransportMode) const {
        if (!same_hemisphere(wo, wi)) return 0;
        Choice p = choice();
        return p.diffuse * cosine_hemisphere_pdf(std::abs(wi.z)) +
               p.specular * cosine_power_pdf(cos_alpha(wo, wi), exponent);
    }

    uint8_t flags() const {
        uint8_t fl = kLobeNone;
        if (!kd.is_zero()) fl |= kLobeReflection | kLobeDiffuse;
        if (!ks.is_zero()) fl |= kLobeReflection | kLobeGlossy;
        return fl;
    }
};

}  // namespace sr
