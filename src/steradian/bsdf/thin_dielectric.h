#pragma once
/// A thin dielectric slab (a window pane): two parallel smooth interfaces with no absorption
/// between them. Light reflected back and forth inside the slab leaves either as reflection
/// (mirror direction) or as transmission straight through (the two refractions cancel, so
/// wi = -wo and the relative IOR crossed is 1). Summing the geometric series of internal
/// reflections incoherently, i.e. without interference (as pbrt-v4's ThinDielectricBxDF;
/// Born & Wolf Sec. 7.6.1 gives the coherent sum):
/// R' = R + T^2 R / (1 - R^2), T' = 1 - R', with R = fr_dielectric(|cos_o|, eta) of one
/// interface (the reflectance inside the slab equals the outer one by Snell's law and the
/// Stokes relations). Lossless: the sampling weight is exactly 1. Symmetric in the two sides.
#include "steradian/bsdf/bxdf_common.h"
#include "steradian/bsdf/fresnel.h"

namespace sr {

struct ThinDielectricLobe {
    Float eta = 1;  ///< IOR of the slab relative to the surrounding medium

    /// Total reflectance R' and transmittance T' = 1 - R' of the slab at |cos| of wo.
    struct Split {
        Float r, t;
    };
    Split split(Float cos_o) const {
        Float r = fr_dielectric(std::abs(cos_o), eta), t = 1 - r;
        if (r < 1) {
            r += sqr(t) * r / (1 - sqr(r));
            t = 1 - r;
        }
        return {r, t};
    }

    /// Always 0: both lobes are Dirac deltas.
    SampledSpectrum f(Vec3, Vec3, TransportMode) const { return SampledSpectrum(0); }
    /// Mirror reflection with probability R' (f = R' / |cos|), else transmission wi = -wo with
    /// probability T' (f = T' / |cos|, no radiance scaling: the path leaves into the same
    /// medium). Empty for grazing wo.
    std::optional<BsdfSample> sample(Vec3 wo, Float uc, Point2, TransportMode) const {
        if (wo.z == 0) return std::nullopt;
        Split s = split(wo.z);
        Float cos_o = std::abs(wo.z);
        if (uc < s.r) {
            return BsdfSample{SampledSpectrum(s.r / cos_o), Vec3(-wo.x, -wo.y, wo.z), s.r,
                              kLobeReflection | kLobeSpecular, 1};
        }
        return BsdfSample{SampledSpectrum(s.t / cos_o), -wo, s.t, kLobeTransmission | kLobeSpecular,
                          1};
    }
    /// Always 0 (deltas).
    Float pdf(Vec3, Vec3, TransportMode) const { return 0; }
    uint8_t flags() const {
        if (eta == 1) return kLobeTransmission | kLobeSpecular;
        return kLobeReflection | kLobeTransmission | kLobeSpecular;
    }
};

}  // namespace sr
