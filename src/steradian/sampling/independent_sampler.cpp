/// IndependentSampler: a PCG32 stream per pixel, positioned per sample and dimension.
#include "steradian/sampling/independent_sampler.h"

#include "steradian/sampling/hash.h"
#include "steradian/sampling/sampler_internal.h"

namespace sr {

using namespace sampler_detail;

// ---- IndependentSampler -----------------------------------------------------------------------

IndependentSampler::IndependentSampler(int samples_per_pixel, uint64_t seed)
    : Sampler(samples_per_pixel), m_seed(seed) {
    check_spp(samples_per_pixel);
}

void IndependentSampler::start_pixel_sample(Vec2i pixel, int sample_index, int dimension) {
    m_pixel_rng.set_sequence(hash(pixel, m_seed));
    m_pixel_rng.advance(int64_t(sample_index) * kDimensionsPerSample);
    m_rng = m_pixel_rng;
    m_rng.advance(kPixelDimensions + dimension);
}

Point2 IndependentSampler::get_pixel_2d() {
    Pcg32 rng = m_pixel_rng;
    Float x = rng.next_float();
    return {x, rng.next_float()};
}

Float IndependentSampler::get_pixel_1d() {
    Pcg32 rng = m_pixel_rng;
    rng.advance(2);
    return rng.next_float();
}

std::unique_ptr<Sampler> IndependentSampler::clone() const {
    return std::make_unique<IndependentSampler>(*this);
}

}  // namespace sr
