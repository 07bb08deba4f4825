#pragma once
/// The two-dimensional Sobol (0,2)-sequence in base 2, Morton codes, and the scramblings
/// (randomizations) used by the Sobol-type samplers.
///
/// A point of a digital sequence is x_d(a) = C_d * a over GF(2): the bits of the index a
/// (least significant first) multiplied by the generator matrix C_d give the binary digits of
/// x_d (most significant first). The first two Sobol dimensions (Sobol 1967) are
///   C_0 = identity (the van der Corput radical inverse: bit reversal),
///   C_1 = upper-triangular Pascal matrix mod 2, C_1[i][j] = binom(j, i) mod 2,
/// and together form a (0,2)-sequence: every aligned block of 2^m consecutive indices is a
/// (0,m,2)-net, i.e. each elementary interval [a 2^-p, (a+1) 2^-p) x [b 2^-q, (b+1) 2^-q) with
/// p + q = m holds exactly one point (Niederreiter 1992, "Random Number Generation and
/// Quasi-Monte Carlo Methods", Ch. 4).
#include <array>
#include <bit>
#include <cstdint>
#include <string>

#if defined(__SSE4_1__) && defined(__SSSE3__) && defined(__x86_64__)
#include <smmintrin.h>
#define SR_SOBOL_SSE4 1
#if defined(__AVX2__)
#include <immintrin.h>
#define SR_SOBOL_AVX2 1
#endif
#endif

#include "steradian/core/math.h"
#include "steradian/sampling/hash.h"
#include "steradian/sampling/rng.h"

namespace sr {

/// Dimension 0 of the Sobol sequence as 0.32 fixed point: the radical inverse in base 2 of
/// the low 32 bits of a (higher bits would only reach digits beyond 2^-32).
constexpr uint32_t sobol_u32_dim0(uint64_t a) { return reverse_bits32(uint32_t(a)); }

/// Applies the Pascal matrix mod 2, y_i = XOR_j [binom(j, i) odd] a_j, to the 64 bits of a
/// (bit i of the result is output digit i). Uses the Sierpinski block structure
/// P_{2n} = [[P_n, P_n], [0, P_n]] (Lucas: binom(j, i) is odd iff i is a submask of j), so
/// P is a product of six "fold the upper half of each block onto the lower half" steps,
/// which commute: y ^= (y >> s) & mask_s for s = 1, 2, ..., 32.
constexpr uint64_t pascal_mod2_transform(uint64_t a) {
    a ^= (a >> 1) & 0x5555555555555555ULL;
    a ^= (a >> 2) & 0x3333333333333333ULL;
    a ^= (a >> 4) & 0x0f0f0f0f0f0f0f0fULL;
    a ^= (a >> 8) & 0x00ff00ff00ff00ffULL;
    a ^= (a >> 16) & 0x0000ffff0000ffffULL;
    a ^= (a >> 32) & 0x00000000ffffffffULL;
    return a;
}

/// Dimension 1 of the Sobol sequence (generator matrix: Pascal's triangle mod 2) as 0.32
/// fixed point: output digit i (weight 2^-(i+1)) goes to bit 31 - i.
constexpr uint32_t sobol_u32_dim1(uint64_t a) {
    return reverse_bits32(uint32_t(pascal_mod2_transform(a)));
}

/// Dimension 2 of the Sobol sequence: primitive polynomial x^2 + x + 1 (degree s = 2,
/// coefficient a_1 = 1) with initial direction integers m_1 = 1, m_2 = 3 (Sobol 1967; the
/// values of Joe & Kuo 2008, "Constructing Sobol sequences with better two-dimensional
/// projections", SIAM J. Sci. Comput. 30(5), table file new-joe-kuo-6.21201, d = 3), and
/// Bratley & Fox's recurrence m_k = 2 a_1 m_{k-1} ^ 4 m_{k-2} ^ m_{k-2}. Dimensions 0, 1
/// and 2 together form a (1,3)-sequence in base 2 (Sobol's bound: t <= sum of (degree - 1)
/// over the polynomials x, x + 1, x^2 + x + 1): every aligned block of 2^m indices is a
/// (1,m,3)-net, each elementary box of volume 2^(1-m) holding exactly two points.
/// kSobolDim2Columns[j] is the image of index bit j in the digit convention of
/// pascal_mod2_transform (bit i = output digit i, of weight 2^-(i+1)).
constexpr std::array<uint32_t, 32> make_sobol_dim2_columns() {
    std::array<uint64_t, 33> m{};
    m[1] = 1;
    m[2] = 3;
    for (int k = 3; k <= 32; ++k) m[k] = (2 * m[k - 1]) ^ (4 * m[k - 2]) ^ m[k - 2];
    std::array<uint32_t, 32> columns{};
    for (int j = 0; j < 32; ++j) {
        // v_{j+1} = m_{j+1} / 2^(j+1) as 0.32 fixed point, then reversed into digit order.
        uint32_t fixed = uint32_t(m[std::size_t(j + 1)] << (31 - j));
        uint32_t digits = 0;
        for (int i = 0; i < 32; ++i) digits |= ((fixed >> (31 - i)) & 1u) << i;
        columns[std::size_t(j)] = digits;
    }
    return columns;
}
inline constexpr std::array<uint32_t, 32> kSobolDim2Columns = make_sobol_dim2_columns();

/// The products of kSobolDim2Columns with each byte of an index (4 tables of 256).
constexpr std::array<std::array<uint32_t, 256>, 4> make_sobol_dim2_bytes() {
    std::array<std::array<uint32_t, 256>, 4> t{};
    for (std::size_t b = 0; b < 4; ++b)
        for (std::size_t v = 0; v < 256; ++v) {
            uint32_t r = 0;
            for (std::size_t j = 0; j < 8; ++j)
                if ((v >> j) & 1) r ^= kSobolDim2Columns[8 * b + j];
            t[b][v] = r;
        }
    return t;
}
inline constexpr std::array<std::array<uint32_t, 256>, 4> kSobolDim2Bytes = make_sobol_dim2_bytes();

/// The Sobol dimension-2 digits of the low 32 bits of a (bit i = digit i, as
/// pascal_mod2_transform); linear over GF(2) in a.
constexpr uint32_t sobol_dim2_digits(uint32_t a) {
    return kSobolDim2Bytes[0][a & 0xff] ^ kSobolDim2Bytes[1][(a >> 8) & 0xff] ^
           kSobolDim2Bytes[2][(a >> 16) & 0xff] ^ kSobolDim2Bytes[3][a >> 24];
}

/// Dimension 2 of the Sobol sequence as 0.32 fixed point.
constexpr uint32_t sobol_u32_dim2(uint64_t a) {
    return reverse_bits32(sobol_dim2_digits(uint32_t(a)));
}

/// Spreads the 32 bits of v to the even bit positions of a 64-bit word.
constexpr uint64_t spread_bits_2(uint32_t v) {
    uint64_t x = v;
    x = (x | (x << 16)) & 0x0000ffff0000ffffULL;
    x = (x | (x << 8)) & 0x00ff00ff00ff00ffULL;
    x = (x | (x << 4)) & 0x0f0f0f0f0f0f0f0fULL;
    x = (x | (x << 2)) & 0x3333333333333333ULL;
    x = (x | (x << 1)) & 0x5555555555555555ULL;
    return x;
}

/// Morton (Z-order) code: bits of x at even positions, bits of y at odd positions, so base-4
/// digit k of the code is the 2x2 quadrant of (x, y) at level k of a quadtree.
constexpr uint64_t encode_morton2(uint32_t x, uint32_t y) {
    return spread_bits_2(x) | (spread_bits_2(y) << 1);
}

/// How a (0,2)-sequence point is randomized. All three keep the (0,m,2)-net property.
enum class Randomization {
    kNone,  ///< plain Sobol points
    kXor,   ///< random digit scrambling: XOR with a per-dimension constant (pbrt "permutedigits")
    kOwen,  ///< hash-based Owen scrambling, Burley 2020 (pbrt "fastowen" and "owen")
};

/// Parses pbrt-v4's randomization names: "none", "permutedigits", "fastowen", "owen" (the last
/// two both give kOwen). Throws sr::Error for anything else.
Randomization randomization_from_string(const std::string& name);
std::string to_string(Randomization r);

/// Applies the randomization to a 0.32 fixed-point value.
constexpr uint32_t randomize(uint32_t v, Randomization r, uint32_t seed) {
    switch (r) {
        case Randomization::kNone:
            return v;
        case Randomization::kXor:
            return v ^ seed;
        case Randomization::kOwen:
            return owen_scramble(v, seed);
    }
    return v;
}

// ---- Randomized points as Floats (the samplers' inner loop) ------------------------------------

#if defined(SR_SOBOL_SSE4)
namespace detail {

// The lookup tables of reverse_bits_epi32: reversed nibble n placed in the high or low half of
// a byte, and the byte reversal of each 32-bit lane.
inline __m128i nibble_reversed_high() {
    return _mm_setr_epi8(0x00, char(0x80), 0x40, char(0xc0), 0x20, char(0xa0), 0x60, char(0xe0),
                         0x10, char(0x90), 0x50, char(0xd0), 0x30, char(0xb0), 0x70, char(0xf0));
}
inline __m128i nibble_reversed_low() {
    return _mm_setr_epi8(0x0, 0x8, 0x4, 0xc, 0x2, 0xa, 0x6, 0xe, 0x1, 0x9, 0x5, 0xd, 0x3, 0xb, 0x7,
                         0xf);
}
inline __m128i byte_swap_epi32() {
    return _mm_setr_epi8(3, 2, 1, 0, 7, 6, 5, 4, 11, 10, 9, 8, 15, 14, 13, 12);
}

/// reverse_bits32 of each 32-bit lane: a byte swap and two 16-entry nibble-reversal lookups.
inline __m128i reverse_bits_epi32(__m128i v) {
    const __m128i nibble = _mm_set1_epi8(0x0f);
    v = _mm_shuffle_epi8(v, byte_swap_epi32());
    __m128i lo = _mm_and_si128(v, nibble);
    __m128i hi = _mm_and_si128(_mm_srli_epi16(v, 4), nibble);
    return _mm_or_si128(_mm_shuffle_epi8(nibble_reversed_high(), lo),
                        _mm_shuffle_epi8(nibble_reversed_low(), hi));
}

/// laine_karras_permutation of each 32-bit lane with that lane's seed.
inline __m128i laine_karras_epi32(__m128i x, __m128i seed) {
    __m128i mul = _mm_or_si128(_mm_srli_epi32(seed, 16), _mm_set1_epi32(1));
    x = _mm_xor_si128(x, _mm_mullo_epi32(x, _mm_set1_epi32(int32_t(kLaineKarrasMul[0]))));
    x = _mm_add_epi32(x, seed);
    x = _mm_mullo_epi32(x, mul);
    x = _mm_xor_si128(x, _mm_mullo_epi32(x, _mm_set1_epi32(int32_t(kLaineKarrasMul[1]))));
    x = _mm_xor_si128(x, _mm_mullo_epi32(x, _mm_set1_epi32(int32_t(kLaineKarrasMul[2]))));
    return x;
}

/// u32_to_unit_float of lanes 0 and 1: exact unsigned -> double conversion (sign flip, signed
/// conversion, + 2^31), truncation to 24 significant bits, exact double -> float.
inline __m128 unit_float_epi32x2(__m128i v) {
    __m128d d = _mm_cvtepi32_pd(_mm_xor_si128(v, _mm_set1_epi32(int32_t(0x80000000u))));
    d = _mm_add_pd(d, _mm_set1_pd(2147483648.0));
    d = _mm_and_pd(d, _mm_castsi128_pd(_mm_set1_epi64x(~int64_t(0x1fffffff))));
    return _mm_cvtpd_ps(_mm_mul_pd(d, _mm_set1_pd(0x1p-32)));  // exact: a power of two
}

/// Lanes 0 and 1 as a Point2 (which is returned in the low half of a register anyway).
inline Point2 to_point2(__m128 f) {
    static_assert(sizeof(Point2) == 8);
    return std::bit_cast<Point2>(_mm_cvtsi128_si64(_mm_castps_si128(f)));
}

#if defined(SR_SOBOL_AVX2)
/// reverse_bits_epi32 of 8 lanes.
inline __m256i reverse_bits_epi32(__m256i v) {
    const __m256i nibble = _mm256_set1_epi8(0x0f);
    v = _mm256_shuffle_epi8(v, _mm256_broadcastsi128_si256(byte_swap_epi32()));
    __m256i lo = _mm256_and_si256(v, nibble);
    __m256i hi = _mm256_and_si256(_mm256_srli_epi16(v, 4), nibble);
    return _mm256_or_si256(
        _mm256_shuffle_epi8(_mm256_broadcastsi128_si256(nibble_reversed_high()), lo),
        _mm256_shuffle_epi8(_mm256_broadcastsi128_si256(nibble_reversed_low()), hi));
}

/// laine_karras_epi32 of 8 lanes.
inline __m256i laine_karras_epi32(__m256i x, __m256i seed) {
    __m256i mul = _mm256_or_si256(_mm256_srli_epi32(seed, 16), _mm256_set1_epi32(1));
    x = _mm256_xor_si256(x, _mm256_mullo_epi32(x, _mm256_set1_epi32(int32_t(kLaineKarrasMul[0]))));
    x = _mm256_add_epi32(x, seed);
    x = _mm256_mullo_epi32(x, mul);
    x = _mm256_xor_si256(x, _mm256_mullo_epi32(x, _mm256_set1_epi32(int32_t(kLaineKarrasMul[1]))));
    x = _mm256_xor_si256(x, _mm256_mullo_epi32(x, _mm256_set1_epi32(int32_t(kLaineKarrasMul[2]))));
    return x;
}

/// u32_to_unit_float of 8 lanes, as unit_float_epi32x2 with 4 lanes per double vector.
inline __m256 unit_float_epi32x8(__m256i v) {
    v = _mm256_xor_si256(v, _mm256_set1_epi32(int32_t(0x80000000u)));
    const __m256d two31 = _mm256_set1_pd(2147483648.0);
    const __m256d mask = _mm256_castsi256_pd(_mm256_set1_epi64x(~int64_t(0x1fffffff)));
    const __m256d scale = _mm256_set1_pd(0x1p-32);
    __m256d d0 = _mm256_add_pd(_mm256_cvtepi32_pd(_mm256_castsi256_si128(v)), two31);
    __m256d d1 = _mm256_add_pd(_mm256_cvtepi32_pd(_mm256_extracti128_si256(v, 1)), two31);
    __m128 f0 = _mm256_cvtpd_ps(_mm256_mul_pd(_mm256_and_pd(d0, mask), scale));
    __m128 f1 = _mm256_cvtpd_ps(_mm256_mul_pd(_mm256_and_pd(d1, mask), scale));
    return _mm256_set_m128(f1, f0);
}

/// sobol_1d_float of the 8 lanes of a, with one seed.
inline __m256 sobol_1d_float_epi32x8(__m256i a, Randomization r, uint32_t seed) {
    const __m256i s = _mm256_set1_epi32(int32_t(seed));
    if (r == Randomization::kOwen) a = laine_karras_epi32(a, s);
    a = reverse_bits_epi32(a);
    if (r == Randomization::kXor) a = _mm256_xor_si256(a, s);
    return unit_float_epi32x8(a);
}
#endif

/// sobol_2d_float with (a, y_digits) in lanes 0 and 1 of v.
inline Point2 sobol_2d_float_epi32(__m128i v, Randomization r, uint64_t key) {
    __m128i k = _mm_cvtsi64_si128(int64_t(key));
    if (r == Randomization::kOwen) v = laine_karras_epi32(v, k);
    v = reverse_bits_epi32(v);
    if (r == Randomization::kXor) v = _mm_xor_si128(v, k);
    return to_point2(unit_float_epi32x2(v));
}

}  // namespace detail
#endif

/// u32_to_unit_float(randomize(sobol_u32_dim0(a), r, seed)) with a single bit reversal (Owen
/// scrambling of the radical inverse is the reversal of a Laine-Karras permutation of a); the
/// reversal and conversion on an SSE register where available (fewer instructions).
inline Float sobol_1d_float(uint32_t a, Randomization r, uint32_t seed) {
    if (r == Randomization::kOwen) a = laine_karras_permutation(a, seed);
#if defined(SR_SOBOL_SSE4)
    __m128i v = detail::reverse_bits_epi32(_mm_cvtsi32_si128(int32_t(a)));
    if (r == Randomization::kXor) v = _mm_xor_si128(v, _mm_cvtsi32_si128(int32_t(seed)));
    return _mm_cvtss_f32(detail::unit_float_epi32x2(v));
#else
    uint32_t v = reverse_bits32(a);
    if (r == Randomization::kXor) v ^= seed;
    return u32_to_unit_float(v);
#endif
}

/// {u32_to_unit_float(randomize(sobol_u32_dim0(a), r, uint32_t(key))),
///  u32_to_unit_float(randomize(sobol_u32_dim1(a), r, uint32_t(key >> 32)))}, given the low 32
/// bits of a and y_digits = uint32_t(pascal_mod2_transform(a)) (which depends on all of a).
/// Both coordinates are scrambled, reversed and converted together (SSE4.1 lanes where
/// available, one 64-bit reversal otherwise).
inline Point2 sobol_2d_float(uint32_t a, uint32_t y_digits, Randomization r, uint64_t key) {
#if defined(SR_SOBOL_SSE4)
    return detail::sobol_2d_float_epi32(_mm_cvtsi64_si128(int64_t((uint64_t(y_digits) << 32) | a)),
                                        r, key);
#else
    uint32_t x = a, y = y_digits;
    if (r == Randomization::kOwen) {
        x = laine_karras_permutation(x, uint32_t(key));
        y = laine_karras_permutation(y, uint32_t(key >> 32));
    }
    uint64_t v = reverse_bits64((uint64_t(x) << 32) | y);  // low half: x reversed, high: y
    if (r == Randomization::kXor) v ^= key;
    return {u32_to_unit_float(uint32_t(v)), u32_to_unit_float(uint32_t(v >> 32))};
#endif
}

}  // namespace sr
