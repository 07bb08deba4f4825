#pragma once
/// Spectral samples carried along a path: N = 4 wavelengths (a hero wavelength plus
/// equally spaced rotations), importance-sampled over the visible range, and the values of
/// a spectral quantity at those wavelengths.
#include <array>
#include <cmath>
#include <cstdint>
#if defined(__SSE4_1__)
#include <smmintrin.h>
#endif

#include "steradian/core/math.h"

namespace sr {

inline constexpr int kSpectrumSamples = 4;
inline constexpr Float kLambdaMin = 360;  ///< nm, lower end of the tabulated range
inline constexpr Float kLambdaMax = 830;  ///< nm, upper end of the tabulated range

/// Four floats as one SSE value (a GCC/Clang vector type: element access v[i], element-wise
/// arithmetic). A struct whose only member is one of these is passed and returned in a single
/// xmm register (SysV x86-64 ABI class SSE+SSEUP). A std::array<float, 4> member is passed in
/// two (one per eight bytes), and the caller then re-packs the halves through the stack into
/// one 16-byte value, which stalls store-to-load forwarding on every non-inlined return.
using Float4 = Float __attribute__((vector_size(4 * sizeof(Float))));

/// Values of a spectral quantity at the path's wavelengths.
struct SampledSpectrum {
    static_assert(kSpectrumSamples == 4 && sizeof(Float) == 4, "v holds four floats");
    Float4 v{};

    SampledSpectrum() = default;
    explicit SampledSpectrum(Float c) : v{c, c, c, c} {}
    explicit SampledSpectrum(Float4 values) : v(values) {}
    /// One value per wavelength, in the order of SampledWavelengths::lambda.
    explicit SampledSpectrum(const std::array<Float, kSpectrumSamples>& values)
        : v{values[0], values[1], values[2], values[3]} {}
    Float operator[](int i) const { return v[i]; }
#if defined(__clang__)
    // Clang cannot bind a reference to a vector element; its alias analysis treats vector
    // types as aliasing everything, so the element is reached through a Float pointer.
    Float& operator[](int i) { return reinterpret_cast<Float*>(&v)[i]; }
#else
    Float& operator[](int i) { return v[i]; }
#endif

#define SR_SS_OP(op)                                                                   \
    SampledSpectrum operator op(const SampledSpectrum& o) const {                      \
        return SampledSpectrum(v op o.v);                                              \
    }                                                                                  \
    SampledSpectrum& operator op##=(const SampledSpectrum& o) {                        \
        v = v op o.v;                                                                  \
        return *this;                                                                  \
    }                                                                                  \
    SampledSpectrum operator op(Float s) const { return SampledSpectrum(v op s); }     \
    SampledSpectrum& operator op##=(Float s) {                                         \
        v = v op s;                                                                    \
        return *this;                                                                  \
    }
    SR_SS_OP(+)
    SR_SS_OP(-)
    SR_SS_OP(*)
#undef SR_SS_OP
    SampledSpectrum operator/(Float s) const { return *this * (1 / s); }
    SampledSpectrum& operator/=(Float s) { return *this *= (1 / s); }
    /// Component-wise division; 0 where the divisor is 0.
    SampledSpectrum safe_div(const SampledSpectrum& o) const {
        SampledSpectrum r;
        for (int i = 0; i < kSpectrumSamples; ++i) r.v[i] = o.v[i] != 0 ? v[i] / o.v[i] : 0;
        return r;
    }
    bool is_zero() const {
        // One comparison of the four values (no early exit whose branch depends on the data).
        auto nonzero = v != Float4{};
        return (nonzero[0] | nonzero[1] | nonzero[2] | nonzero[3]) == 0;
    }
    explicit operator bool() const { return !is_zero(); }
    Float max_value() const { return std::max(std::max(v[0], v[1]), std::max(v[2], v[3])); }
    Float min_value() const { return std::min(std::min(v[0], v[1]), std::min(v[2], v[3])); }
    Float average() const { return ((v[0] + v[1]) + (v[2] + v[3])) / kSpectrumSamples; }
    bool has_nonfinite() const {
        for (int i = 0; i < kSpectrumSamples; ++i)
            if (!std::isfinite(v[i])) return true;
        return false;
    }
};
inline SampledSpectrum operator*(Float s, const SampledSpectrum& a) { return a * s; }
inline SampledSpectrum exp(const SampledSpectrum& a) {
    SampledSpectrum r;
    for (int i = 0; i < kSpectrumSamples; ++i) r.v[i] = std::exp(a.v[i]);
    return r;
}

/// The visible-wavelength importance distribution, p(l) proportional to
/// 1/cosh^2(kVisibleRate (l - kVisiblePeak)) on [360, 830] nm (the sampling density pbrt-v4
/// uses; Radziszewski et al. 2009 proposed this family). Its inverse CDF is
/// l = kVisiblePeak - atanh(y) / kVisibleRate with y = kVisibleY0 - kVisibleYSlope u.
inline constexpr Float kVisiblePeak = 538;               ///< nm
inline constexpr Float kVisibleRate = 0.0072f;           ///< 1/nm
inline constexpr Float kVisibleInvRate = 138.888889f;    ///< 1 / kVisibleRate, nm
inline constexpr Float kVisiblePdfScale = 0.0039398042f; ///< normalisation over [360, 830], 1/nm
inline constexpr Float kVisibleY0 = 0.85691062f;         ///< tanh(kVisibleRate (538 - 360))
inline constexpr Float kVisibleYSlope = 1.82750197f;     ///< kVisibleY0 + tanh(kVisibleRate (830 - 538))

/// pdf of the visible-wavelength importance distribution; zero outside [360, 830] nm.
inline Float visible_wavelengths_pdf(Float lambda) {
    if (lambda < kLambdaMin || lambda > kLambdaMax) return 0;
    return kVisiblePdfScale / sqr(std::cosh(kVisibleRate * (lambda - kVisiblePeak)));
}
/// Inverse-CDF sample of visible_wavelengths_pdf for u in [0, 1).
inline Float sample_visible_wavelengths(Float u) {
    return kVisiblePeak - kVisibleInvRate * std::atanh(kVisibleY0 - kVisibleYSlope * u);
}
/// Both at once, cheaply: since cosh^2(atanh y) = 1 / (1 - y^2) the pdf is
/// kVisiblePdfScale (1 - y^2): one logarithm, no cosh.
inline Float sample_visible_wavelengths(Float u, Float& pdf) {
    Float y = kVisibleY0 - kVisibleYSlope * u;
    pdf = kVisiblePdfScale * (1 - y * y);
    return kVisiblePeak - kVisibleInvRate * Float(0.5) * std::log((1 + y) / (1 - y));
}

#if defined(__SSE4_1__)
/// Natural logarithm of four positive, finite, normal floats: x = 2^e m with m in
/// [sqrt(1/2), sqrt(2)), log m = 2 atanh(s) with s = (m - 1) / (m + 1), |s| < 0.172, by the
/// series of atanh to s^9 (truncation error below 1e-9). Error within a few float ulps
/// (sampled_test.cpp checks it against std::log in double).
inline __m128 log_ps(__m128 x) {
    const __m128 one = _mm_set1_ps(1);
    __m128i xi = _mm_castps_si128(x);
    __m128i e = _mm_sub_epi32(_mm_srli_epi32(xi, 23), _mm_set1_epi32(127));
    __m128 m = _mm_castsi128_ps(
        _mm_or_si128(_mm_and_si128(xi, _mm_set1_epi32(0x007fffff)), _mm_set1_epi32(0x3f800000)));
    __m128 big = _mm_cmpgt_ps(m, _mm_set1_ps(1.41421356f));
    m = _mm_blendv_ps(m, _mm_mul_ps(m, _mm_set1_ps(0.5f)), big);
    e = _mm_sub_epi32(e, _mm_castps_si128(big));  // a true mask is -1: e + 1
    __m128 s = _mm_div_ps(_mm_sub_ps(m, one), _mm_add_ps(m, one));
    __m128 s2 = _mm_mul_ps(s, s);
    __m128 p = _mm_set1_ps(Float(1.0 / 9));
    p = _mm_add_ps(_mm_mul_ps(p, s2), _mm_set1_ps(Float(1.0 / 7)));
    p = _mm_add_ps(_mm_mul_ps(p, s2), _mm_set1_ps(Float(1.0 / 5)));
    p = _mm_add_ps(_mm_mul_ps(p, s2), _mm_set1_ps(Float(1.0 / 3)));
    __m128 log_m = _mm_mul_ps(_mm_set1_ps(2), _mm_add_ps(s, _mm_mul_ps(_mm_mul_ps(s, s2), p)));
    return _mm_add_ps(_mm_mul_ps(_mm_cvtepi32_ps(e), _mm_set1_ps(Float(0.693147181))), log_m);
}
#endif

/// The wavelengths of one path and their sampling pdfs.
struct SampledWavelengths {
    std::array<Float, kSpectrumSamples> lambda{};
    std::array<Float, kSpectrumSamples> pdf{};

    /// Hero wavelength plus rotations by multiples of 1/N in primary sample space, so each
    /// is marginally distributed by visible_wavelengths_pdf.
    ///
    /// The average over the N rotated wavelengths is a 1/N-periodic function of the hero's
    /// primary sample, so stratifying u over [0, 1) stratifies that function only
    /// spp/N ways. Instead the high bits of u place the rotation offset within one period
    /// (spp-way stratified there), and a hash of them chooses which rotation is the hero, so
    /// the hero alone (after terminate_secondary) is still uniform over [0, 1) up to a
    /// 2^-22-fine interleaving of the four quarters, even for regular u (stratum centres). For
    /// a spiky emission spectrum at 64 spp this lowers the spectral RMSE four-fold.
    static SampledWavelengths sample_visible(Float u) {
        static_assert(kSpectrumSamples == 4, "the period split below uses two bits");
        uint32_t bits = uint32_t(u * Float(1 << 24));  // u has 24 significant bits
        uint32_t high = bits >> 2;
        Float offset = Float(high) * Float(1.0 / (1 << 22)) / kSpectrumSamples;
        uint32_t quarter = (high * 0x9E3779B1u) >> 30;  // Fibonacci hashing: top two bits
        Float hero = offset + Float(quarter) / kSpectrumSamples;
        SampledWavelengths w;
#if defined(__SSE4_1__)
        // sample_visible_wavelengths(up, pdf) for the four rotations at once.
        __m128 up = _mm_add_ps(_mm_set1_ps(hero), _mm_setr_ps(0, 0.25f, 0.5f, 0.75f));
        up = _mm_sub_ps(up, _mm_and_ps(_mm_cmpge_ps(up, _mm_set1_ps(1)), _mm_set1_ps(1)));
        __m128 y = _mm_sub_ps(_mm_set1_ps(kVisibleY0), _mm_mul_ps(_mm_set1_ps(kVisibleYSlope), up));
        __m128 one = _mm_set1_ps(1);
        _mm_storeu_ps(w.pdf.data(), _mm_mul_ps(_mm_set1_ps(kVisiblePdfScale),
                                               _mm_sub_ps(one, _mm_mul_ps(y, y))));
        __m128 l = log_ps(_mm_div_ps(_mm_add_ps(one, y), _mm_sub_ps(one, y)));
        _mm_storeu_ps(w.lambda.data(),
                      _mm_sub_ps(_mm_set1_ps(kVisiblePeak),
                                 _mm_mul_ps(_mm_set1_ps(kVisibleInvRate * Float(0.5)), l)));
#else
        for (int i = 0; i < kSpectrumSamples; ++i) {
            Float up = hero + Float(i) / kSpectrumSamples;
            if (up >= 1) up -= 1;
            w.lambda[i] = sample_visible_wavelengths(up, w.pdf[i]);
        }
#endif
        return w;
    }
    /// Uniform over [lmin, lmax], hero plus rotations (used by tests and meters).
    static SampledWavelengths sample_uniform(Float u, Float lmin = kLambdaMin,
                                             Float lmax = kLambdaMax) {
        SampledWavelengths w;
        for (int i = 0; i < kSpectrumSamples; ++i) {
            Float up = u + Float(i) / kSpectrumSamples;
            if (up > 1) up -= 1;
            w.lambda[i] = lerp(up, lmin, lmax);
            w.pdf[i] = 1 / (lmax - lmin);
        }
        return w;
    }
    Float operator[](int i) const { return lambda[i]; }
    /// Keeps only the hero wavelength (after a dispersive event): the others get pdf 0 and
    /// the hero's pdf is divided by N so the estimator stays unbiased.
    void terminate_secondary() {
        if (secondary_terminated()) return;
        for (int i = 1; i < kSpectrumSamples; ++i) pdf[i] = 0;
        pdf[0] /= kSpectrumSamples;
    }
    bool secondary_terminated() const {
        for (int i = 1; i < kSpectrumSamples; ++i)
            if (pdf[i] != 0) return false;
        return true;
    }
    SampledSpectrum pdf_spectrum() const {
        SampledSpectrum r;
        for (int i = 0; i < kSpectrumSamples; ++i) r.v[i] = pdf[i];
        return r;
    }
};

}  // namespace sr
