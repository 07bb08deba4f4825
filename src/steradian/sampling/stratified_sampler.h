#pragma once
/// StratifiedSampler: jittered stratified samples, one per stratum in every dimension.
#include <cstdint>
#include <memory>
#include <string>

#include "steradian/core/math.h"
#include "steradian/sampling/sampler.h"

namespace sr {

/// Stratified (jittered) sampling as in pbrt: x_samples * y_samples samples per pixel; in
/// every dimension (1D: samples_per_pixel strata of [0,1); 2D: an x_samples by y_samples grid)
/// each stratum receives exactly one sample. The sample-to-stratum assignment is a random
/// permutation per (pixel, dimension, seed) (Kensler 2013), so dimensions are decorrelated;
/// jitter places each sample uniformly inside its stratum (otherwise at its centre).
class StratifiedSampler final : public Sampler {
  public:
    StratifiedSampler(int x_samples, int y_samples, bool jitter = true, uint64_t seed = 0);
    void start_pixel_sample(Vec2i pixel, int sample_index, int dimension = 0) override;
    Float get_1d() override;
    Point2 get_2d() override;
    void skip_1d() override { ++m_dimension; }
    void skip_2d() override { m_dimension += 2; }
    Point2 get_pixel_2d() override { return sample_2d(0); }
    Float get_pixel_1d() override { return sample_1d(2); }
    std::unique_ptr<Sampler> clone() const override;
    std::string name() const override { return "stratified"; }

    int x_samples() const { return m_x_samples; }
    int y_samples() const { return m_y_samples; }

  private:
    Float sample_1d(int dimension) const;
    Point2 sample_2d(int dimension) const;

    int m_x_samples, m_y_samples;
    bool m_jitter;
    uint64_t m_seed;
    uint64_t m_pixel_key = 0;
    int m_sample_index = 0;
    int m_dimension = kPixelDimensions;
};

}  // namespace sr
