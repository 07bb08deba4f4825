#include "steradian/bsdf/hair.h"

#include "steradian/bsdf/fresnel.h"

namespace sr {

namespace {

/// The modified Bessel function of the first kind I0(x), by its power series
/// sum (x^2 / 4)^k / (k!)^2 (enough terms for the arguments below the asymptotic switch).
Float bessel_i0(Float x) {
    const Float q = x * x / 4;
    Float term = 1, sum = 1;
    for (int k = 1; k < 16; ++k) {
        term *= q / Float(k * k);
        sum += term;
    }
    return sum;
}

/// log I0(x); from x = 8 on by the asymptotic expansion I0(x) ~ e^x / sqrt(2 pi x) (1 +
/// 1 / 8x + 9 / 128x^2 + 225 / 3072x^3), whose next term is below 3e-5 there (Abramowitz and
/// Stegun 9.7.1). pbrt-v4's LogI0 keeps half the 1 / 8x term from x = 12 on, which makes
/// the lobes of small variance lose up to 0.5 % of their mass near their peak.
Float log_bessel_i0(Float x) {
    if (x >= 8) {
        const Float r = 1 / x;
        return x - Float(0.5) * std::log(2 * kPi * x) +
               std::log1p(r * (Float(1) / 8 + r * (Float(9) / 128 + r * (Float(225) / 3072))));
    }
    return std::log(bessel_i0(x));
}

/// d'Eon et al. 2011's longitudinal scattering function of variance v, normalised so that
/// its integral against cos(theta_i) d theta_i over [-pi/2, pi/2] is 1.
Float longitudinal(Float cos_i, Float cos_o, Float sin_i, Float sin_o, Float v) {
    const Float a = cos_i * cos_o / v, b = sin_i * sin_o / v;
    if (v <= Float(0.1))  // in logarithms: sinh(1 / v) and I0(a) overflow
        return std::exp(log_bessel_i0(a) - b - 1 / v + std::log(1 / v));
    return std::exp(-b) * bessel_i0(a) / (2 * v * std::sinh(1 / v));
}

Float logistic(Float x, Float s) {
    x = std::abs(x);
    const Float e = std::exp(-x / s);
    return e / (s * sqr(1 + e));
}

Float logistic_cdf(Float x, Float s) { return 1 / (1 + std::exp(-x / s)); }

/// The logistic density of scale s restricted to [-pi, pi] and renormalised.
Float trimmed_logistic(Float x, Float s) {
    return logistic(x, s) / (logistic_cdf(kPi, s) - logistic_cdf(-kPi, s));
}

/// Inverts the trimmed logistic's distribution function at u.
Float sample_trimmed_logistic(Float u, Float s) {
    const Float lo = logistic_cdf(-kPi, s), k = logistic_cdf(kPi, s) - lo;
    const Float x = -s * std::log(1 / (u * k + lo) - 1);
    return clamp(x, -kPi, kPi);
}

/// phi - phi_c wrapped to [-pi, pi].
Float wrap_angle(Float phi) {
    phi = std::remainder(phi, 2 * kPi);
    return clamp(phi, -kPi, kPi);
}

/// The azimuth of lobe p's centre (Chiang et al. 2016, eq. 3 with their near-field gamma).
Float lobe_azimuth(int p, Float gamma_o, Float gamma_t) {
    return 2 * Float(p) * gamma_t - 2 * gamma_o + Float(p) * kPi;
}

}  // namespace

HairLobe::HairLobe(Float h, Float eta, const SampledSpectrum& sigma_a, Float beta_m, Float beta_n,
                   Float alpha)
    : m_h(clamp(h, Float(-1), Float(1))),
      m_eta(eta),
      m_gamma_o(safe_asin(m_h)),
      m_sigma_a(sigma_a) {
    // Chiang et al. 2016, eq. 7 and 8: roughness to variance and to logistic scale.
    m_v[0] = sqr(Float(0.726) * beta_m + Float(0.812) * sqr(beta_m) +
                 Float(3.7) * std::pow(beta_m, Float(20)));
    m_v[1] = Float(0.25) * m_v[0];
    m_v[2] = 4 * m_v[0];
    m_v[3] = m_v[2];
    m_s = Float(0.626657069) *  // sqrt(pi / 8)
          (Float(0.265) * beta_n + Float(1.194) * sqr(beta_n) +
           Float(5.372) * std::pow(beta_n, Float(22)));
    // sin and cos of 2^k alpha by the double-angle formulas.
    m_sin_2k_alpha[0] = std::sin(radians(alpha));
    m_cos_2k_alpha[0] = safe_sqrt(1 - sqr(m_sin_2k_alpha[0]));
    for (int k = 1; k < kPMax; ++k) {
        m_sin_2k_alpha[k] = 2 * m_cos_2k_alpha[k - 1] * m_sin_2k_alpha[k - 1];
        m_cos_2k_alpha[k] = sqr(m_cos_2k_alpha[k - 1]) - sqr(m_sin_2k_alpha[k - 1]);
    }
}

HairLobe::OutTerms HairLobe::out_terms(Vec3 wo) const {
    OutTerms o;
    o.sin_theta_o = clamp(wo.x, Float(-1), Float(1));
    o.cos_theta_o = safe_sqrt(1 - sqr(o.sin_theta_o));
    o.phi_o = std::atan2(wo.z, wo.y);
    // The refracted ray: its longitudinal angle, and its azimuthal offset by Bravais's
    // effective index eta' = sqrt(eta^2 - sin^2 theta_o) / cos theta_o.
    const Float sin_theta_t = o.sin_theta_o / m_eta;
    const Float cos_theta_t = safe_sqrt(1 - sqr(sin_theta_t));
    const Float eta_p = safe_sqrt(sqr(m_eta) - sqr(o.sin_theta_o)) / o.cos_theta_o;
    const Float sin_gamma_t = clamp(m_h / eta_p, Float(-1), Float(1));
    const Float cos_gamma_t = safe_sqrt(1 - sqr(sin_gamma_t));
    o.gamma_t = std::asin(sin_gamma_t);
    // Transmittance of one chord through the fibre (length 2 cos gamma_t / cos theta_t
    // diameters).
    SampledSpectrum t;
    for (int i = 0; i < kSpectrumSamples; ++i)
        t[i] = std::exp(-m_sigma_a[i] * (2 * cos_gamma_t / cos_theta_t));
    // Attenuations: Fresnel at the entry point, then a geometric series for p >= kPMax.
    const Float fr = fr_dielectric(o.cos_theta_o * safe_sqrt(1 - sqr(m_h)), m_eta);
    o.ap[0] = SampledSpectrum(fr);
    o.ap[1] = t * sqr(1 - fr);
    for (int p = 2; p < kPMax; ++p) o.ap[p] = o.ap[p - 1] * t * fr;
    for (int i = 0; i < kSpectrumSamples; ++i) {
        const Float tf = t[i] * fr;
        o.ap[kPMax][i] = tf < 1 ? o.ap[kPMax - 1][i] * tf / (1 - tf) : 0;
    }
    // theta_o tilted by the cuticle scales: R by -2 alpha, TT by alpha, TRT by 4 alpha.
    const Float st = o.sin_theta_o, ct = o.cos_theta_o;
    o.sin_tilt[0] = st * m_cos_2k_alpha[1] - ct * m_sin_2k_alpha[1];
    o.cos_tilt[0] = ct * m_cos_2k_alpha[1] + st * m_sin_2k_alpha[1];
    o.sin_tilt[1] = st * m_cos_2k_alpha[0] + ct * m_sin_2k_alpha[0];
    o.cos_tilt[1] = ct * m_cos_2k_alpha[0] - st * m_sin_2k_alpha[0];
    o.sin_tilt[2] = st * m_cos_2k_alpha[2] + ct * m_sin_2k_alpha[2];
    o.cos_tilt[2] = ct * m_cos_2k_alpha[2] - st * m_sin_2k_alpha[2];
    for (Float& c : o.cos_tilt) c = std::abs(c);  // a tilt past the pole
    return o;
}

std::array<Float, HairLobe::kPMax + 1> HairLobe::lobe_pdf(const OutTerms& o) {
    std::array<Float, kPMax + 1> pdf;
    Float sum = 0;
    for (int p = 0; p <= kPMax; ++p) sum += pdf[p] = o.ap[p].average();
    for (Float& x : pdf) x = sum > 0 ? x / sum : Float(1) / (kPMax + 1);
    return pdf;
}

template <typename W>
auto HairLobe::lobe_sum(const OutTerms& o, Vec3 wi, const W& weights) const {
    const Float sin_i = clamp(wi.x, Float(-1), Float(1)), cos_i = safe_sqrt(1 - sqr(sin_i));
    const Float phi = std::atan2(wi.z, wi.y) - o.phi_o;
    auto sum = weights[0] * Float(0);
    for (int p = 0; p < kPMax; ++p) {
        const Float mp = longitudinal(cos_i, o.cos_tilt[p], sin_i, o.sin_tilt[p], m_v[p]);
        const Float np =
            trimmed_logistic(wrap_angle(phi - lobe_azimuth(p, m_gamma_o, o.gamma_t)), m_s);
        sum += weights[p] * (mp * np);
    }
    const Float mp =
        longitudinal(cos_i, o.cos_theta_o, sin_i, o.sin_theta_o, m_v[kPMax]) * kInv2Pi;
    sum += weights[kPMax] * mp;
    return sum;
}

SampledSpectrum HairLobe::f(Vec3 wo, Vec3 wi, TransportMode) const {
    const OutTerms o = out_terms(wo);
    SampledSpectrum f = lobe_sum(o, wi, o.ap);
    // The model gives f |cos theta_z| (its lobes integrate against the longitudinal measure);
    // the BSDF is that over |cos| of wi with the shading normal.
    const Float c = std::abs(wi.z);
    return c > 0 ? f / c : SampledSpectrum(0);
}

Float HairLobe::pdf(Vec3 wo, Vec3 wi, TransportMode) const {
    const OutTerms o = out_terms(wo);
    return lobe_sum(o, wi, lobe_pdf(o));
}

std::optional<BsdfSample> HairLobe::sample(Vec3 wo, Float uc, Point2 u, TransportMode mode) const {
    const OutTerms o = out_terms(wo);
    const std::array<Float, kPMax + 1> lp = lobe_pdf(o);
    // Choose the lobe with uc, and reuse what is left of uc for the azimuth.
    int p = 0;
    Float acc = 0;
    for (; p < kPMax; ++p) {
        if (uc < acc + lp[p]) break;
        acc += lp[p];
    }
    uc = lp[p] > 0 ? std::min((uc - acc) / lp[p], kOneMinusEpsilon) : Float(0.5);
    // theta_i from the longitudinal lobe (d'Eon et al. 2011, sampled around -theta_o').
    const Float sin_o = p < kPMax ? o.sin_tilt[p] : o.sin_theta_o;
    const Float cos_o = p < kPMax ? o.cos_tilt[p] : o.cos_theta_o;
    const Float v = m_v[p];
    const Float cos_t =
        1 + v * std::log(std::max(u[0], Float(1e-5)) + (1 - u[0]) * std::exp(-2 / v));
    const Float sin_t = safe_sqrt(1 - sqr(cos_t));
    const Float sin_i = clamp(-cos_t * sin_o + sin_t * std::cos(2 * kPi * u[1]) * cos_o,
                              Float(-1), Float(1));
    const Float cos_i = safe_sqrt(1 - sqr(sin_i));
    // phi_i from the azimuthal lobe.
    const Float dphi = p < kPMax ? lobe_azimuth(p, m_gamma_o, o.gamma_t) +
                                       sample_trimmed_logistic(uc, m_s)
                                 : 2 * kPi * uc;
    const Float phi_i = o.phi_o + dphi;
    const Vec3 wi(sin_i, cos_i * std::cos(phi_i), cos_i * std::sin(phi_i));
    BsdfSample s;
    s.wi = wi;
    s.f = f(wo, wi, mode);
    s.pdf_sa = lobe_sum(o, wi, lp);
    s.flags = uint8_t((wi.z * wo.z > 0 ? kLobeReflection : kLobeTransmission) | kLobeGlossy);
    if (!(s.pdf_sa > 0) || wi.z == 0) return std::nullopt;
    return s;
}

std::array<Float, 3> HairLobe::sigma_a_from_concentration(Float ce, Float cp) {
    // pbrt-v4 (HairBxDF::SigmaAFromConcentration): the absorption of eumelanin and of
    // pheomelanin per unit concentration, linear sRGB.
    constexpr std::array<Float, 3> eu{0.419f, 0.697f, 1.37f}, pheo{0.187f, 0.4f, 1.05f};
    return {ce * eu[0] + cp * pheo[0], ce * eu[1] + cp * pheo[1], ce * eu[2] + cp * pheo[2]};
}

SampledSpectrum HairLobe::sigma_a_from_reflectance(const SampledSpectrum& c, Float beta_n) {
    // Chiang et al. 2016, eq. 9: sigma_a = (ln c / (5.969 - 0.215 b + 2.532 b^2 - 10.73 b^3 +
    // 5.574 b^4 + 0.245 b^5))^2.
    const Float b = beta_n;
    const Float d = 5.969f - 0.215f * b + 2.532f * b * b - 10.73f * b * b * b +
                    5.574f * b * b * b * b + 0.245f * b * b * b * b * b;
    SampledSpectrum s;
    for (int i = 0; i < kSpectrumSamples; ++i) s[i] = sqr(std::log(c[i]) / d);
    return s;
}

}  // namespace sr
