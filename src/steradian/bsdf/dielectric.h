#pragma once
/// A dielectric interface (glass, water): specular or rough (microfacet) reflection and
/// refraction, the split between them given by the Fresnel equations.
///
/// Smooth (mf.effectively_smooth()): one specular reflection and one specular refraction
/// direction, chosen with probability R and T = 1 - R (so the sampling weight f |cos| / pdf is
/// exactly 1, or 1/etap^2 for refraction in Radiance mode).
/// Rough: the microfacet BSDF of Walter, Marschner, Li, Torrance 2007, "Microfacet Models for
/// Refraction through Rough Surfaces" (EGSR), with the Trowbridge-Reitz distribution, Smith's
/// height-correlated G, visible-normal sampling (Heitz 2018) and the reflection/refraction
/// choice made per sampled microfacet by its Fresnel reflectance. Single scattering only: energy
/// lost to inter-reflections between microfacets is not returned (albedo < 1 at high
/// roughness).
///
/// Conventions (see fresnel.h):
/// - eta = n_below / n_above: the IOR on the side the shading normal points away from (z < 0,
///   "inside") over the IOR on the side it points to (z > 0, "outside"). eta > 1 for glass
///   in air with an outward normal; eta < 1 describes an interface seen from the denser side.
/// - BsdfSample::eta of a refraction is the relative IOR crossed, n_(wi side) / n_(wo side):
///   eta when wo is above, 1/eta when wo is below; 1 for reflections. Integrators that apply
///   Russian roulette to the throughput should divide out the radiance scaling, i.e. track
///   eta_scale *= sqr(sample.eta) on Radiance-mode refraction (pbrt-v4's etaScale).
/// - TransportMode: in Radiance mode a refraction carries the radiance scaling
///   (n_(wo side) / n_(wi side))^2 = 1 / etap^2 (Veach 1997, "Robust Monte Carlo Methods
///   for Light Transport Simulation", Ch. 5: radiance is compressed into the smaller solid
///   angle of the denser medium); in Importance mode it is not applied, which makes the
///   Importance-mode BSDF the adjoint:
///   f_importance(wo, wi) = f_radiance(wi, wo) (Veach 1997, Ch. 5; BTDFs obey
///   f(wo, wi) / n_o^2 = f(wi, wo) / n_i^2).
/// - eta == 1 (index-matched) is a pass-through: specular transmission wi = -wo with weight 1,
///   whatever the roughness.
///
/// Dispersion contract: the lobe takes one scalar eta because the refracted direction depends
/// on it, and one path can follow only one direction. A material whose IOR varies with
/// wavelength must evaluate its eta spectrum at the hero wavelength lambda[0], build the lobe
/// with that value, and call lambda.terminate_secondary() before the path's throughput is
/// multiplied by anything this lobe returns (the secondary wavelengths' values would
/// otherwise be computed with the hero's eta). A constant eta (ConstantSpectrum) needs no
/// termination. Guard against a spectrum that is 0 outside its tabulated range: use eta = 1
/// there (pbrt-v4 does the same).
#include "steradian/bsdf/bxdf_common.h"
#include "steradian/bsdf/microfacet.h"

namespace sr {

struct DielectricLobe {
    Float eta = 1;       ///< relative IOR n_below / n_above (see the header comment)
    TrowbridgeReitz mf;  ///< roughness; alpha < 1e-3 in both axes means smooth (specular)

    /// BSDF value (1/sr, no cosine) for wo, wi in the shading frame, on the same side
    /// (reflection) or opposite sides (refraction, with the Radiance-mode scaling 1/etap^2).
    /// Zero for smooth interfaces (the deltas are only reachable through sample()).
    SampledSpectrum f(Vec3 wo, Vec3 wi, TransportMode mode) const;
    /// Samples reflection or refraction off a visible microfacet (rough) or the specular pair
    /// (smooth; pdf_sa is then the discrete probability R or T and f the delta's weight).
    /// uc chooses reflection (uc < R) or refraction; u samples the microfacet normal. Empty for
    /// grazing wo, total internal reflection rounding failures, and microfacet samples whose
    /// scattered direction lands on the wrong side of the macro-surface.
    std::optional<BsdfSample> sample(Vec3 wo, Float uc, Point2 u, TransportMode mode) const;
    /// Solid-angle pdf of sample() producing wi (rough); 0 for smooth interfaces.
    Float pdf(Vec3 wo, Vec3 wi, TransportMode mode) const;

    /// One branch of the interface, for layered lobes that must cross it or stay below it
    /// (pbrt-v4's BxDFReflTransFlags).
    enum class Branch : uint8_t { Reflection, Transmission };
    /// sample() forced into `branch`: the same visible microfacet (rough) or the specular
    /// direction (smooth), then always that branch, so pdf_sa is the density of this
    /// restricted sampler (smooth: 1) and f the BSDF value as in sample(). *branch_prob
    /// receives the probability with which sample() itself would have taken that branch at
    /// that microfacet (R or 1 - R), so sample()'s density of wi is pdf_sa * *branch_prob.
    /// Empty when the branch is impossible (reflection of an index-matched interface,
    /// transmission under total internal reflection) or the direction lands on the wrong side.
    std::optional<BsdfSample> sample_branch(Vec3 wo, Point2 u, TransportMode mode, Branch branch,
                                            Float* branch_prob) const;
    /// Solid-angle density of sample_branch(wo, ., ., branch) producing wi (rough); 0 for
    /// smooth interfaces and for a wi of the other branch.
    Float pdf_branch(Vec3 wo, Vec3 wi, Branch branch) const;
    uint8_t flags() const {
        if (eta == 1) return kLobeTransmission | kLobeSpecular;
        return kLobeReflection | kLobeTransmission |
               (mf.effectively_smooth() ? kLobeSpecular : kLobeGlossy);
    }
};

}  // namespace sr
