#pragma once
/// PaddedSobolSampler: padded, Owen-scrambled 2D Sobol samples per dimension pair.
#include <array>
#include <cstdint>
#include <memory>
#include <string>

#include "steradian/core/math.h"
#include "steradian/sampling/sampler.h"
#include "steradian/sampling/sobol.h"

namespace sr {

/// How PaddedSobolSampler shuffles sample indices per (pixel, dimension).
enum class SobolIndexShuffle {
    kNestedUniform,  ///< Burley 2020 nested uniform shuffle (hash-based Owen scrambling of the
                     ///< index)
    kPermutation,    ///< Kensler 2013 permutation of [0, samples_per_pixel) (pbrt-v4 "paddedsobol")
};

/// Padded, Owen-scrambled 2D Sobol sampling per dimension pair (Burley 2020, "Practical
/// Hash-based Owen Scrambling", JCGT 9(4), Sec. 3 and 4): for every pixel and dimension the
/// sample index is shuffled and the (0,2)-sequence point of the shuffled index is Owen
/// scrambled, both with keys hashed from (pixel, dimension, seed). For samples_per_pixel =
/// 2^m, each pixel's samples form a (0,m,2)-net in every dimension pair (and are stratified in
/// every single dimension); different pixels and dimension pairs are decorrelated.
/// Dimensions from kLowDiscrepancyDimensions on are hashed pseudo-random numbers. The keys of
/// the current pixel are memoized per dimension (they do not depend on the sample index).
class PaddedSobolSampler final : public Sampler {
  public:
    PaddedSobolSampler(int samples_per_pixel, uint64_t seed = 0,
                       SobolIndexShuffle shuffle = SobolIndexShuffle::kNestedUniform,
                       Randomization randomize = Randomization::kOwen);
    void start_pixel_sample(Vec2i pixel, int sample_index, int dimension = 0) override;
    Float get_1d() override;
    Point2 get_2d() override;
    void skip_1d() override { ++m_dimension; }
    void skip_2d() override { m_dimension += 2; }
    Point2 get_pixel_2d() override { return sample_2d(0); }
    /// Sobol dimension 2 of get_pixel_2d()'s shuffled index, scrambled with dimension 2's key.
    Float get_pixel_1d() override;
    std::unique_ptr<Sampler> clone() const override;
    /// "sobol" for the nested uniform shuffle, "paddedsobol" for the permutation shuffle.
    std::string name() const override;

  private:
    /// The shuffled sample index for dimension d < kLowDiscrepancyDimensions (keys filled).
    template <SobolIndexShuffle kShuffle>
    uint32_t shuffled_index(int d) const;
    /// Computes and memoizes the keys of dimension d for the current pixel.
    void fill_keys(int d);
    Point2 sample_2d(int dimension);
    // Kernels of get_1d() and sample_2d() for dimension d < kLowDiscrepancyDimensions,
    // specialized on the index shuffle.
    using Get1dFn = Float (*)(PaddedSobolSampler&, int);
    using Sample2dFn = Point2 (*)(PaddedSobolSampler&, int);
    void select_kernels();
    template <SobolIndexShuffle kShuffle>
    static Float get_1d_impl(PaddedSobolSampler& s, int d);
    template <SobolIndexShuffle kShuffle>
    static Float fill_and_get_1d(PaddedSobolSampler& s, int d);
    template <SobolIndexShuffle kShuffle>
    Float value_1d(int d) const;
    template <SobolIndexShuffle kShuffle>
    static Point2 sample_2d_impl(PaddedSobolSampler& s, int d);
    template <SobolIndexShuffle kShuffle>
    static Point2 fill_and_sample_2d(PaddedSobolSampler& s, int d);
    template <SobolIndexShuffle kShuffle>
    Point2 value_2d(int d) const;

    // Configuration.
    uint64_t m_seed;
    SobolIndexShuffle m_shuffle;
    Randomization m_randomize;
    int m_log2_spp;               // ceil(log2(samples per pixel))
    uint32_t m_low_mask;          // 2^m - 1
    uint32_t m_permutation_mask;  // permutation_mask(samples per pixel)
    Get1dFn m_get_1d_fn = nullptr;
    Sample2dFn m_sample_2d_fn = nullptr;

    // Current pixel; memoized per-dimension keys.
    bool m_have_pixel = false;
    Vec2i m_pixel{0, 0};
    uint64_t m_pixel_key = 0;
    uint64_t m_keys_valid = 0;  // bit d: the keys of dimension d are filled
    std::array<uint32_t, kLowDiscrepancyDimensions> m_index_key{};     // index shuffle seed
    std::array<uint64_t, kLowDiscrepancyDimensions> m_scramble_key{};  // point scrambling key
    // Sobol dimension-1 digits of the shuffled index's bits above the low m bits (the same for
    // all sample indices < 2^m).
    std::array<uint32_t, kLowDiscrepancyDimensions> m_high_pascal{};

    // Current pixel sample.
    int m_sample_index = 0;
    uint32_t m_reversed_index = 0;  // reverse_bits32(sample index)
    bool m_split_pascal = false;    // sample index < 2^m <= 256: use m_high_pascal and a table
    uint64_t m_sample_key = 0;      // key of the hashed dimensions
    int m_dimension = kPixelDimensions;
};

/// The Owen-scrambled Sobol sampler of the "sobol" name: PaddedSobolSampler with the nested
/// uniform index shuffle (its default).
using SobolSampler = PaddedSobolSampler;

}  // namespace sr
