#pragma once
/// pbrt-v4's "measured" material: the tabulated isotropic or anisotropic BRDFs of the RGL
/// material database, in the adaptive parameterisation of J. Dupuy and W. Jakob, "An Adaptive
/// Parameterization for Efficient Material Acquisition and Rendering" (ACM TOG 37(6), 2018),
/// read from their .bsdf tensor files (bsdf/tensor_file.h) and evaluated and sampled as
/// pbrt-v4's MeasuredBxDF does.
///
/// Angles map to the unit square by u = sqrt(2 theta / pi) (theta = pi u^2 / 2) and
/// v = phi / (2 pi) + 1/2; a direction's solid angle is dw = 2 pi^2 u sin(theta) du dv. With
/// wo the fixed direction (the file's theta_i, phi_i) and wm the half vector of wo and wi:
/// - "ndf" tabulates the microfacet distribution D(wm) over (u, v) of wm, "sigma" the projected
///   microfacet area sigma(wo) over (u, v) of wo;
/// - "vndf" tabulates, per (phi_i, theta_i), a density over (u, v) of wm (of isotropic
///   materials, v of phi_m - phi_o): sampling it maps a point u' of the unit square to wm;
/// - "spectra" tabulates, per (phi_i, theta_i, wavelength), a value fr over u' and
///   "luminance" a density over u' that sampling applies first;
/// - f(wo, wi) = max(0, fr(u')) D(wm) / (4 sigma(wo) cos theta_i), u' the point the VNDF
///   warp maps to wm;
/// - sample(): u -> u' by the luminance table, u' -> wm by the VNDF table, wi = wm's
///   reflection of wo; pdf = p_lum(u') p_vndf(wm) / (4 (wo . wm) 2 pi^2 u_m sin theta_m).
/// Tables are interpolated bilinearly over the square and linearly between the tabulated
/// phi_i, theta_i (radians) and wavelengths (nm; a wavelength outside the file's range takes
/// the nearest tabulated one). Both sides reflect (a wo below the surface mirrors the
/// configuration). Negative values of the sampling tables are taken as 0; the tables'
/// integrals need not be 1 (each slice is normalised, as pbrt-v4 does).
#include <memory>
#include <string>
#include <string_view>
#include <vector>

#include "steradian/bsdf/bxdf_common.h"
#include "steradian/sampling/piecewise_linear_2d.h"

namespace sr {

struct MeasuredBrdf {
    std::string name;  ///< the file, for messages
    std::vector<float> wavelengths;
    bool isotropic = true;
    PiecewiseLinear2D ndf, sigma;  ///< interpolants over (u, v)
    PiecewiseLinear2D vndf;        ///< density over (u, v) of wm, params (phi_i, theta_i)
    PiecewiseLinear2D luminance;   ///< density over u', params (phi_i, theta_i)
    PiecewiseLinear2D spectra;     ///< interpolant over u', params (phi_i, theta_i, lambda)
};

/// The BRDF of a .bsdf file's contents. Throws sr::Error naming `name` and the field when the
/// file is not a tensor file, lacks a field pbrt-v4 needs (theta_i, phi_i, ndf, sigma, vndf,
/// luminance, spectra, wavelengths, jacobian), has a field of the wrong type or shape, holds
/// a value that is not finite, or describes an anisotropic table over less than the full
/// circle of phi_i (pbrt-v4 refuses those too).
MeasuredBrdf parse_measured_brdf(std::string_view bytes, std::string_view name);
/// parse_measured_brdf() of the file at `path` (read whole, up to kMaxSceneFileBytes).
MeasuredBrdf read_measured_brdf(const std::string& path);

/// The measured BRDF at one set of wavelengths; `brdf` outlives the lobe (the scene owns it).
struct MeasuredLobe {
    static constexpr bool kIgnoresUc = true;
    const MeasuredBrdf* brdf = nullptr;
    SampledWavelengths lambda;

    SampledSpectrum f(Vec3 wo, Vec3 wi, TransportMode mode) const;
    std::optional<BsdfSample> sample(Vec3 wo, Float uc, Point2 u, TransportMode mode) const;
    Float pdf(Vec3 wo, Vec3 wi, TransportMode mode) const;
    uint8_t flags() const { return kLobeReflection | kLobeGlossy; }
};

/// The map of the parameterisation: theta in [0, pi/2] <-> u in [0, 1], phi in [-pi, pi]
/// <-> v in [0, 1].
inline Float measured_theta_to_u(Float theta) { return std::sqrt(theta * (2 / kPi)); }
inline Float measured_phi_to_v(Float phi) { return phi * (1 / (2 * kPi)) + Float(0.5); }
inline Float measured_u_to_theta(Float u) { return u * u * (kPi / 2); }
inline Float measured_v_to_phi(Float v) { return (2 * v - 1) * kPi; }

}  // namespace sr
