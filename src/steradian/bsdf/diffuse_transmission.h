#pragma once
/// Lambertian reflection and Lambertian transmission (paper, leaves, lamp shades): f = r / pi
/// for wi on wo's side, t / pi on the other side. Reciprocal; albedo (max r + max t) <= 1 is
/// the material's responsibility. Sampling picks the side with probability proportional to
/// max(r) and max(t), then a cosine-weighted direction on that side.
#include "steradian/bsdf/bxdf_common.h"
#include "steradian/sampling/warp.h"

namespace sr {

struct DiffuseTransmissionLobe {
    SampledSpectrum r;  ///< directional-hemispherical reflectance, in [0, 1]
    SampledSpectrum t;  ///< directional-hemispherical transmittance, in [0, 1]

    /// BSDF value (1/sr, no cosine): r / pi on wo's side, t / pi on the other.
    SampledSpectrum f(Vec3 wo, Vec3 wi, TransportMode) const {
        return same_hemisphere(wo, wi) ? r * kInvPi : t * kInvPi;
    }
    /// uc < max(r) / (max(r) + max(t)) chooses reflection; u a cosine-weighted direction.
    /// Empty if both r and t are 0 or the direction is grazing.
    std::optional<BsdfSample> sample(Vec3 wo, Float uc, Point2 u, TransportMode) const {
        Float pr = r.max_value(), pt = t.max_value();
        if (pr + pt <= 0 || wo.z == 0) return std::nullopt;
        Vec3 wi = sample_cosine_hemisphere(u);
        if (wi.z == 0) return std::nullopt;
        Float pdf = cosine_hemisphere_pdf(wi.z);
        if (uc < pr / (pr + pt)) {
            if (wo.z < 0) wi.z = -wi.z;
            return BsdfSample{r * kInvPi, wi, pdf * pr / (pr + pt), kLobeReflection | kLobeDiffuse,
                              1};
        }
        if (wo.z > 0) wi.z = -wi.z;
        return BsdfSample{t * kInvPi, wi, pdf * pt / (pr + pt), kLobeTransmission | kLobeDiffuse,
                          1};
    }
    /// Solid-angle pdf: |cos wi| / pi times the probability of wi's side.
    Float pdf(Vec3 wo, Vec3 wi, TransportMode) const {
        Float pr = r.max_value(), pt = t.max_value();
        if (pr + pt <= 0 || wo.z == 0) return 0;
        Float side = same_hemisphere(wo, wi) ? pr : pt;
        return cosine_hemisphere_pdf(std::abs(wi.z)) * side / (pr + pt);
    }
    uint8_t flags() const {
        uint8_t fl = kLobeNone;
        if (!r.is_zero()) fl |= kLobeReflection | kLobeDiffuse;
        if (!t.is_zero()) fl |= kLobeTransmission | kLobeDiffuse;
        return fl;
    }
};

}  // namespace sr
