#pragma once
/// The interior of pbrt-v4's "subsurface" material as a homogeneous medium: its coefficients at
/// a point (the random walk of integrators/path/volpath.cpp evaluates them once, at the point
/// where the path enters), and the single-scattering albedo that gives a random walk a wanted
/// multiple-scattering reflectance (the "reflectance" + "mfp" form).
#include "steradian/material/material.h"

namespace sr {

/// The single-scattering albedo alpha of a semi-infinite, isotropically scattering medium
/// with an index-matched boundary whose diffuse reflectance (the fraction of uniformly
/// incident light that comes back out, every order of scattering) is A. The fit of
/// M. J.-Y. Chiang, P. Kutz, B. Burley, "Practical and Controllable Subsurface Scattering for
/// Production Path Tracing", ACM SIGGRAPH 2016 Talks:
///   alpha = 1 - (4.09712 + 4.20863 A - sqrt(9.59217 + 41.6808 A + 17.7126 A^2))^2,
/// which inverts van de Hulst's approximation for that medium (H. C. van de Hulst, "Multiple
/// Light Scattering", 1980), A = (1 - s)(1 - 0.139 s) / (1 + 1.17 s), s = sqrt(1 - alpha):
/// the fit reproduces it to 1e-4. Against a random walk of that geometry (4e5 walks per point,
/// our measurement; the talk states no error bound) the reflectance of the fitted alpha is
/// within 0.003 of A over A in [0.05, 0.99]. Monotone; A <= 0 gives 0 and A >= 1 gives 1 (the
/// formula itself gives 6e-6 at A = 0).
///
/// With a boundary of relative IOR eta != 1, the walk's light is reflected back in at the
/// boundary (diffuse internal reflectance r_i = diffuse_internal_reflectance(eta)), so the
/// interior must be brighter for the object to reflect A: taking the light that returns to
/// the boundary as diffuse, the interior's A_0 and the object's A are related by the adding
/// formula A = A_0 (1 - r_i) / (1 - r_i A_0), i.e. A_0 = A / (1 - r_i + r_i A), and
/// alpha = subsurface_albedo(A_0, 0). (The adding formula is the approximation here; the walk
/// itself is exact.)
Float subsurface_albedo(Float reflectance, Float internal_r = 0);

/// Absorption and scattering coefficients (per unit length of the scene) at the path's
/// wavelengths.
struct SubsurfaceCoefficients {
    SampledSpectrum sigma_a, sigma_s;
};

/// The coefficients of material m at hit h, as pbrt-v4's SubsurfaceMaterial::GetBSSRDF
/// evaluates its textures: scale * sigma_a and scale * sigma_s (clamped to >= 0), or, with a
/// reflectance A (clamped to [0, 1]) and a mean free path (times scale, as pbrt-v4 scales it),
/// sigma_t = 1 / mfp, sigma_s = alpha sigma_t, sigma_a = (1 - alpha) sigma_t per wavelength,
/// alpha = subsurface_albedo(A, m.internal_r). (pbrt-v4 inverts the reflectance of its photon-beam-diffusion
/// table instead; see docs/pbrt-support.md.) A mean free path <= 0 is read as 1e-30.
SubsurfaceCoefficients subsurface_coefficients(const SubsurfaceMaterial& m,
                                               const MaterialContext& ctx, const SurfaceHit& h,
                                               const SampledWavelengths& lambda);

}  // namespace sr
