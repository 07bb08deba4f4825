#pragma once
/// IndependentSampler: independent uniform random samples from a PCG32 stream per pixel.
#include <cstdint>
#include <memory>
#include <string>

#include "steradian/core/math.h"
#include "steradian/sampling/rng.h"
#include "steradian/sampling/sampler.h"

namespace sr {

/// Independent uniform random samples: a PCG32 stream per pixel (selected by a hash of pixel
/// and seed), positioned at sample_index * 65536 + dimension. Supports up to 65536 dimensions
/// per sample. The baseline every other sampler must agree with in expectation.
class IndependentSampler final : public Sampler {
  public:
    IndependentSampler(int samples_per_pixel, uint64_t seed = 0);
    void start_pixel_sample(Vec2i pixel, int sample_index, int dimension = 0) override;
    Float get_1d() override { return m_rng.next_float(); }
    Point2 get_2d() override {
        Float x = m_rng.next_float();
        return {x, m_rng.next_float()};
    }
    void skip_1d() override { m_rng.next_u32(); }
    void skip_2d() override {
        m_rng.next_u32();
        m_rng.next_u32();
    }
    Point2 get_pixel_2d() override;
    Float get_pixel_1d() override;
    std::unique_ptr<Sampler> clone() const override;
    std::string name() const override { return "independent"; }

    static constexpr int64_t kDimensionsPerSample = 65536;

  private:
    uint64_t m_seed;
    Pcg32 m_pixel_rng;  // positioned at the sample's dimension 0
    Pcg32 m_rng;        // positioned at the next dimension
};

}  // namespace sr
