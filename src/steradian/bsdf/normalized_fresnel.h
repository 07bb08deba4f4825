#pragma once
/// The exit lobe of subsurface scattering (pbrt-v4's NormalizedFresnelBxDF, its BSSRDF's
/// directional term S_w): where light leaves a subsurface material, it leaves with the
/// distribution f = (1 - F_r(cos theta_i, eta)) / (c pi) in the outside hemisphere, F_r the
/// Fresnel reflectance of light arriving from outside at the interface of relative IOR eta,
/// and c = 1 - 2 int_0^1 F_r(mu, eta) mu dmu (the diffuse Fresnel transmittance) normalising
/// it: int f |cos| dw = 1 over the hemisphere. In Radiance mode f carries eta^2, as pbrt-v4's:
/// the radiance of light crossing into the denser side is compressed into a smaller solid
/// angle (the entry refraction's 1 / eta^2, see dielectric.h, is undone on the way out).
///
/// The shading frame's +z is the outside: the integrator builds this lobe at the exit point
/// with z along the normal turned to the side the path leaves to. Reflection only, on wo's
/// side; cosine-weighted sampling (as pbrt-v4).
#include "steradian/bsdf/bxdf_common.h"
#include "steradian/bsdf/fresnel.h"
#include "steradian/sampling/warp.h"

namespace sr {

/// c(eta) = 1 - 2 int_0^1 F_r(mu, eta) mu dmu, by the midpoint rule on 4096 intervals (in
/// double; error < 1e-6). pbrt-v4 uses a polynomial fit, 1 - 2 FresnelMoment1(1 / eta), which
/// agrees to 3e-5 for eta in [1.1, 2] but is 0.4 % low at eta = 1 (where c is exactly 1): the
/// quadrature keeps the lobe's energy exactly 1. Call once per material, not per hit.
inline Float normalized_fresnel_c(Float eta) {
    constexpr int kN = 4096;
    double sum = 0;
    for (int i = 0; i < kN; ++i) {
        double mu = (i + 0.5) / kN;
        sum += double(fr_dielectric(Float(mu), eta)) * mu;
    }
    return Float(1 - 2 * sum / kN);
}

/// The fraction of diffuse (cosine-weighted) light inside a medium of relative IOR eta that
/// its boundary reflects back in: 2 int_0^1 F_r(mu, 1 / eta) mu dmu, total internal reflection
/// included (0.596 at eta = 1.5, 0 at eta = 1), by the same quadrature. Once per material.
inline Float diffuse_internal_reflectance(Float eta) {
    constexpr int kN = 4096;
    double sum = 0;
    for (int i = 0; i < kN; ++i) {
        double mu = (i + 0.5) / kN;
        sum += double(fr_dielectric(Float(mu), 1 / eta)) * mu;
    }
    return Float(2 * sum / kN);
}

struct NormalizedFresnelLobe {
    Float eta = 1;                            ///< relative IOR, inside over outside
    Float c = 1;                              ///< normalized_fresnel_c(eta)
    static constexpr bool kIgnoresUc = true;  ///< sample() does not read uc

    SampledSpectrum f(Vec3 wo, Vec3 wi, TransportMode mode) const {
        if (!same_hemisphere(wo, wi)) return SampledSpectrum(0);
        return SampledSpectrum(value(wi, mode));
    }
    std::optional<BsdfSample> sample(Vec3 wo, Float, Point2 u, TransportMode mode) const {
        Vec3 wi = sample_cosine_hemisphere(u);
        if (wo.z < 0) wi.z = -wi.z;
        Float pdf = cosine_hemisphere_pdf(std::abs(wi.z));
        if (pdf == 0) return std::nullopt;
        const SampledSpectrum f(value(wi, mode));
        // f |cos| / pdf = pi f: the sample's cos_over_pdf is pi.
        return BsdfSample{f, wi, pdf, kLobeReflection | kLobeDiffuse, 1, kPi};
    }
    Float pdf(Vec3 wo, Vec3 wi, TransportMode) const {
        if (!same_hemisphere(wo, wi)) return 0;
        return cosine_hemisphere_pdf(std::abs(wi.z));
    }
    uint8_t flags() const { return kLobeReflection | kLobeDiffuse; }

  private:
    Float value(Vec3 wi, TransportMode mode) const {
        Float v = (1 - fr_dielectric(std::abs(wi.z), eta)) / (c * kPi);
        return mode == TransportMode::Radiance ? v * sqr(eta) : v;
    }
};

}  // namespace sr
