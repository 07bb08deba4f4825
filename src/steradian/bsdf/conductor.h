#pragma once
/// A metal: specular reflection (smooth) or Torrance-Sparrow microfacet reflection (rough),
/// weighted by the Fresnel reflectance of a conductor with complex IOR eta + i k.
///
/// Rough: f(wo, wi) = D(wm) F(wo . wm) G(wo, wi) / (4 |cos_o| |cos_i|) with wm the half vector
/// (Torrance & Sparrow 1967, "Theory for Off-Specular Reflection from Roughened Surfaces",
/// JOSA 57(9); in the form of Walter et al. 2007, Eq. 20), Trowbridge-Reitz D, Smith's
/// height-correlated G, anisotropic when mf.alpha_x != mf.alpha_y (alpha_x along the shading
/// frame's s axis). Sampled by visible normals (Heitz 2018): weight G / G1(wo) * F. Single
/// scattering: some energy is lost at high roughness (albedo < F).
///
/// eta and k are relative to the outer medium and sampled at the path's wavelengths; they do
/// not change directions, so no wavelength is terminated. A material given a "reflectance" r
/// instead (pbrt-v4's conductor) can use eta = 1, k = 2 sqrt(r) / sqrt(1 - r), which makes
/// the normal-incidence reflectance r. Both sides of the surface reflect (wo.z < 0 mirrors
/// the configuration); culling back faces is the caller's business.
#include "steradian/bsdf/bxdf_common.h"
#include "steradian/bsdf/microfacet.h"

namespace sr {

struct ConductorLobe {
    SampledSpectrum eta;  ///< real part of the relative IOR per wavelength
    SampledSpectrum k;    ///< extinction coefficient (imaginary part) per wavelength
    TrowbridgeReitz mf;   ///< roughness; alpha < 1e-3 in both axes means a mirror
    static constexpr bool kIgnoresUc = true;  ///< sample() does not read uc

    /// BSDF value (1/sr, no cosine) for wo, wi on the same side; 0 for mirrors (deltas).
    SampledSpectrum f(Vec3 wo, Vec3 wi, TransportMode mode) const;
    /// Mirror reflection (pdf_sa = 1, f = F / |cos|) or a reflection off a visible
    /// microfacet normal sampled with u (uc unused). Empty if wo is grazing or the reflected
    /// direction falls below the surface.
    std::optional<BsdfSample> sample(Vec3 wo, Float uc, Point2 u, TransportMode mode) const;
    /// Solid-angle pdf of sample() producing wi: D(wo, wm) / (4 |wo . wm|); 0 for mirrors.
    Float pdf(Vec3 wo, Vec3 wi, TransportMode mode) const;
    uint8_t flags() const {
        return kLobeReflection | (mf.effectively_smooth() ? kLobeSpecular : kLobeGlossy);
    }
};

}  // namespace sr
