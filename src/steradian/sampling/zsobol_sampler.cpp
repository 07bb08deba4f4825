/// ZSobolSampler: base-4 digit shuffles, per-pixel memoization and tables, and the kernels.
#include "steradian/sampling/zsobol_sampler.h"

#include <algorithm>
#include <array>
#include <bit>
#include <cstring>

#include "steradian/core/error.h"
#include "steradian/sampling/hash.h"
#include "steradian/sampling/sampler_internal.h"

namespace sr {

using namespace sampler_detail;

namespace {

/// The 24 permutations of {0, 1, 2, 3} in lexicographic order.
constexpr std::array<std::array<uint8_t, 4>, 24> make_base4_permutations() {
    std::array<std::array<uint8_t, 4>, 24> perms{};
    std::array<uint8_t, 4> p{0, 1, 2, 3};
    for (auto& out : perms) {
        out = p;
        std::next_permutation(p.begin(), p.end());
    }
    return perms;
}
constexpr auto kBase4Permutations = make_base4_permutations();

/// kBase4Columns[d][p] = kBase4Permutations[p][d]: the image of digit d under each
/// permutation, so that a digit known in advance selects its row once.
constexpr std::array<std::array<uint8_t, 24>, 4> make_base4_columns() {
    std::array<std::array<uint8_t, 24>, 4> cols{};
    for (std::size_t p = 0; p < 24; ++p)
        for (std::size_t d = 0; d < 4; ++d) cols[d][p] = kBase4Permutations[p][d];
    return cols;
}
constexpr auto kBase4Columns = make_base4_columns();

/// Odd multiplier that turns (node hash ^ dimension key) into a permutation choice (a
/// bijection whose top bits depend on all bits).
constexpr uint64_t kPermutationMul = 0xd6e8feb86659fd93ULL;

/// Hash of the quadtree node of base-4 digit `digit` whose index bits above the digit are
/// `higher` (the index shifted right past the digit).
inline uint64_t digit_node_hash(uint64_t higher, uint64_t seed_key, int digit) {
    return mix_bits((higher ^ seed_key) + kGolden64 * uint64_t(digit + 1));
}

/// Hash of the node of the single-bit lowest digit (odd m) whose index bits above bit 0 are
/// `higher`.
inline uint64_t bit_node_hash(uint64_t higher, uint64_t seed_key) {
    return mix_bits(higher ^ seed_key);
}

/// Which of the 24 permutations of {0,1,2,3} a quadtree node uses for a dimension.
inline std::size_t base4_permutation(uint64_t node_hash, uint64_t dim_key) {
    uint64_t t = (node_hash ^ dim_key) * kPermutationMul;
    return std::size_t(((t >> 32) * 24) >> 32);
}

/// Whether a single-bit node flips its bit for a dimension.
inline uint64_t binary_flip(uint64_t node_hash, uint64_t dim_key) {
    return ((node_hash ^ dim_key) * kPermutationMul) >> 63;
}

}  // namespace

// ---- ZSobolSampler ----------------------------------------------------------------------------

ZSobolSampler::ZSobolSampler(int samples_per_pixel, Vec2i resolution, uint64_t seed,
                             Randomization randomize)
    : Sampler(samples_per_pixel), m_seed(seed), m_seed_key(mix_bits(seed)), m_randomize(randomize) {
    check_spp(samples_per_pixel);
    if (resolution.x < 1 || resolution.y < 1) {
        throw Error(
            fmt::format("zsobol sampler: invalid resolution {} x {}", resolution.x, resolution.y));
    }
    m_log2_spp = int(std::bit_width(uint32_t(samples_per_pixel) - 1));  // ceil(log2(spp))
    int log2_res = int(std::bit_width(uint32_t(std::max(resolution.x, resolution.y)) - 1));
    if (2 * log2_res + m_log2_spp > 64) {
        throw Error("zsobol sampler: resolution x samples per pixel exceed 64-bit sample indices");
    }
    m_num_sample_digits = (m_log2_spp + 1) / 2;
    m_num_base4_digits = log2_res + m_num_sample_digits;
    m_hashed_digits_end = std::min(m_num_base4_digits, m_num_sample_digits + kHashedPixelLevels);
    int odd = m_log2_spp & 1;
    int xor_lo = 2 * m_hashed_digits_end - odd, xor_hi = 2 * m_num_base4_digits - odd;
    if (xor_hi > xor_lo) {
        uint64_t below_hi = xor_hi < 64 ? (uint64_t(1) << xor_hi) - 1 : ~uint64_t(0);
        m_xor_mask = below_hi & ~((uint64_t(1) << xor_lo) - 1);
    }
    // The keys depend on (dimension, seed) only.
    for (int d = 0; d < kLowDiscrepancyDimensions; ++d) {
        m_dim_key[std::size_t(d)] = dimension_key(d);
        m_scramble_key[std::size_t(d)] = mix_bits(dimension_key(d));
    }
    select_kernels();
}

// Digits are base 4 from the top; if log2(spp) is odd, the lowest digit is a single bit, so that
// the boundary between pixel bits and sample bits is always a digit boundary: digits
// [0, m_num_sample_digits) hold the sample index, the others the pixel. Each digit is a node of
// the quadtree over (pixels, samples), identified by the digits above it and its level; its
// hash is computed once (per pixel for the hashed pixel digits and the highest sample digit,
// whose node is the pixel; per pixel sample for the other sample digits), leaving one multiply
// per digit and dimension.
void ZSobolSampler::set_pixel(Vec2i pixel) {
    int odd = m_log2_spp & 1;
    int top = m_num_sample_digits - 1;  // the highest sample digit (-1: none)
    m_have_pixel = true;
    m_pixel = pixel;
    m_pixel_key = hash(pixel, m_seed);
    m_prefix_valid = 0;
    m_table_pixel = false;
    m_level_hashes_valid = false;
    m_pixel_index = encode_morton2(uint32_t(pixel.x), uint32_t(pixel.y)) << m_log2_spp;
    int top_shift = 2 * m_num_base4_digits - odd;
    m_index_high_bits = top_shift < 64 ? (m_pixel_index >> top_shift) << top_shift : 0;
    for (int i = std::max(top, odd); i < m_hashed_digits_end; ++i) {
        int shift = 2 * i - odd;
        uint64_t higher = shift + 2 < 64 ? m_pixel_index >> (shift + 2) : 0;
        m_node_hash[std::size_t(i)] = digit_node_hash(higher, m_seed_key, i);
    }
    if (odd && top == 0) m_node_hash[0] = bit_node_hash(m_pixel_index >> 1, m_seed_key);
}

void ZSobolSampler::start_pixel_sample(Vec2i pixel, int sample_index, int dimension) {
    if (!m_have_pixel || pixel != m_pixel) set_pixel(pixel);
    m_sample_index = sample_index;
    m_dimension = kPixelDimensions + dimension;
    m_table_sample = m_table_pixel && sample_index >= m_table_lo && sample_index < m_table_hi;
    if (m_table_sample)
        m_sample_nodes_valid = false;
    else
        compute_sample_nodes();
}

void ZSobolSampler::compute_sample_nodes() {
    int odd = m_log2_spp & 1;
    int top = m_num_sample_digits - 1;
    m_morton_index = m_pixel_index | uint64_t(uint32_t(m_sample_index));
    m_sample_key = hashed_dimensions_key(m_pixel_key, m_sample_index);
    for (int i = odd; i < top; ++i) {
        int shift = 2 * i - odd;
        m_node_hash[std::size_t(i)] = digit_node_hash(m_morton_index >> (shift + 2), m_seed_key, i);
    }
    if (odd && top > 0) m_node_hash[0] = bit_node_hash(m_morton_index >> 1, m_seed_key);
    for (int i = odd; i <= top; ++i)
        m_sample_column[std::size_t(i)] =
            kBase4Columns[(m_morton_index >> (2 * i - odd)) & 3].data();
    m_sample_nodes_valid = true;
}

// ---- Tables (start_pixel()) ----
//
// The sample digits of a pixel's 2^m samples are the leaves of a quadtree whose root is the
// pixel (the highest sample digit): for a dimension, each node at level i (digit i, at bit
// 2i - odd) permutes its 4 children by a permutation hashed from the node and the dimension,
// so that the sample digits of sample j are the OR over the levels of
// perm(node(j))[digit_i(j)] << (2i - odd). The tables hash each node once per dimension and
// fill the digits of its children in runs.

void ZSobolSampler::start_pixel(Vec2i pixel, int first_sample, int end_sample) {
    if (!m_have_pixel || pixel != m_pixel) set_pixel(pixel);
    const int n = 1 << std::min(m_log2_spp, 30);
    first_sample = std::max(first_sample, 0);
    end_sample = std::min(end_sample, n);
    if (m_log2_spp < 3 || m_log2_spp > 8 || end_sample - first_sample < 8) {
        m_table_pixel = false;
        return;
    }
    int lo = first_sample & ~7, hi = std::min(n, (end_sample + 7) & ~7);
    if (m_table_pixel && lo >= m_table_lo && hi <= m_table_hi) return;  // still filled
    m_table_pixel = true;
    m_table_lo = lo;
    m_table_hi = hi;
    m_table_valid_x = m_table_valid_y = 0;
    if (m_table_x.empty()) {
        m_table_x.resize(std::size_t(kTableDimensions) << m_log2_spp);
        m_table_y.resize(std::size_t(kTableDimensions) << m_log2_spp);
    }
}

void ZSobolSampler::fill_level_hashes() {
    const int m = m_log2_spp, odd = m & 1, top = m_num_sample_digits - 1;
    std::size_t total = 0;
    for (int i = 0; i < top; ++i) {
        m_level_offset[std::size_t(i)] = int(total);
        // Level i's nodes: the samples sharing the digits above digit i (above bit 0 for the
        // single-bit digit of odd m).
        int node_shift = (odd && i == 0) ? 1 : 2 * i - odd + 2;
        total += std::size_t(1) << (m - node_shift);
    }
    m_level_hash.resize(total);
    for (int i = 0; i < top; ++i) {
        uint64_t* h = m_level_hash.data() + m_level_offset[std::size_t(i)];
        if (odd && i == 0) {
            for (uint64_t k = 0; k < (uint64_t(1) << (m - 1)); ++k)
                h[k] = bit_node_hash((m_pixel_index >> 1) | k, m_seed_key);
        } else {
            int node_shift = 2 * i - odd + 2;
            for (uint64_t k = 0; k < (uint64_t(1) << (m - node_shift)); ++k)
                h[k] = digit_node_hash((m_pixel_index >> node_shift) | k, m_seed_key, i);
        }
    }
    m_level_hashes_valid = true;
}

namespace {

/// A node's permuted child digits as the bytes of its samples, digit q repeated `run` times:
/// kChildBytes1[p] (run 1, 4 bytes), kChildBytes2[p] (run 2, 8 bytes), kChildBytes4[p] (run 4,
/// 16 bytes) for permutation p, little-endian. Shifting them left by a digit's bit position
/// keeps every byte in place (digits are below 4, positions below 7).
constexpr std::array<uint32_t, 24> make_child_bytes1() {
    std::array<uint32_t, 24> t{};
    for (std::size_t p = 0; p < 24; ++p)
        for (std::size_t q = 0; q < 4; ++q) t[p] |= uint32_t(kBase4Permutations[p][q]) << (8 * q);
    return t;
}
constexpr std::array<uint64_t, 24> make_child_bytes2() {
    std::array<uint64_t, 24> t{};
    for (std::size_t p = 0; p < 24; ++p)
        for (std::size_t b = 0; b < 8; ++b)
            t[p] |= uint64_t(kBase4Permutations[p][b / 2]) << (8 * b);
    return t;
}
constexpr std::array<std::array<uint64_t, 2>, 24> make_child_bytes4() {
    std::array<std::array<uint64_t, 2>, 24> t{};
    for (std::size_t p = 0; p < 24; ++p)
        for (std::size_t b = 0; b < 16; ++b)
            t[p][b / 8] |= uint64_t(kBase4Permutations[p][b / 4]) << (8 * (b % 8));
    return t;
}
constexpr auto kChildBytes1 = make_child_bytes1();
constexpr auto kChildBytes2 = make_child_bytes2();
constexpr auto kChildBytes4 = make_child_bytes4();

template <typename T>
inline void or_bytes(uint8_t* p, T v) {
    T w;
    std::memcpy(&w, p, sizeof(T));
    w |= v;
    std::memcpy(p, &w, sizeof(T));
}

/// ORs the child digits of a node with permutation `perm` into its samples' bytes p[0, 4 run).
inline void or_child_digits(uint8_t* p, std::size_t perm, int shift, int run) {
    switch (run) {
        case 1:
            or_bytes(p, kChildBytes1[perm] << shift);
            return;
        case 2:
            or_bytes(p, kChildBytes2[perm] << shift);
            return;
        case 4:
            or_bytes(p, kChildBytes4[perm][0] << shift);
            or_bytes(p + 8, kChildBytes4[perm][1] << shift);
            return;
        default:
            for (std::size_t q = 0; q < 4; ++q) {
                uint64_t w = uint64_t(kBase4Permutations[perm][q] << shift) * 0x0101010101010101ULL;
                for (int t = 0; t < run; t += 8) or_bytes(p + int(q) * run + t, w);
            }
    }
}

}  // namespace

// Not vectorized: GCC's vector code for the node loop (16 iterations at 64 spp, a 64-bit
// multiply each) ran more instructions than the scalar loop.
[[gnu::optimize("no-tree-vectorize")]] void ZSobolSampler::table_sample_digits(int d,
                                                                               uint8_t* low) const {
    const int m = m_log2_spp, odd = m & 1, top = m_num_sample_digits - 1;  // m >= 3: top >= 1
    const uint64_t key = m_dim_key[std::size_t(d)];
    const int lo = m_table_lo, hi = m_table_hi;  // multiples of 8
    for (int j = lo; j < hi; j += 8) std::memset(low + j, 0, 8);
    // The highest digit: one node, the pixel, whose permutation is memoized per dimension.
    {
        const int shift = 2 * top - odd, run = 1 << shift;
        const int k0 = lo >> (shift + 2);
        or_child_digits(low + (k0 << (shift + 2)), m_top_choice[std::size_t(d)], shift, run);
    }
    for (int i = odd; i < top; ++i) {
        const int shift = 2 * i - odd, run = 1 << shift, node_shift = shift + 2;
        const uint64_t* h = m_level_hash.data() + m_level_offset[std::size_t(i)];
        const int k_end = (hi + (1 << node_shift) - 1) >> node_shift;
        for (int k = lo >> node_shift; k < k_end; ++k)
            or_child_digits(low + (k << node_shift), base4_permutation(h[k], key), shift, run);
    }
    if (odd) {  // the single-bit lowest digit: one flip per pair of samples
        const uint64_t* h = m_level_hash.data();
        for (int k = lo >> 1; k < hi >> 1; ++k)
            or_bytes(low + 2 * k, uint16_t(binary_flip(h[k], key) ? 0x0001 : 0x0100));
    }
}

namespace {

/// out[j] = sobol_1d_float(base ^ low[j], r, seed): the randomized Sobol dimension 0, for j in
/// [lo, hi), multiples of 8.
void randomized_dim0(uint32_t base, const uint8_t* low, float* out, int lo, int hi, Randomization r,
                     uint32_t seed) {
#if defined(SR_SOBOL_AVX2)
    const __m256i b = _mm256_set1_epi32(int32_t(base));
    for (int j = lo; j < hi; j += 8) {
        __m256i a =
            _mm256_cvtepu8_epi32(_mm_loadl_epi64(reinterpret_cast<const __m128i*>(low + j)));
        _mm256_storeu_ps(out + j, detail::sobol_1d_float_epi32x8(_mm256_xor_si256(a, b), r, seed));
    }
#else
    for (int j = lo; j < hi; ++j) out[j] = sobol_1d_float(base ^ low[j], r, seed);
#endif
}

}  // namespace

[[gnu::noinline]] void ZSobolSampler::build_table(int slot, bool need_y) {
    // Slot 2 (get_pixel_1d): Sobol dimension 2 of dimension 0's index.
    const int d = slot == 2 ? 0 : slot;
    const auto i = std::size_t(d);
    if (!((m_prefix_valid >> d) & 1)) fill_pixel_dimension(d);
    if (!m_level_hashes_valid) fill_level_hashes();
    alignas(32) uint8_t low[256];
    table_sample_digits(d, low);
    const int lo = m_table_lo, hi = m_table_hi;
    const std::size_t base = std::size_t(slot) << m_log2_spp;
    const uint64_t bit = uint64_t(1) << slot;
    // The index is prefix | low with no prefix bits below 2^m; the Sobol dimension-1 and -2
    // digits are linear over GF(2) and map the bits below 2^8 to bits below 2^8, so those of
    // the index are the prefix's (memoized) XOR those of low, from byte tables.
    alignas(32) uint8_t mapped[256];
    if (!(m_table_valid_x & bit)) {
        if (slot == 2) {
            for (int j = lo; j < hi; ++j) mapped[j] = uint8_t(kSobolDim2Bytes[0][low[j]]);
            randomized_dim0(sobol_dim2_digits(uint32_t(m_prefix[0])), mapped,
                            m_table_x.data() + base, lo, hi, m_randomize,
                            uint32_t(m_scramble_key[2]));
        } else {
            randomized_dim0(uint32_t(m_prefix[i]), low, m_table_x.data() + base, lo, hi,
                            m_randomize, uint32_t(m_scramble_key[i]));
        }
        m_table_valid_x |= bit;
    }
    if (need_y && !(m_table_valid_y & bit)) {
        // value_2d's second coordinate: dimension-1 digits, scrambled with the key's high half.
        // pascal_mod2_transform of 8 bytes at once: no step moves a bit across a byte.
        for (int j = lo; j < hi; j += 8) {
            uint64_t a;
            std::memcpy(&a, low + j, 8);
            a ^= (a >> 1) & 0x5555555555555555ULL;
            a ^= (a >> 2) & 0x3333333333333333ULL;
            a ^= (a >> 4) & 0x0f0f0f0f0f0f0f0fULL;
            std::memcpy(mapped + j, &a, 8);
        }
        randomized_dim0(m_prefix_pascal[i], mapped, m_table_y.data() + base, lo, hi, m_randomize,
                        uint32_t(m_scramble_key[i] >> 32));
        m_table_valid_y |= bit;
    }
}

// Per-node random permutation of the four quadrants (Ahmed & Wonka 2020, Sec. 4: a nested,
// Owen-style shuffle of the Morton index in base 4), chosen from the node's hash and the
// dimension's key; above the hashed levels, XOR with a per-dimension constant (also nested:
// it maps aligned blocks onto aligned blocks).

uint64_t ZSobolSampler::pixel_digits(uint64_t dim_key, uint64_t dim_xor) const {
    int odd = m_log2_spp & 1;
    uint64_t result = m_index_high_bits | ((m_pixel_index & m_xor_mask) ^ dim_xor);
    for (int i = m_num_sample_digits; i < m_hashed_digits_end; ++i) {
        int shift = 2 * i - odd;
        std::size_t digit = (m_pixel_index >> shift) & 3;
        std::size_t perm = base4_permutation(m_node_hash[std::size_t(i)], dim_key);
        result |= uint64_t(kBase4Permutations[perm][digit]) << shift;
    }
    return result;
}

uint8_t ZSobolSampler::top_sample_choice(uint64_t dim_key) const {
    int top = m_num_sample_digits - 1;
    if (top < 0) return 0;
    if ((m_log2_spp & 1) && top == 0) return uint8_t(binary_flip(m_node_hash[0], dim_key));
    return uint8_t(base4_permutation(m_node_hash[std::size_t(top)], dim_key));
}

template <int kLog2Spp>
uint64_t ZSobolSampler::sample_digits(uint64_t dim_key, uint8_t top_choice) const {
    if constexpr (kLog2Spp == 0) {
        return 0;
    } else {
        const int m = kLog2Spp > 0 ? kLog2Spp : m_log2_spp;
        const int odd = m & 1, top = (m + 1) / 2 - 1;
        if (top < 0) return 0;
        uint64_t result;
        if (odd && top == 0) {
            result = (m_morton_index & 1) ^ top_choice;
        } else {
            result = uint64_t(m_sample_column[std::size_t(top)][top_choice]) << (2 * top - odd);
            if (odd) result |= (m_morton_index & 1) ^ binary_flip(m_node_hash[0], dim_key);
        }
        for (int i = odd; i < top; ++i) {
            std::size_t perm = base4_permutation(m_node_hash[std::size_t(i)], dim_key);
            result |= uint64_t(m_sample_column[std::size_t(i)][perm]) << (2 * i - odd);
        }
        return result;
    }
}

uint64_t ZSobolSampler::sobol_index(int dimension) {
    if (!m_sample_nodes_valid) compute_sample_nodes();
    uint64_t key = dimension_key(dimension);
    return pixel_digits(key, dimension_xor(key)) | sample_digits<-1>(key, top_sample_choice(key));
}

void ZSobolSampler::fill_pixel_dimension(int d) {
    auto i = std::size_t(d);
    uint64_t key = m_dim_key[i];
    m_prefix[i] = pixel_digits(key, dimension_xor(key));
    m_prefix_pascal[i] = uint32_t(pascal_mod2_transform(m_prefix[i]));
    m_top_choice[i] = top_sample_choice(key);
    m_prefix_valid |= uint64_t(1) << d;
}

// The hot paths make no calls but tail calls (the first use of a dimension in a pixel goes
// through a separate function that fills and then evaluates), so they need no stack frame.
// They are instantiated per log2(samples per pixel) <= 8, so that the sample digit loop is
// unrolled, and selected once by the constructor.

template <int kLog2Spp>
Float ZSobolSampler::get_1d_impl(ZSobolSampler& s, int d) {
    if (!((s.m_prefix_valid >> d) & 1)) [[unlikely]]
        return fill_and_get_1d<kLog2Spp>(s, d);
    return s.value_1d<kLog2Spp>(d);
}

template <int kLog2Spp>
[[gnu::noinline]] Float ZSobolSampler::fill_and_get_1d(ZSobolSampler& s, int d) {
    s.fill_pixel_dimension(d);
    return s.value_1d<kLog2Spp>(d);
}

template <int kLog2Spp>
[[gnu::always_inline]] inline Float ZSobolSampler::value_1d(int d) const {
    auto i = std::size_t(d);
    uint64_t a = m_prefix[i] | sample_digits<kLog2Spp>(m_dim_key[i], m_top_choice[i]);
    return sobol_1d_float(uint32_t(a), m_randomize, uint32_t(m_scramble_key[std::size_t(d)]));
}

template <int kLog2Spp>
Point2 ZSobolSampler::sample_2d_impl(ZSobolSampler& s, int d) {
    if (!((s.m_prefix_valid >> d) & 1)) [[unlikely]]
        return fill_and_sample_2d<kLog2Spp>(s, d);
    return s.value_2d<kLog2Spp>(d);
}

template <int kLog2Spp>
[[gnu::noinline]] Point2 ZSobolSampler::fill_and_sample_2d(ZSobolSampler& s, int d) {
    s.fill_pixel_dimension(d);
    return s.value_2d<kLog2Spp>(d);
}

template <int kLog2Spp>
[[gnu::always_inline]] inline Point2 ZSobolSampler::value_2d(int d) const {
    auto i = std::size_t(d);
    uint64_t low = sample_digits<kLog2Spp>(m_dim_key[i], m_top_choice[i]);
    uint64_t a = m_prefix[i] | low;
    // Dimension-1 digits: the memoized ones of the pixel digits and those of the sample digits.
    uint32_t y_digits = m_prefix_pascal[i];
    if constexpr (kLog2Spp >= 0 && kLog2Spp <= 8)
        y_digits ^= kPascal8[std::size_t(low)];
    else
        y_digits ^= uint32_t(pascal_mod2_transform(low));
    return sobol_2d_float(uint32_t(a), y_digits, m_randomize, m_scramble_key[i]);
}

template <int kLog2Spp>
Float ZSobolSampler::pixel_1d_impl(ZSobolSampler& s, int) {
    if (!(s.m_prefix_valid & 1)) s.fill_pixel_dimension(0);
    uint64_t a = s.m_prefix[0] | s.sample_digits<kLog2Spp>(s.m_dim_key[0], s.m_top_choice[0]);
    return sobol_1d_float(sobol_dim2_digits(uint32_t(a)), s.m_randomize,
                          uint32_t(s.m_scramble_key[2]));
}

void ZSobolSampler::select_kernels() {
    switch (m_log2_spp) {
#define SR_ZSOBOL_CASE(m)                    \
    case m:                                  \
        m_get_1d_fn = &get_1d_impl<m>;       \
        m_sample_2d_fn = &sample_2d_impl<m>; \
        m_pixel_1d_fn = &pixel_1d_impl<m>;   \
        return;
        SR_ZSOBOL_CASE(0)
        SR_ZSOBOL_CASE(1)
        SR_ZSOBOL_CASE(2)
        SR_ZSOBOL_CASE(3)
        SR_ZSOBOL_CASE(4)
        SR_ZSOBOL_CASE(5)
        SR_ZSOBOL_CASE(6)
        SR_ZSOBOL_CASE(7)
        SR_ZSOBOL_CASE(8)
#undef SR_ZSOBOL_CASE
        default:
            m_get_1d_fn = &get_1d_impl<-1>;
            m_sample_2d_fn = &sample_2d_impl<-1>;
            m_pixel_1d_fn = &pixel_1d_impl<-1>;
    }
}

// get_1d() and get_2d() serve a filled table entry without a stack frame; everything else
// (filling a table, the memoized per-sample path, hashed dimensions) is a tail call.
Float ZSobolSampler::get_1d() {
    int d = m_dimension;
    if (use_table(d) && ((m_table_valid_x >> d) & 1)) {
        m_dimension = d + 1;
        return m_table_x[table_index(d)];
    }
    return get_1d_slow();
}

[[gnu::noinline]] Float ZSobolSampler::get_1d_slow() {
    int d = m_dimension++;
    if (use_table(d)) {
        build_table(d, false);
        return m_table_x[table_index(d)];
    }
    if (!m_sample_nodes_valid) [[unlikely]]
        compute_sample_nodes();
    if (d >= kLowDiscrepancyDimensions) [[unlikely]]
        return hashed_1d(m_sample_key, d);
    return m_get_1d_fn(*this, d);
}

Point2 ZSobolSampler::get_2d() {
    int d = m_dimension;
    if (use_table(d) && ((m_table_valid_y >> d) & 1)) {
        m_dimension = d + 2;
        return {m_table_x[table_index(d)], m_table_y[table_index(d)]};
    }
    return get_2d_slow();
}

[[gnu::noinline]] Point2 ZSobolSampler::get_2d_slow() {
    Point2 p = sample_2d(m_dimension);
    m_dimension += 2;
    return p;
}

Point2 ZSobolSampler::sample_2d(int d) {
    if (use_table(d)) return table_2d(d);
    if (!m_sample_nodes_valid) [[unlikely]]
        compute_sample_nodes();
    if (d >= kLowDiscrepancyDimensions) [[unlikely]]
        return hashed_2d(m_sample_key, d);
    return m_sample_2d_fn(*this, d);
}

Float ZSobolSampler::get_pixel_1d() {
    if (m_table_sample) {
        if (!((m_table_valid_x >> 2) & 1)) [[unlikely]]
            build_table(2, false);
        return m_table_x[table_index(2)];
    }
    if (!m_sample_nodes_valid) [[unlikely]]
        compute_sample_nodes();
    return m_pixel_1d_fn(*this, 0);
}

std::unique_ptr<Sampler> ZSobolSampler::clone() const {
    return std::make_unique<ZSobolSampler>(*this);
}

}  // namespace sr
