#pragma once
/// Mirror reflection, Snell refraction and the Fresnel equations for dielectric and conducting
/// interfaces (Born & Wolf, "Principles of Optics", 7th ed., Sec. 1.5.2 and 14.2; Pharr, Jakob,
/// Humphreys, "Physically Based Rendering", 4th ed., Sec. 9.3 and 9.4).
///
/// Convention for the relative index of refraction: eta = n_t / n_i, the index on the far side
/// of the interface (the side the normal points away from, z < 0 in the shading frame) over
/// the index on the near side (the side the normal points to). A negative cosine means the
/// incident direction is on the far side; the functions then swap the roles (eta -> 1/eta).
#include <complex>

#include "steradian/bsdf/bxdf_common.h"

namespace sr {

/// Mirror direction of w about the unit normal n: 2 (w . n) n - w. Both w and the result
/// point away from the surface.
inline Vec3 reflect(Vec3 w, Vec3 n) { return n * (2 * dot(w, n)) - w; }

/// Refraction of the unit direction wi (pointing away from the surface) through an interface
/// with unit normal n and relative IOR eta = n_t / n_i as above. If wi is on the side n points
/// away from (dot(wi, n) < 0) the interface is seen from below: eta is inverted and n flipped.
/// On success stores the transmitted unit direction (pointing away on the other side) in *wt
/// and the relative IOR actually crossed (n_t / n_i for this wi) in *etap (may be null);
/// returns false under total internal reflection.
/// Snell's law in vector form: wt = -wi / eta + (cos_i / eta - cos_t) n (PBR 4th ed. Eq. 9.3).
inline bool refract(Vec3 wi, Normal3 n, Float eta, Float* etap, Vec3* wt) {
    Float cos_i = dot(n, wi);
    if (cos_i < 0) {
        eta = 1 / eta;
        cos_i = -cos_i;
        n = -n;
    }
    Float sin2_i = std::max(Float(0), 1 - sqr(cos_i));
    Float sin2_t = sin2_i / sqr(eta);
    if (sin2_t >= 1) return false;
    Float cos_t = safe_sqrt(1 - sin2_t);
    *wt = -wi / eta + n * (cos_i / eta - cos_t);
    if (etap) *etap = eta;
    return true;
}

/// Power reflectances for the two linear polarisations: rs for s (TE, E perpendicular to the
/// plane of incidence), rp for p (TM, E in the plane of incidence).
struct FresnelSp {
    Float rs = 1;
    Float rp = 1;
};

/// Fresnel power reflectances |r_s|^2 and |r_p|^2 of a lossless dielectric interface (Born &
/// Wolf Eq. 1.5.20/21): r_s = (cos_i - eta cos_t) / (cos_i + eta cos_t),
/// r_p = (eta cos_i - cos_t) / (eta cos_i + cos_t). cos_i < 0 means incidence from the far
/// side (eta inverted); total internal reflection gives {1, 1}. rp vanishes at Brewster's
/// angle tan(theta_i) = eta.
inline FresnelSp fr_dielectric_sp(Float cos_i, Float eta) {
    cos_i = clamp(cos_i, Float(-1), Float(1));
    if (cos_i < 0) {
        eta = 1 / eta;
        cos_i = -cos_i;
    }
    Float sin2_t = (1 - sqr(cos_i)) / sqr(eta);
    if (sin2_t >= 1) return {1, 1};
    Float cos_t = safe_sqrt(1 - sin2_t);
    Float r_s = (cos_i - eta * cos_t) / (cos_i + eta * cos_t);
    Float r_p = (eta * cos_i - cos_t) / (eta * cos_i + cos_t);
    return {sqr(r_s), sqr(r_p)};
}

/// Unpolarised Fresnel reflectance of a dielectric interface, (|r_s|^2 + |r_p|^2) / 2, for the
/// cosine of the incident direction with the normal (negative: from the far side) and
/// eta = n_t / n_i. 1 under total internal reflection; ((eta - 1) / (eta + 1))^2 at normal
/// incidence. The transmittance is 1 - fr_dielectric.
inline Float fr_dielectric(Float cos_i, Float eta) {
    FresnelSp r = fr_dielectric_sp(cos_i, eta);
    return Float(0.5) * (r.rs + r.rp);
}

/// fr_dielectric per wavelength (for a spectrally varying eta).
inline SampledSpectrum fr_dielectric(Float cos_i, const SampledSpectrum& eta) {
    SampledSpectrum r;
    for (int i = 0; i < kSpectrumSamples; ++i) r[i] = fr_dielectric(cos_i, eta[i]);
    return r;
}

/// Unpolarised Fresnel reflectance of an absorbing medium with complex relative IOR
/// eta = n + i k (Born & Wolf Sec. 14.2: the dielectric formulas continued to complex eta, with
/// eta cos_t = w = sqrt(eta^2 - sin^2_i) on the principal branch, Re w >= 0: the wave decays
/// into the conductor). Incidence from the dielectric side only: cos_i is clamped to [0, 1].
/// At normal incidence this is ((n - 1)^2 + k^2) / ((n + 1)^2 + k^2); with k = 0 it equals
/// fr_dielectric. n, k >= 0.
///
/// In real arithmetic (no complex division or square root): with c = cos_i, s2 = sin^2_i and
/// w = a + i b,
///   |r_s|^2 = |c - w|^2 / |c + w|^2 = (|w|^2 + c^2 - 2 a c) / (|w|^2 + c^2 + 2 a c),
///   r_p / r_s = -(c w - s2) / (c w + s2) (substituting eta^2 = w^2 + s2), so
///   |r_p|^2 = |r_s|^2 (c^2 |w|^2 + s2^2 - 2 a c s2) / (c^2 |w|^2 + s2^2 + 2 a c s2),
/// where |w|^2 = |eta^2 - s2| and a = Re sqrt(eta^2 - s2), taken from b = Im w when
/// Re(eta^2 - s2) < 0 (metals) to avoid cancellation: a b = n k.
inline Float fr_complex(Float cos_i, Float eta, Float k) {
    Float c = clamp(cos_i, Float(0), Float(1));
    Float c2 = c * c, s2 = 1 - c2;
    Float re = sqr(eta) - sqr(k) - s2;  // u = eta^2 - s2 = re + i 2 n k
    Float nk = eta * k;
    Float norm_w2 = std::sqrt(sqr(re) + 4 * sqr(nk));  // |u| = |w|^2
    Float a;
    if (re >= 0) {
        a = std::sqrt(Float(0.5) * (norm_w2 + re));
    } else {
        Float b = std::sqrt(Float(0.5) * (norm_w2 - re));
        a = b > 0 ? nk / b : 0;
    }
    Float t1 = norm_w2 + c2, t2 = 2 * a * c;
    if (t1 + t2 == 0) return 1;  // |w| = c = 0: grazing onto an index-matched medium
    Float rs = (t1 - t2) / (t1 + t2);
    Float t3 = c2 * norm_w2 + sqr(s2), t4 = t2 * s2;
    Float rp = rs * (t3 - t4) / (t3 + t4);
    return Float(0.5) * (rs + rp);
}

/// fr_complex for a complex relative IOR eta = n + i k.
inline Float fr_complex(Float cos_i, std::complex<Float> eta) {
    return fr_complex(cos_i, eta.real(), eta.imag());
}

/// fr_complex per wavelength: eta and k sampled at the path's wavelengths.
inline SampledSpectrum fr_complex(Float cos_i, const SampledSpectrum& eta,
                                  const SampledSpectrum& k) {
    SampledSpectrum r;
    for (int i = 0; i < kSpectrumSamples; ++i) r[i] = fr_complex(cos_i, eta[i], k[i]);
    return r;
}

}  // namespace sr
