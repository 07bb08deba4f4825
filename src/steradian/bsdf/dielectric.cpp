#include "steradian/bsdf/dielectric.h"

#include "steradian/bsdf/fresnel.h"

namespace sr {

namespace {

/// The microfacet normal that scatters wo into wi, oriented to the upper hemisphere.
struct HalfVector {
    Vec3 wm;
    Float etap;    ///< n_(wi side) / n_(wo side); 1 for reflection
    bool reflect;  ///< wo and wi on the same side
};

/// Generalised half vector of Walter et al. 2007: wo + wi for reflection (Eq. 13) and
/// -(n_o wo + n_i wi) for refraction (Eq. 16), here as wo + etap wi, normalised and flipped
/// to wm.z > 0. Empty for grazing directions and for configurations that need a back-facing
/// microfacet (wm seen from behind by wo or wi): a microfacet only scatters light arriving at
/// its front (the chi+ factors of Walter's masking term).
std::optional<HalfVector> half_vector(Vec3 wo, Vec3 wi, Float eta) {
    Float cos_o = wo.z, cos_i = wi.z;
    if (cos_o == 0 || cos_i == 0) return std::nullopt;
    bool reflect = cos_o * cos_i > 0;
    Float etap = reflect ? 1 : (cos_o > 0 ? eta : 1 / eta);
    Vec3 wm = wo + wi * etap;
    if (length_squared(wm) == 0) return std::nullopt;
    wm = face_forward(normalize(wm), Vec3(0, 0, 1));
    if (dot(wm, wi) * cos_i < 0 || dot(wm, wo) * cos_o < 0) return std::nullopt;
    return HalfVector{wm, etap, reflect};
}

/// wo reflected (reflect) or refracted by the microfacet wm; empty if the result does not
/// leave on the side that branch requires (or refraction is total internal reflection).
std::optional<Vec3> scatter_off(Vec3 wo, Vec3 wm, Float eta, bool reflect) {
    Vec3 wi;
    if (reflect) {
        wi = sr::reflect(wo, wm);
        if (!same_hemisphere(wo, wi)) return std::nullopt;
    } else if (!refract(wo, wm, eta, nullptr, &wi) || same_hemisphere(wo, wi) || wi.z == 0) {
        return std::nullopt;
    }
    return wi;
}

/// Jacobian |dwm / dwi| of the refraction half vector (Walter et al. 2007, Eq. 17, written
/// with etap = n_i / n_o): |wi . wm| / (wi . wm + wo . wm / etap)^2.
Float refraction_jacobian(Vec3 wo, Vec3 wi, Vec3 wm, Float etap) {
    return std::abs(dot(wi, wm)) / sqr(dot(wi, wm) + dot(wo, wm) / etap);
}

/// The refraction BTDF of Walter et al. 2007, Eq. 21, in the Importance-mode (adjoint) form
/// D (1 - F) G |wi.wm| |wo.wm| / (|cos_i| |cos_o| (wi.wm + wo.wm / etap)^2); Radiance mode
/// divides it by etap^2, which gives Walter's radiance form with n_o^2 in the numerator.
Float btdf(const TrowbridgeReitz& mf, Vec3 wo, Vec3 wi, Vec3 wm, Float etap, Float t,
           TransportMode mode) {
    Float denom = sqr(dot(wi, wm) + dot(wo, wm) / etap) * wi.z * wo.z;
    Float ft = mf.D(wm) * t * mf.G(wo, wi) * std::abs(dot(wi, wm) * dot(wo, wm) / denom);
    if (mode == TransportMode::Radiance) ft /= sqr(etap);
    return ft;
}

/// Fresnel transmittance of the refraction between wo and wi through h.wm, evaluated from the
/// direction in the optically rarer medium. T is the same from both sides (Stokes relations),
/// but from the denser side near the critical angle cos_t = sqrt(1 - eta^2 sin^2) cancels
/// catastrophically in float (percent-level errors within 0.01 of the critical cosine), which
/// would break the reciprocity f(wo, wi) / n_o^2 = f(wi, wo) / n_i^2 there.
Float transmittance(Float eta, Vec3 wo, Vec3 wi, const HalfVector& h) {
    Vec3 w_rare = h.etap > 1 ? wo : wi;  // etap = n_i / n_o > 1: wo's side is the rarer one
    return 1 - fr_dielectric(dot(w_rare, h.wm), eta);
}

/// BSDF value for a valid half vector h of (wo, wi).
Float f_at(const TrowbridgeReitz& mf, Float eta, Vec3 wo, Vec3 wi, const HalfVector& h,
           TransportMode mode) {
    if (h.reflect) {
        // Torrance-Sparrow reflection (Walter et al. 2007, Eq. 20).
        Float r = fr_dielectric(dot(wo, h.wm), eta);
        return mf.D(h.wm) * mf.G(wo, wi) * r / std::abs(4 * wi.z * wo.z);
    }
    return btdf(mf, wo, wi, h.wm, h.etap, transmittance(eta, wo, wi, h), mode);
}

/// Solid-angle density of wi given the branch, for a valid half vector h of (wo, wi): the
/// visible-normal pdf of h.wm times the Jacobian dwm/dwi (Walter et al. 2007: 1 / (4 |wo.wm|)
/// for reflection, Eq. 14; Eq. 17 for refraction).
Float branch_pdf_at(const TrowbridgeReitz& mf, Vec3 wo, Vec3 wi, const HalfVector& h) {
    Float pdf_wm = mf.pdf(wo, h.wm);
    if (h.reflect) return pdf_wm / (4 * std::abs(dot(wo, h.wm)));
    return pdf_wm * refraction_jacobian(wo, wi, h.wm, h.etap);
}

/// Probability R or T = 1 - R with which sample() takes h's branch at the microfacet h.wm.
Float branch_prob_at(Float eta, Vec3 wo, Vec3 wi, const HalfVector& h) {
    return h.reflect ? fr_dielectric(dot(wo, h.wm), eta) : transmittance(eta, wo, wi, h);
}

/// Solid-angle pdf of sample() producing wi, for a valid half vector h of (wo, wi): the
/// branch density times the probability of the branch.
Float pdf_at(const TrowbridgeReitz& mf, Float eta, Vec3 wo, Vec3 wi, const HalfVector& h) {
    return branch_pdf_at(mf, wo, wi, h) * branch_prob_at(eta, wo, wi, h);
}

}  // namespace

SampledSpectrum DielectricLobe::f(Vec3 wo, Vec3 wi, TransportMode mode) const {
    if (eta == 1 || mf.effectively_smooth()) return SampledSpectrum(0);
    std::optional<HalfVector> h = half_vector(wo, wi, eta);
    if (!h) return SampledSpectrum(0);
    return SampledSpectrum(f_at(mf, eta, wo, wi, *h, mode));
}

std::optional<BsdfSample> DielectricLobe::sample(Vec3 wo, Float uc, Point2 u,
                                                 TransportMode mode) const {
    if (wo.z == 0) return std::nullopt;
    if (eta == 1) {
        // Index-matched: the interface is invisible.
        return BsdfSample{SampledSpectrum(1 / std::abs(wo.z)), -wo, 1,
                          kLobeTransmission | kLobeSpecular, 1};
    }
    if (mf.effectively_smooth()) {
        Float r = fr_dielectric(wo.z, eta), t = 1 - r;
        if (uc < r) {
            Vec3 wi(-wo.x, -wo.y, wo.z);
            return BsdfSample{SampledSpectrum(r / std::abs(wi.z)), wi, r,
                              kLobeReflection | kLobeSpecular, 1};
        }
        Vec3 wi;
        Float etap = 1;
        if (!refract(wo, Vec3(0, 0, 1), eta, &etap, &wi) || wi.z == 0) return std::nullopt;
        Float ft = t / std::abs(wi.z);
        if (mode == TransportMode::Radiance) ft /= sqr(etap);
        return BsdfSample{SampledSpectrum(ft), wi, t, kLobeTransmission | kLobeSpecular, etap};
    }

    // Rough: a visible microfacet normal, then reflection or refraction off it with
    // probabilities R and T of that microfacet (as pbrt-v4's DielectricBxDF).
    Vec3 wm = mf.sample_wm(wo, u);
    std::optional<Vec3> scattered = scatter_off(wo, wm, eta, uc < fr_dielectric(dot(wo, wm), eta));
    if (!scattered) return std::nullopt;
    Vec3 wi = *scattered;
    // f and pdf of the direction actually returned, through the same code as f() and pdf():
    // near the critical angle the refracted wi is ill-conditioned in wm, and the half vector
    // recomputed from (wo, wi) is the one that pdf() will see when MIS asks for this wi.
    std::optional<HalfVector> h = half_vector(wo, wi, eta);
    if (!h) return std::nullopt;
    Float pdf = pdf_at(mf, eta, wo, wi, *h);
    if (pdf == 0) return std::nullopt;
    return BsdfSample{SampledSpectrum(f_at(mf, eta, wo, wi, *h, mode)), wi, pdf,
                      uint8_t((h->reflect ? kLobeReflection : kLobeTransmission) | kLobeGlossy),
                      h->etap};
}

Float DielectricLobe::pdf(Vec3 wo, Vec3 wi, TransportMode) const {
    if (eta == 1 || mf.effectively_smooth()) return 0;
    std::optional<HalfVector> h = half_vector(wo, wi, eta);
    if (!h) return 0;
    return pdf_at(mf, eta, wo, wi, *h);
}

std::optional<BsdfSample> DielectricLobe::sample_branch(Vec3 wo, Point2 u, TransportMode mode,
                                                        Branch branch, Float* branch_prob) const {
    bool want_reflect = branch == Branch::Reflection;
    if (wo.z == 0) return std::nullopt;
    if (eta == 1) {
        if (want_reflect) return std::nullopt;
        *branch_prob = 1;
        return BsdfSample{SampledSpectrum(1 / std::abs(wo.z)), -wo, 1,
                          kLobeTransmission | kLobeSpecular, 1};
    }
    if (mf.effectively_smooth()) {
        Float r = fr_dielectric(wo.z, eta);
        if (want_reflect) {
            if (r == 0) return std::nullopt;
            Vec3 wi(-wo.x, -wo.y, wo.z);
            *branch_prob = r;
            return BsdfSample{SampledSpectrum(r / std::abs(wi.z)), wi, 1,
                              kLobeReflection | kLobeSpecular, 1};
        }
        Vec3 wi;
        Float etap = 1;
        if (r >= 1 || !refract(wo, Vec3(0, 0, 1), eta, &etap, &wi) || wi.z == 0)
            return std::nullopt;
        Float ft = (1 - r) / std::abs(wi.z);
        if (mode == TransportMode::Radiance) ft /= sqr(etap);
        *branch_prob = 1 - r;
        return BsdfSample{SampledSpectrum(ft), wi, 1, kLobeTransmission | kLobeSpecular, etap};
    }

    std::optional<Vec3> scattered = scatter_off(wo, mf.sample_wm(wo, u), eta, want_reflect);
    if (!scattered) return std::nullopt;
    Vec3 wi = *scattered;
    // As in sample(): f and densities through the half vector of the returned direction.
    std::optional<HalfVector> h = half_vector(wo, wi, eta);
    if (!h || h->reflect != want_reflect) return std::nullopt;
    Float pdf = branch_pdf_at(mf, wo, wi, *h);
    if (pdf == 0) return std::nullopt;
    *branch_prob = branch_prob_at(eta, wo, wi, *h);
    return BsdfSample{SampledSpectrum(f_at(mf, eta, wo, wi, *h, mode)), wi, pdf,
                      uint8_t((want_reflect ? kLobeReflection : kLobeTransmission) | kLobeGlossy),
                      h->etap};
}

Float DielectricLobe::pdf_branch(Vec3 wo, Vec3 wi, Branch branch) const {
    if (eta == 1 || mf.effectively_smooth()) return 0;
    std::optional<HalfVector> h = half_vector(wo, wi, eta);
    if (!h || h->reflect != (branch == Branch::Reflection)) return 0;
    return branch_pdf_at(mf, wo, wi, *h);
}

}  // namespace sr
