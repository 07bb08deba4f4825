#pragma once
/// A layered BSDF: a dielectric interface (smooth or rough) over an opaque base lobe (Lambert or
/// conductor), with an optional homogeneous slab between them, evaluated by position-free
/// random walks as in Guo, Hasan, Zhao 2018, "Position-Free Monte Carlo Simulation for
/// Arbitrary Layered BSDFs" (ACM TOG 37(6)), in the stochastic form of pbrt-v4's LayeredBxDF
/// (Pharr, Jakob, Humphreys, "Physically Based Rendering", 4th ed., Sec. 14.3). This is
/// pbrt-v4's "coateddiffuse" and "coatedconductor".
///
/// Geometry. The walk runs in the lobe's shading frame in depth z only (the slab is laterally
/// infinite, positions do not matter): the interface at z = thickness, the base at z = 0. The
/// slab has extinction sigma_t = 1 per unit of thickness; with a non-zero albedo it scatters
/// (single-scattering albedo `albedo`, Henyey-Greenstein phase function of asymmetry g), with
/// albedo 0 it only absorbs (transmittance exp(-thickness / |cos|) per crossing). The stack is
/// two-sided (a wo below the surface sees the mirrored configuration) and opaque: f is zero for
/// wi on the other side of the surface. Walks are cut after max_depth events (interface or base
/// interactions and medium scatterings), as in pbrt-v4; energy beyond is lost.
///
/// Sampling (sample()). The physical random walk: the interface's own sample() at wo (a
/// reflection ends there), then inside, alternately distance sampling in the slab, the base's
/// sample() and the interface's sample() from below until a refraction leaves the slab. The
/// returned weight f |cos| / pdf_sa is the walk's path throughput, an unbiased estimate of the
/// BSDF integral (the estimator of a path of the layered structure, pbrt-v4's "pdf is
/// proportional"). For multiple importance sampling the returned pdf_sa is this lobe's pdf()
/// at the sampled direction and f is scaled to match, so that f |cos| / pdf_sa stays the walk's
/// weight and pdf_sa is the same function of (wo, wi) that next-event estimation sees.
///
/// Evaluation (f() and pdf()). Both are unbiased Monte Carlo estimates made by n_samples walks
/// with next-event estimation through the interface (Guo et al. 2018, Sec. 5; pbrt-v4 Sec.
/// 14.3.2): a walk enters through a transmission sampled at wo, a second transmission is sampled
/// at wi with the adjoint transport mode, and every base or medium vertex of the walk connects
/// to the exit both along that presampled direction and along its own sampled direction,
/// combined by the power heuristic. Unlike pbrt-v4, whose pdf() is a cheap approximation
/// (single-bounce, without the refraction Jacobians, mixed with a uniform density) used only for
/// MIS weights, pdf() here estimates the actual density of sample()'s walk by the same
/// next-event scheme with densities in place of BSDF values (the walk's interface reflections
/// weighted by the probability that sample() reflects there), so it integrates over the
/// hemisphere to the probability that sample() returns a non-specular direction and a
/// chi-square test of sample() against it is meaningful. Its multiple-importance weights use the
/// true densities of both connection strategies (pbrt-v4 uses the reverse-direction pdf for
/// one of them). pdf() is floored at kPdfFloor so that a sampled direction never gets a zero
/// pdf.
///
/// Determinism. The random numbers of f() and pdf() come from a PCG32 stream seeded by a hash of
/// (wo, wi) (different streams for f and for pdf, so that the MIS weight of a light sample is
/// independent of the f it multiplies, as in pbrt-v4); sample() seeds from (wo, uc, u). Each is
/// a pure function of its arguments.
///
/// Spectral behaviour: the walk's directions do not depend on wavelength (the interface takes
/// the hero wavelength's eta; see dielectric.h for dispersion), the base's and the medium's
/// spectra weight the walk.
#include "steradian/bsdf/bxdf_common.h"
#include "steradian/bsdf/conductor.h"
#include "steradian/bsdf/dielectric.h"
#include "steradian/bsdf/lambert.h"

namespace sr {

template <typename Bottom>
struct LayeredLobe {
    /// Smallest value pdf() returns for a direction it can scatter into (1/sr).
    static constexpr Float kPdfFloor = 1e-6f;

    DielectricLobe top;      ///< the interface; eta = n_coating / n_outside
    Bottom bottom;           ///< the base, seen from inside the coating (z > 0 side)
    SampledSpectrum albedo;  ///< single-scattering albedo of the slab; 0: absorbing only
    Float thickness = 0;     ///< slab optical thickness (sigma_t = 1), >= 0
    Float g = 0;             ///< Henyey-Greenstein asymmetry, in (-1, 1)
    uint16_t max_depth = 10;
    uint16_t n_samples = 1;

    /// Estimate of the BSDF value (1/sr, no cosine) for wo, wi on the same side; 0 for the
    /// other side and when every path is specular (those are only reachable through sample()).
    SampledSpectrum f(Vec3 wo, Vec3 wi, TransportMode mode) const;
    /// A random walk through the layers (see the file comment): the weight f |cos| / pdf_sa is
    /// the walk's throughput; pdf_sa is pdf(wo, wi) for non-specular results and the walk's
    /// discrete probability for specular ones. Empty when the walk is absorbed by a black base,
    /// fails, or exceeds max_depth.
    std::optional<BsdfSample> sample(Vec3 wo, Float uc, Point2 u, TransportMode mode) const;
    /// Estimate of the solid-angle density of sample() producing wi (non-specular part),
    /// floored at kPdfFloor; 0 on the other side and for specular-only configurations.
    Float pdf(Vec3 wo, Vec3 wi, TransportMode mode) const;
    uint8_t flags() const;
};

/// pbrt-v4's "coateddiffuse": a dielectric coating over a Lambertian base.
using CoatedDiffuseLobe = LayeredLobe<LambertLobe>;
/// pbrt-v4's "coatedconductor": a dielectric coating over a conductor whose eta and k are
/// relative to the coating.
using CoatedConductorLobe = LayeredLobe<ConductorLobe>;

extern template struct LayeredLobe<LambertLobe>;
extern template struct LayeredLobe<ConductorLobe>;

}  // namespace sr
