/// StratifiedSampler: permuted strata per (pixel, dimension), jittered inside the stratum.
#include "steradian/sampling/stratified_sampler.h"

#include <cmath>

#include "steradian/core/error.h"
#include "steradian/sampling/hash.h"

namespace sr {

namespace {

/// A value in stratum `stratum` of n equal strata of [0, 1), at fraction delta in [0, 1) of
/// the stratum. Nudged by an ulp if float rounding would put it in a neighbouring stratum (or
/// on 1), so stratification holds exactly for the returned floats.
Float stratum_sample(int stratum, double delta, int n) {
    auto f = Float((double(stratum) + delta) / double(n));
    while (f > 0 && double(f) * n >= double(stratum) + 1) f = std::nextafter(f, Float(0));
    while (double(f) * n < double(stratum)) f = std::nextafter(f, Float(1));
    return f;
}

/// Jitter fraction in [0, 1) from 32 hash bits, or the stratum centre.
double jitter_fraction(bool jitter, uint32_t bits) { return jitter ? double(bits) * 0x1p-32 : 0.5; }

}  // namespace

// ---- StratifiedSampler ------------------------------------------------------------------------

StratifiedSampler::StratifiedSampler(int x_samples, int y_samples, bool jitter, uint64_t seed)
    : Sampler(x_samples * y_samples),
      m_x_samples(x_samples),
      m_y_samples(y_samples),
      m_jitter(jitter),
      m_seed(seed) {
    if (x_samples < 1 || y_samples < 1) {
        throw Error(fmt::format("stratified sampler needs at least 1 x 1 samples, not {} x {}",
                                x_samples, y_samples));
    }
}

void StratifiedSampler::start_pixel_sample(Vec2i pixel, int sample_index, int dimension) {
    m_pixel_key = hash(pixel, m_seed);
    m_sample_index = sample_index;
    m_dimension = kPixelDimensions + dimension;
}

Float StratifiedSampler::get_1d() { return sample_1d(m_dimension++); }

Float StratifiedSampler::sample_1d(int dimension) const {
    uint64_t key = hash_combine(m_pixel_key, uint64_t(dimension));
    int n = samples_per_pixel();
    auto stratum = int(permutation_element(uint32_t(m_sample_index), uint32_t(n), uint32_t(key)));
    uint64_t jitter_bits = hash_combine(key, uint64_t(m_sample_index));
    return stratum_sample(stratum, jitter_fraction(m_jitter, uint32_t(jitter_bits)), n);
}

Point2 StratifiedSampler::get_2d() {
    Point2 p = sample_2d(m_dimension);
    m_dimension += 2;
    return p;
}

Point2 StratifiedSampler::sample_2d(int dimension) const {
    uint64_t key = hash_combine(m_pixel_key, uint64_t(dimension));
    auto stratum = int(permutation_element(uint32_t(m_sample_index), uint32_t(samples_per_pixel()),
                                           uint32_t(key)));
    uint64_t jitter_bits = hash_combine(key, uint64_t(m_sample_index));
    int sx = stratum % m_x_samples, sy = stratum / m_x_samples;
    return {
        stratum_sample(sx, jitter_fraction(m_jitter, uint32_t(jitter_bits)), m_x_samples),
        stratum_sample(sy, jitter_fraction(m_jitter, uint32_t(jitter_bits >> 32)), m_y_samples)};
}

std::unique_ptr<Sampler> StratifiedSampler::clone() const {
    return std::make_unique<StratifiedSampler>(*this);
}

}  // namespace sr
