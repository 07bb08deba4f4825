#pragma once
/// pbrt-v4's "hair" scattering model: Chiang, Bitterli, Tappan and Burley 2016, "A Practical
/// and Controllable Hair and Fur Model for Production Path Tracing" (the near-field
/// azimuthal model with a trimmed-logistic Np and the attenuations Ap of a smooth dielectric
/// cylinder), with d'Eon, Francois, Hill, Letteri and Aubry 2011, "An Energy-Conserving Hair
/// Reflectance Model" for the longitudinal lobes Mp; the cuticle-scale tilt alpha shifts the
/// lobes R, TT and TRT by -2 alpha, alpha and 4 alpha (Marschner et al. 2003).
///
/// The frame is the hair's: x along the fibre (the curve's dpdu), z the shading normal, so a
/// direction is w = (sin theta, cos theta cos phi, cos theta sin phi). h in [-1, 1] is where
/// the ray met the fibre's width (h = sin gamma_o); the hair material gives h = 2 v - 1.
/// The lobe scatters into the whole sphere (reflection and transmission). It conserves energy:
/// with sigma_a = 0 the integral of f |cos theta_z| over the sphere is 1 for every wo, h and
/// roughness (tests/stat/hair_test.cpp). f is not reciprocal in general (Ap depends on wo
/// only); with alpha = 0 it is where |theta_i| = |theta_o|.
#include <array>

#include "steradian/bsdf/bxdf_common.h"

namespace sr {

struct HairLobe {
    static constexpr int kPMax = 3;  ///< lobes R, TT, TRT, and the sum of all further ones

    /// h in [-1, 1]; eta the fibre's IOR; sigma_a its absorption coefficient per unit
    /// diameter (>= 0); beta_m and beta_n the longitudinal and azimuthal roughness in
    /// [0, 1]; alpha the scale tilt in degrees.
    HairLobe(Float h, Float eta, const SampledSpectrum& sigma_a, Float beta_m, Float beta_n,
             Float alpha);

    SampledSpectrum f(Vec3 wo, Vec3 wi, TransportMode mode) const;
    std::optional<BsdfSample> sample(Vec3 wo, Float uc, Point2 u, TransportMode mode) const;
    Float pdf(Vec3 wo, Vec3 wi, TransportMode mode) const;
    uint8_t flags() const { return kLobeReflection | kLobeTransmission | kLobeGlossy; }

    /// pbrt-v4's sigma_a of a fibre with eumelanin and pheomelanin concentrations ce and cp,
    /// as linear sRGB (an unbounded RGB to be uplifted to a spectrum).
    static std::array<Float, 3> sigma_a_from_concentration(Float ce, Float cp);
    /// Chiang et al. 2016, eq. 9: the sigma_a that gives a multiple-scattering colour c
    /// (per wavelength, in (0, 1]) at azimuthal roughness beta_n.
    static SampledSpectrum sigma_a_from_reflectance(const SampledSpectrum& c, Float beta_n);

  private:
    /// The per-direction terms of wo that f, sample and pdf share.
    struct OutTerms {
        Float sin_theta_o, cos_theta_o, phi_o, gamma_t;
        std::array<Float, kPMax> sin_tilt, cos_tilt;  ///< theta_o shifted by lobe p's tilt
        std::array<SampledSpectrum, kPMax + 1> ap;
    };
    OutTerms out_terms(Vec3 wo) const;
    /// The probability of choosing lobe p: its Ap averaged over the wavelengths, normalised.
    static std::array<Float, kPMax + 1> lobe_pdf(const OutTerms& o);
    /// sum over p of Mp(theta_i) Np(phi) weights[p] (Np of the last term is 1 / 2 pi).
    template <typename W>
    auto lobe_sum(const OutTerms& o, Vec3 wi, const W& weights) const;

    Float m_h, m_eta, m_gamma_o;
    SampledSpectrum m_sigma_a;
    std::array<Float, kPMax + 1> m_v;  ///< variance of each longitudinal lobe
    Float m_s;                         ///< logistic scale of the azimuthal lobes
    std::array<Float, kPMax> m_sin_2k_alpha, m_cos_2k_alpha;
};

}  // namespace sr
