#pragma once
/// Lambertian reflection: f = R / pi in the upper hemisphere of the shading frame.
#include "steradian/bsdf/bxdf_common.h"
#include "steradian/sampling/warp.h"

namespace sr {

struct LambertLobe {
    SampledSpectrum r;  ///< directional-hemispherical reflectance, in [0, 1]
    static constexpr bool kIgnoresUc = true;  ///< sample() does not read uc

    /// BSDF value (1/sr); zero unless wo and wi are on the same side.
    SampledSpectrum f(Vec3 wo, Vec3 wi, TransportMode) const {
        if (!same_hemisphere(wo, wi)) return SampledSpectrum(0);
        return r * kInvPi;
    }
    /// Cosine-weighted hemisphere sample on wo's side.
    std::optional<BsdfSample> sample(Vec3 wo, Float, Point2 u, TransportMode) const {
        Vec3 wi = sample_cosine_hemisphere(u);
        if (wo.z < 0) wi.z = -wi.z;
        Float pdf = cosine_hemisphere_pdf(std::abs(wi.z));
        if (pdf == 0) return std::nullopt;
        // f |cos| / pdf = r exactly: (r / pi) |cos| / (|cos| / pi).
        return BsdfSample{r * kInvPi, wi, pdf, kLobeReflection | kLobeDiffuse, 1, kPi};
    }
    Float pdf(Vec3 wo, Vec3 wi, TransportMode) const {
        if (!same_hemisphere(wo, wi)) return 0;
        return cosine_hemisphere_pdf(std::abs(wi.z));
    }
    uint8_t flags() const { return r.is_zero() ? kLobeNone : (kLobeReflection | kLobeDiffuse); }
};

}  // namespace sr
