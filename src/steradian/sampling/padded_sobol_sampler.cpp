/// PaddedSobolSampler: the per-(pixel, dimension) keys and the kernels of each index shuffle.
#include "steradian/sampling/padded_sobol_sampler.h"

#include <bit>

#include "steradian/sampling/hash.h"
#include "steradian/sampling/sampler_internal.h"

namespace sr {

using namespace sampler_detail;

namespace {

/// sobol_1d_float(nested_uniform_shuffle(i, index_seed), r, seed) given reversed_index =
/// reverse_bits32(i): two Laine-Karras permutations, each followed by a bit reversal (on SSE
/// registers where available: there the two reversals and the conversion cost about half the
/// scalar instructions).
[[gnu::always_inline]] inline Float nested_sobol_1d_float(uint32_t reversed_index,
                                                          uint32_t index_seed, Randomization r,
                                                          uint32_t seed) {
#if defined(SR_SOBOL_SSE4)
    __m128i v = detail::laine_karras_epi32(_mm_cvtsi32_si128(int32_t(reversed_index)),
                                           _mm_cvtsi32_si128(int32_t(index_seed)));
    v = detail::reverse_bits_epi32(v);  // the shuffled index
    __m128i s = _mm_cvtsi32_si128(int32_t(seed));
    if (r == Randomization::kOwen) v = detail::laine_karras_epi32(v, s);
    v = detail::reverse_bits_epi32(v);
    if (r == Randomization::kXor) v = _mm_xor_si128(v, s);
    return _mm_cvtss_f32(detail::unit_float_epi32x2(v));
#else
    return sobol_1d_float(reverse_bits32(laine_karras_permutation(reversed_index, index_seed)), r,
                          seed);
#endif
}

}  // namespace

// ---- PaddedSobolSampler -----------------------------------------------------------------------

PaddedSobolSampler::PaddedSobolSampler(int samples_per_pixel, uint64_t seed,
                                       SobolIndexShuffle shuffle, Randomization randomize)
    : Sampler(samples_per_pixel), m_seed(seed), m_shuffle(shuffle), m_randomize(randomize) {
    check_spp(samples_per_pixel);
    m_log2_spp = int(std::bit_width(uint32_t(samples_per_pixel) - 1));
    m_low_mask = uint32_t((uint64_t(1) << m_log2_spp) - 1);
    m_permutation_mask = permutation_mask(uint32_t(samples_per_pixel));
    select_kernels();
}

void PaddedSobolSampler::start_pixel_sample(Vec2i pixel, int sample_index, int dimension) {
    if (!m_have_pixel || pixel != m_pixel) {
        m_have_pixel = true;
        m_pixel = pixel;
        m_pixel_key = hash(pixel, m_seed);
        m_keys_valid = 0;
    }
    m_sample_index = sample_index;
    m_reversed_index = reverse_bits32(uint32_t(sample_index));
    m_split_pascal = m_log2_spp <= 8 && (uint32_t(sample_index) & ~m_low_mask) == 0;
    m_sample_key = hashed_dimensions_key(m_pixel_key, sample_index);
    m_dimension = kPixelDimensions + dimension;
}

void PaddedSobolSampler::fill_keys(int d) {
    auto i = std::size_t(d);
    uint64_t key = hash_combine(m_pixel_key, uint64_t(d));
    m_index_key[i] = uint32_t(key);
    m_scramble_key[i] = mix_bits(key);
    // The nested uniform shuffle maps [0, 2^m) into one aligned block of 2^m indices: its bits
    // above the low m are those of the image of 0. The permutation stays below 2^m.
    uint32_t high = m_shuffle == SobolIndexShuffle::kNestedUniform
                        ? nested_uniform_shuffle(0, uint32_t(key)) & ~m_low_mask
                        : 0;
    m_high_pascal[i] = uint32_t(pascal_mod2_transform(high));
    m_keys_valid |= uint64_t(1) << d;
}

template <SobolIndexShuffle kShuffle>
[[gnu::always_inline]] inline uint32_t PaddedSobolSampler::shuffled_index(int d) const {
    uint32_t seed = m_index_key[std::size_t(d)];
    if constexpr (kShuffle == SobolIndexShuffle::kPermutation) {
        return permutation_element(uint32_t(m_sample_index), uint32_t(samples_per_pixel()),
                                   m_permutation_mask, seed);
    } else {
        // nested_uniform_shuffle(sample index), with the index reversed once per pixel sample.
        return reverse_bits32(laine_karras_permutation(m_reversed_index, seed));
    }
}

// As for ZSobolSampler: kernels per index shuffle, selected by the constructor; the first use
// of a dimension in a pixel is a tail call, so that the hot paths need no stack frame.

void PaddedSobolSampler::select_kernels() {
    if (m_shuffle == SobolIndexShuffle::kPermutation) {
        m_get_1d_fn = &get_1d_impl<SobolIndexShuffle::kPermutation>;
        m_sample_2d_fn = &sample_2d_impl<SobolIndexShuffle::kPermutation>;
    } else {
        m_get_1d_fn = &get_1d_impl<SobolIndexShuffle::kNestedUniform>;
        m_sample_2d_fn = &sample_2d_impl<SobolIndexShuffle::kNestedUniform>;
    }
}

Float PaddedSobolSampler::get_1d() {
    int d = m_dimension++;
    if (d >= kLowDiscrepancyDimensions) [[unlikely]]
        return hashed_1d(m_sample_key, d);
    return m_get_1d_fn(*this, d);
}

template <SobolIndexShuffle kShuffle>
Float PaddedSobolSampler::get_1d_impl(PaddedSobolSampler& s, int d) {
    if (!((s.m_keys_valid >> d) & 1)) [[unlikely]]
        return fill_and_get_1d<kShuffle>(s, d);
    return s.value_1d<kShuffle>(d);
}

template <SobolIndexShuffle kShuffle>
[[gnu::noinline]] Float PaddedSobolSampler::fill_and_get_1d(PaddedSobolSampler& s, int d) {
    s.fill_keys(d);
    return s.value_1d<kShuffle>(d);
}

template <SobolIndexShuffle kShuffle>
[[gnu::always_inline]] inline Float PaddedSobolSampler::value_1d(int d) const {
    auto scramble = uint32_t(m_scramble_key[std::size_t(d)]);
    if constexpr (kShuffle == SobolIndexShuffle::kNestedUniform) {
        return nested_sobol_1d_float(m_reversed_index, m_index_key[std::size_t(d)], m_randomize,
                                     scramble);
    } else {
        return sobol_1d_float(shuffled_index<kShuffle>(d), m_randomize, scramble);
    }
}

Point2 PaddedSobolSampler::get_2d() {
    Point2 p = sample_2d(m_dimension);
    m_dimension += 2;
    return p;
}

Point2 PaddedSobolSampler::sample_2d(int d) {
    if (d >= kLowDiscrepancyDimensions) [[unlikely]]
        return hashed_2d(m_sample_key, d);
    return m_sample_2d_fn(*this, d);
}

template <SobolIndexShuffle kShuffle>
Point2 PaddedSobolSampler::sample_2d_impl(PaddedSobolSampler& s, int d) {
    if (!((s.m_keys_valid >> d) & 1)) [[unlikely]]
        return fill_and_sample_2d<kShuffle>(s, d);
    return s.value_2d<kShuffle>(d);
}

template <SobolIndexShuffle kShuffle>
[[gnu::noinline]] Point2 PaddedSobolSampler::fill_and_sample_2d(PaddedSobolSampler& s, int d) {
    s.fill_keys(d);
    return s.value_2d<kShuffle>(d);
}

template <SobolIndexShuffle kShuffle>
[[gnu::always_inline]] inline Point2 PaddedSobolSampler::value_2d(int d) const {
    auto i = std::size_t(d);
#if defined(SR_SOBOL_SSE4)
    if (kShuffle == SobolIndexShuffle::kNestedUniform && m_split_pascal) {
        // The shuffled index on an SSE register (as in nested_sobol_1d_float), its dimension-1
        // digits from the table into lane 1.
        __m128i v = detail::laine_karras_epi32(_mm_cvtsi32_si128(int32_t(m_reversed_index)),
                                               _mm_cvtsi32_si128(int32_t(m_index_key[i])));
        v = detail::reverse_bits_epi32(v);
        auto a = uint32_t(_mm_cvtsi128_si32(v));
        v = _mm_insert_epi32(v, int32_t(m_high_pascal[i] ^ kPascal8[a & m_low_mask]), 1);
        return detail::sobol_2d_float_epi32(v, m_randomize, m_scramble_key[i]);
    }
#endif
    uint32_t a = shuffled_index<kShuffle>(d);
    uint32_t y_digits = m_split_pascal ? m_high_pascal[i] ^ kPascal8[a & m_low_mask]
                                       : uint32_t(pascal_mod2_transform(a));
    return sobol_2d_float(a, y_digits, m_randomize, m_scramble_key[i]);
}

Float PaddedSobolSampler::get_pixel_1d() {
    if (!(m_keys_valid & 1)) fill_keys(0);
    if (!((m_keys_valid >> 2) & 1)) fill_keys(2);
    uint32_t a = m_shuffle == SobolIndexShuffle::kPermutation
                     ? shuffled_index<SobolIndexShuffle::kPermutation>(0)
                     : shuffled_index<SobolIndexShuffle::kNestedUniform>(0);
    return sobol_1d_float(sobol_dim2_digits(a), m_randomize, uint32_t(m_scramble_key[2]));
}

std::unique_ptr<Sampler> PaddedSobolSampler::clone() const {
    return std::make_unique<PaddedSobolSampler>(*this);
}

std::string PaddedSobolSampler::name() const {
    return m_shuffle == SobolIndexShuffle::kPermutation ? "paddedsobol" : "sobol";
}

}  // namespace sr
