/// Spectrum variant dispatch, the per-struct evaluations, CIE integration and Planck's law.
#include "steradian/spectrum/spectrum.h"

#include <algorithm>
#include <cmath>
#if defined(__SSE4_1__)
#include <smmintrin.h>
#endif

#include "steradian/core/error.h"
#include "steradian/spectrum/cie_data.h"
#include "steradian/spectrum/sigmoid.h"

namespace sr {

namespace {

constexpr int kDenseCount = int(kLambdaMax - kLambdaMin) + 1;  // 471 samples, one per nm
static_assert(kDenseCount == cie::kCmfCount);
static_assert(int(kLambdaMin) == cie::kCmfFirstNm);

DenselySampledSpectrum dense_from_table(const float* table) {
    return DenselySampledSpectrum{
        std::make_shared<const std::vector<Float>>(table, table + kDenseCount)};
}

}  // namespace

// ---- per-struct evaluation ------------------------------------------------------------------

namespace {

/// O(1): index and linear interpolation between the two neighbouring integer wavelengths of a
/// table of kDenseCount values from kLambdaMin; 0 outside the table.
inline Float dense_lookup(const Float* v, Float lambda) {
    Float t = lambda - kLambdaMin;
    if (!(t >= 0 && t <= kLambdaMax - kLambdaMin)) return 0;
    int i = std::min(int(t), kDenseCount - 2);
    Float f = t - Float(i);
    return v[i] + f * (v[i + 1] - v[i]);
}

}  // namespace

Float DenselySampledSpectrum::operator()(Float lambda) const {
    if (!values) return 0;
    SR_DCHECK(int(values->size()) == kDenseCount);
    return dense_lookup(values->data(), lambda);
}

Float DenselySampledSpectrum::max_value() const {
    if (!values || values->empty()) return 0;
    return *std::max_element(values->begin(), values->end());
}

Float PiecewiseLinearSpectrum::operator()(Float lambda) const {
    if (!lambdas || lambdas->empty()) return 0;
    const std::vector<Float>& l = *lambdas;
    const std::vector<Float>& v = *values;
    if (!(lambda >= l.front() && lambda <= l.back())) return 0;
    if (l.size() == 1) return v[0];
    // First sample strictly above lambda; the segment is [i, i + 1].
    auto it = std::upper_bound(l.begin(), l.end(), lambda);
    size_t i = size_t(std::max<std::ptrdiff_t>(it - l.begin(), 1)) - 1;
    i = std::min(i, l.size() - 2);
    Float t = (lambda - l[i]) / (l[i + 1] - l[i]);
    return v[i] + t * (v[i + 1] - v[i]);
}

Float PiecewiseLinearSpectrum::max_value() const {
    if (!values || values->empty()) return 0;
    return *std::max_element(values->begin(), values->end());
}

double planck(double lambda_nm, double temperature_k) {
    if (!(temperature_k > 0) || !(lambda_nm > 0)) return 0;
    constexpr double c = 299792458.0;     // m/s
    constexpr double h = 6.62606957e-34;  // J s
    constexpr double kb = 1.3806488e-23;  // J/K
    double l = lambda_nm * 1e-9;          // m
    double l5 = (l * l) * (l * l) * l;
    // B(l, T) = 2 h c^2 / (l^5 (exp(h c / (l kb T)) - 1))
    return (2 * h * c * c) / (l5 * std::expm1((h * c) / (l * kb * temperature_k)));
}

BlackbodySpectrum::BlackbodySpectrum(Float T) : temperature(T) {
    if (!(T > 0)) {
        normalization = 0;
        return;
    }
    double lambda_max_nm = kWienDisplacement / double(T) * 1e9;
    normalization = Float(1 / planck(lambda_max_nm, T));
}

Float BlackbodySpectrum::operator()(Float lambda) const {
    return Float(planck(lambda, temperature) * double(normalization));
}

Float RgbAlbedoSpectrum::operator()(Float lambda) const {
    return sigmoid_polynomial(c0, c1, c2, lambda);
}
Float RgbAlbedoSpectrum::max_value() const { return sigmoid_polynomial_max(c0, c1, c2); }

Float RgbUnboundedSpectrum::operator()(Float lambda) const {
    return scale * sigmoid_polynomial(c0, c1, c2, lambda);
}
Float RgbUnboundedSpectrum::max_value() const { return scale * sigmoid_polynomial_max(c0, c1, c2); }

Float RgbIlluminantSpectrum::operator()(Float lambda) const {
    return scale * sigmoid_polynomial(c0, c1, c2, lambda) * illuminant(lambda);
}
Float RgbIlluminantSpectrum::max_value() const {
    return scale * sigmoid_polynomial_max(c0, c1, c2) * illuminant.max_value();
}

// ---- variant dispatch -----------------------------------------------------------------------

Float Spectrum::operator()(Float lambda) const {
    return std::visit([lambda](const auto& s) -> Float { return s(lambda); }, m_v);
}

SampledSpectrum Spectrum::sample(const SampledWavelengths& lambda) const {
    // Tabulated spectra (materials and most emitters after the scene builder) first: the table
    // pointer is read once for the four wavelengths.
    if (const auto* d = std::get_if<DenselySampledSpectrum>(&m_v); d && d->values) {
        const Float* v = d->values->data();
        SampledSpectrum r;
#if defined(__SSE4_1__)
        // dense_lookup for the four wavelengths at once (the same arithmetic; the clamp
        // before the conversion keeps the index in the table for any input, NaN included).
        static_assert(kSpectrumSamples == 4);
        __m128 t = _mm_sub_ps(_mm_loadu_ps(lambda.lambda.data()), _mm_set1_ps(kLambdaMin));
        __m128 inside = _mm_and_ps(_mm_cmpge_ps(t, _mm_setzero_ps()),
                                   _mm_cmple_ps(t, _mm_set1_ps(kLambdaMax - kLambdaMin)));
        __m128 tc = _mm_min_ps(_mm_max_ps(t, _mm_setzero_ps()), _mm_set1_ps(Float(kDenseCount - 2)));
        __m128i i = _mm_cvttps_epi32(tc);
        __m128 f = _mm_sub_ps(t, _mm_cvtepi32_ps(i));
        alignas(16) int32_t ix[4];
        _mm_store_si128(reinterpret_cast<__m128i*>(ix), i);
        __m128 a = _mm_setr_ps(v[ix[0]], v[ix[1]], v[ix[2]], v[ix[3]]);
        __m128 b = _mm_setr_ps(v[ix[0] + 1], v[ix[1] + 1], v[ix[2] + 1], v[ix[3] + 1]);
        __m128 x = _mm_add_ps(a, _mm_mul_ps(f, _mm_sub_ps(b, a)));
        r.v = Float4(_mm_and_ps(x, inside));
#else
        for (int i = 0; i < kSpectrumSamples; ++i) r.v[i] = dense_lookup(v, lambda.lambda[i]);
#endif
        return r;
    }
    // One dispatch per call; the loop over the wavelengths runs inside the alternative.
    return std::visit(
        [&lambda](const auto& s) {
            SampledSpectrum r;
            for (int i = 0; i < kSpectrumSamples; ++i) r.v[i] = s(lambda.lambda[i]);
            return r;
        },
        m_v);
}

Float Spectrum::max_value() const {
    return std::visit([](const auto& s) -> Float { return s.max_value(); }, m_v);
}

// ---- construction ---------------------------------------------------------------------------

DenselySampledSpectrum densely_sampled(const Spectrum& s) {
    if (const auto* d = s.get_if<DenselySampledSpectrum>(); d && d->values) return *d;
    auto v = std::make_shared<std::vector<Float>>(kDenseCount);
    for (int i = 0; i < kDenseCount; ++i) (*v)[i] = s(kLambdaMin + Float(i));
    return DenselySampledSpectrum{std::move(v)};
}

PiecewiseLinearSpectrum piecewise_linear_from_interleaved(const std::vector<Float>& pairs,
                                                          bool normalize) {
    if (pairs.empty() || pairs.size() % 2 != 0)
        throw Error(
            fmt::format("spectrum: expected (lambda, value) pairs, got {} numbers", pairs.size()));
    size_t n = pairs.size() / 2;
    auto l = std::make_shared<std::vector<Float>>(n);
    auto v = std::make_shared<std::vector<Float>>(n);
    for (size_t i = 0; i < n; ++i) {
        (*l)[i] = pairs[2 * i];
        (*v)[i] = pairs[2 * i + 1];
        if (!std::isfinite((*l)[i]) || !std::isfinite((*v)[i]))
            throw Error(fmt::format("spectrum: non-finite value in pair {}", i));
        if (i > 0 && !((*l)[i] > (*l)[i - 1]))
            throw Error(
                fmt::format("spectrum: wavelengths must increase strictly ({} nm follows {} nm)",
                            (*l)[i], (*l)[i - 1]));
    }
    PiecewiseLinearSpectrum s{l, v};
    if (normalize) {
        // pbrt-v4: scale so that the CIE Y of the spectrum (1 nm sums / kCieYIntegral) is 1.
        Float y = inner_product(Spectrum(s), Spectrum(cie_y()));
        if (y > 0) {
            Float k = kCieYIntegral / y;
            for (Float& x : *v) x *= k;
        }
    }
    return s;
}

// ---- CIE colour matching functions and integration ------------------------------------------

const DenselySampledSpectrum& cie_x() {
    static const DenselySampledSpectrum s = dense_from_table(cie::kX);
    return s;
}
const DenselySampledSpectrum& cie_y() {
    static const DenselySampledSpectrum s = dense_from_table(cie::kY);
    return s;
}
const DenselySampledSpectrum& cie_z() {
    static const DenselySampledSpectrum s = dense_from_table(cie::kZ);
    return s;
}

const DenselySampledSpectrum& cie_scotopic_v() {
    // The 1 nm table placed at its wavelengths in the 360..830 nm grid, zero elsewhere.
    static const DenselySampledSpectrum s = [] {
        static_assert(cie::kScotopicFirstNm >= int(kLambdaMin));
        static_assert(cie::kScotopicFirstNm + cie::kScotopicCount - 1 <= int(kLambdaMax));
        auto v = std::make_shared<std::vector<Float>>(kDenseCount, Float(0));
        for (int i = 0; i < cie::kScotopicCount; ++i)
            (*v)[size_t(cie::kScotopicFirstNm - int(kLambdaMin) + i)] = cie::kScotopicV[i];
        return DenselySampledSpectrum{std::move(v)};
    }();
    return s;
}

Float inner_product(const Spectrum& a, const Spectrum& b) {
    double sum = 0;
    for (int i = 0; i < kDenseCount; ++i) {
        Float lambda = kLambdaMin + Float(i);
        sum += double(a(lambda)) * double(b(lambda));
    }
    return Float(sum);
}

Xyz spectrum_to_xyz(const Spectrum& s) {
    double x = 0, y = 0, z = 0;
    for (int i = 0; i < kDenseCount; ++i) {
        double v = s(kLambdaMin + Float(i));
        x += cie::kX[i] * v;
        y += cie::kY[i] * v;
        z += cie::kZ[i] * v;
    }
    return {Float(x / kCieYIntegral), Float(y / kCieYIntegral), Float(z / kCieYIntegral)};
}

Float spectrum_to_photometric(const Spectrum& s) {
    // pbrt-v4: for an RGB illuminant only the illuminant counts; its RGB scale is the
    // light's business.
    if (const auto* rs = s.get_if<RgbIlluminantSpectrum>())
        return inner_product(Spectrum(rs->illuminant), Spectrum(cie_y()));
    return inner_product(s, Spectrum(cie_y()));
}

Xyz reflectance_to_xyz(const Spectrum& r, const Spectrum& illuminant) {
    double x = 0, y = 0, z = 0, yw = 0;
    for (int i = 0; i < kDenseCount; ++i) {
        Float lambda = kLambdaMin + Float(i);
        double e = illuminant(lambda);
        double v = r(lambda) * e;
        x += cie::kX[i] * v;
        y += cie::kY[i] * v;
        z += cie::kZ[i] * v;
        yw += cie::kY[i] * e;
    }
    if (!(yw > 0)) return {};
    return {Float(x / yw), Float(y / yw), Float(z / yw)};
}

}  // namespace sr
