#pragma once
/// PCG32 pseudo-random number generator (O'Neill 2014, "PCG: A Family of Simple Fast
/// Space-Efficient Statistically Good Algorithms for Random Number Generation", HMC-CS-2014-0905;
/// the "PCG XSH RR 64/32" member, pcg-random.org). A 64-bit LCG state with 2^63 selectable
/// streams and a permuted 32-bit output. Jump-ahead by Brown (1994), "Random Number Generation
/// with Arbitrary Strides", Trans. Am. Nucl. Soc. 71.
#include <bit>
#include <cstdint>
#if defined(__SSE2__) && defined(__x86_64__)
#include <emmintrin.h>
#endif

#include "steradian/core/error.h"
#include "steradian/core/math.h"

namespace sr {

/// Converts 32 random bits to a Float in [0, 1) by truncation (round toward zero) of
/// v * 2^-32. Truncation keeps every dyadic interval [k 2^-j, (k+1) 2^-j), j <= 24, closed
/// under the conversion (rounding to nearest would push values just below a boundary onto
/// it), so stratified and (0,m,2)-net integers stay stratified as floats, and the largest
/// result is kOneMinusEpsilon: 1 is never returned.
inline Float u32_to_unit_float(uint32_t v) {
    // double(v) is exact; clearing the low 29 of its 52 mantissa bits truncates it to 24
    // significant bits, which the double -> float conversion then keeps exactly (branch-free;
    // equal to masking v below its 24 most significant set bits, checked for all 2^32 inputs).
    constexpr uint64_t kMask = ~uint64_t(0x1fffffff);
#if defined(__SSE2__) && defined(__x86_64__)
    // The same on the SIMD registers: no round trip through an integer register (shorter
    // latency; the samplers call this on every dimension).
    __m128d d = _mm_cvtsi64_sd(_mm_setzero_pd(), int64_t(v));
    d = _mm_and_pd(d, _mm_castsi128_pd(_mm_set1_epi64x(int64_t(kMask))));
    return Float(_mm_cvtss_f32(_mm_cvtsd_ss(_mm_setzero_ps(), d))) * 0x1p-32f;
#else
    uint64_t bits = std::bit_cast<uint64_t>(double(v)) & kMask;
    return Float(std::bit_cast<double>(bits)) * 0x1p-32f;
#endif
}

class Pcg32 {
  public:
    static constexpr uint64_t kDefaultState = 0x853c49e6748fea9bULL;
    static constexpr uint64_t kDefaultStream = 0xda3e39cb94b95bdbULL;
    static constexpr uint64_t kMultiplier = 0x5851f42d4c957f2dULL;

    /// The reference generator's default state and stream.
    Pcg32() = default;
    /// Stream seq_index (its top bit is ignored: 2^63 streams), starting state derived from
    /// seed, as pcg32_srandom_r(seed, seq_index) of the reference implementation.
    Pcg32(uint64_t seq_index, uint64_t seed) { set_sequence(seq_index, seed); }
    /// Stream seq_index with a starting state derived from seq_index itself.
    explicit Pcg32(uint64_t seq_index) { set_sequence(seq_index); }

    /// Selects stream seq_index and the starting position derived from seed.
    void set_sequence(uint64_t seq_index, uint64_t seed) {
        m_state = 0;
        m_inc = (seq_index << 1) | 1;
        next_u32();
        m_state += seed;
        next_u32();
    }
    /// Selects stream seq_index; the seed is a 64-bit mix of seq_index (splitmix64 finalizer).
    void set_sequence(uint64_t seq_index) { set_sequence(seq_index, seed_from(seq_index)); }

    /// Uniform 32-bit integer; advances the state by one step.
    uint32_t next_u32() {
        uint64_t old = m_state;
        m_state = old * kMultiplier + m_inc;
        auto xorshifted = uint32_t(((old >> 18) ^ old) >> 27);
        auto rot = uint32_t(old >> 59);
        return (xorshifted >> rot) | (xorshifted << ((32 - rot) & 31));
    }

    /// Unbiased uniform integer in [0, bound), bound > 0 (Lemire 2019, "Fast Random Integer
    /// Generation in an Interval", ACM TOMACS 29(1): multiply-shift with rejection of the
    /// 2^32 mod bound short values). Consumes one or (rarely) more steps.
    uint32_t next_u32(uint32_t bound) {
        SR_DCHECK(bound > 0);
        uint64_t m = uint64_t(next_u32()) * bound;
        auto low = uint32_t(m);
        if (low < bound) {
            uint32_t threshold = (0u - bound) % bound;
            while (low < threshold) {
                m = uint64_t(next_u32()) * bound;
                low = uint32_t(m);
            }
        }
        return uint32_t(m >> 32);
    }

    /// Uniform Float in [0, 1) from one step; never 1 (at most kOneMinusEpsilon).
    Float next_float() { return u32_to_unit_float(next_u32()); }

    /// Uniform double in [0, 1) with 53 random bits; consumes two steps; never 1.
    double next_double() {
        uint64_t hi = next_u32();
        uint64_t lo = next_u32();
        return double(((hi << 32) | lo) >> 11) * 0x1p-53;
    }

    /// Moves the state by delta steps (negative: backwards; the period is 2^64) in
    /// O(log |delta|) (Brown 1994): the affine LCG step x -> a x + c composed with itself
    /// by repeated squaring.
    void advance(int64_t delta) {
        uint64_t cur_mult = kMultiplier, cur_plus = m_inc;
        uint64_t acc_mult = 1, acc_plus = 0;
        // Two's complement: stepping 2^64 - |delta| forward is stepping |delta| backward.
        auto d = uint64_t(delta);
        while (d > 0) {
            if (d & 1) {
                acc_mult *= cur_mult;
                acc_plus = acc_plus * cur_mult + cur_plus;
            }
            cur_plus = (cur_mult + 1) * cur_plus;
            cur_mult *= cur_mult;
            d >>= 1;
        }
        m_state = acc_mult * m_state + acc_plus;
    }

    /// Number of steps from `other` to *this (both must be on the same stream): the unique
    /// d in [-2^63, 2^63) with other.advance(d) == *this. Found bit by bit from the lowest,
    /// since the low k bits of an LCG state only depend on the low k bits of the previous one.
    int64_t operator-(const Pcg32& other) const {
        SR_DCHECK(m_inc == other.m_inc);
        uint64_t cur_mult = kMultiplier, cur_plus = m_inc;
        uint64_t cur_state = other.m_state, bit = 1, distance = 0;
        while (m_state != cur_state) {
            if ((m_state & bit) != (cur_state & bit)) {
                cur_state = cur_state * cur_mult + cur_plus;
                distance |= bit;
            }
            cur_plus = (cur_mult + 1) * cur_plus;
            cur_mult *= cur_mult;
            bit <<= 1;
        }
        return int64_t(distance);
    }

    bool operator==(const Pcg32&) const = default;

  private:
    // splitmix64 finalizer (kept local so rng.h does not depend on hash.h).
    static constexpr uint64_t seed_from(uint64_t v) {
        v ^= v >> 30;
        v *= 0xbf58476d1ce4e5b9ULL;
        v ^= v >> 27;
        v *= 0x94d049bb133111ebULL;
        v ^= v >> 31;
        return v;
    }

    uint64_t m_state = kDefaultState;
    uint64_t m_inc = kDefaultStream;
};

}  // namespace sr
