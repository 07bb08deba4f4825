#pragma once
/// Integer hashing for deterministic sampling: 64-bit finalizer, byte hashing of small
/// trivially-copyable tuples, hash-based permutations and hash-based Owen scrambling.
/// Every sample in steradian is a pure function of (pixel, sample index, dimension, seed);
/// these functions turn such tuples into decorrelated bits.
#include <cstddef>
#include <cstdint>
#include <cstring>
#include <type_traits>

namespace sr {

/// 2^64 / golden ratio, the Weyl increment of splitmix64.
inline constexpr uint64_t kGolden64 = 0x9e3779b97f4a7c15ULL;

/// Bijective 64-bit finalizer with full avalanche: the splitmix64 output function
/// (Steele, Lea, Flood 2014, "Fast Splittable Pseudorandom Number Generators", OOPSLA),
/// whose constants are Stafford's "Mix13" variant of the MurmurHash3 finalizer
/// (D. Stafford 2011, "Better Bit Mixing - Improving on MurmurHash3's 64-bit Finalizer").
constexpr uint64_t mix_bits(uint64_t v) {
    v ^= v >> 30;
    v *= 0xbf58476d1ce4e5b9ULL;
    v ^= v >> 27;
    v *= 0x94d049bb133111ebULL;
    v ^= v >> 31;
    return v;
}

/// Hash of h extended by v: the splitmix64 output at position v + 1 of a stream started
/// at h. Cheap (one mix) way to derive per-dimension keys from a per-pixel key.
constexpr uint64_t hash_combine(uint64_t h, uint64_t v) {
    return mix_bits(h + kGolden64 * (v + 1));
}

/// MurmurHash64A of len bytes (Austin Appleby, MurmurHash2 family, public domain), reading
/// little-endian 8-byte blocks.
inline uint64_t murmur_hash64a(const unsigned char* key, std::size_t len, uint64_t seed) {
    constexpr uint64_t m = 0xc6a4a7935bd1e995ULL;
    constexpr int r = 47;
    uint64_t h = seed ^ (uint64_t(len) * m);
    std::size_t n_blocks = len / 8;
    for (std::size_t b = 0; b < n_blocks; ++b) {
        uint64_t k;
        std::memcpy(&k, key + 8 * b, 8);
        k *= m;
        k ^= k >> r;
        k *= m;
        h ^= k;
        h *= m;
    }
    const unsigned char* tail = key + 8 * n_blocks;
    std::size_t rest = len & 7;
    if (rest > 0) {
        for (std::size_t i = rest; i-- > 0;) h ^= uint64_t(tail[i]) << (8 * i);
        h *= m;
    }
    h ^= h >> r;
    h *= m;
    h ^= h >> r;
    return h;
}

/// 64-bit hash of the bytes of the arguments, concatenated in order. Arguments must be
/// trivially copyable and should have no padding bytes (Vec2i, integers and floats are fine;
/// note +0.0f and -0.0f hash differently).
template <typename... Args>
uint64_t hash(Args... args) {
    static_assert(sizeof...(Args) > 0, "hash() needs at least one argument");
    static_assert((std::is_trivially_copyable_v<Args> && ...),
                  "hash() arguments must be trivially copyable");
    constexpr std::size_t n = (sizeof(Args) + ...);
    unsigned char buf[n];
    std::size_t offset = 0;
    ((std::memcpy(buf + offset, &args, sizeof(Args)), offset += sizeof(Args)), ...);
    return murmur_hash64a(buf, n, 0);
}

/// The smallest 2^k - 1 >= n - 1 (all bits below the highest set bit of n - 1): the mask of
/// permutation_element's power-of-two range.
constexpr uint32_t permutation_mask(uint32_t n) {
    uint32_t w = n - 1;
    w |= w >> 1;
    w |= w >> 2;
    w |= w >> 4;
    w |= w >> 8;
    w |= w >> 16;
    return w;
}

/// Element i of a pseudo-random permutation of {0, ..., n-1} selected by seed; i < n, and
/// w = permutation_mask(n) (precomputed by callers that use the same n many times).
/// Kensler 2013, "Correlated Multi-Jittered Sampling", Pixar Technical Memo 13-01, Listing 3:
/// a bijective hash on the smallest power-of-two range covering n (xorshifts and odd
/// multiplications restricted to the low bits) with cycle walking back into [0, n).
inline uint32_t permutation_element(uint32_t i, uint32_t n, uint32_t w, uint32_t seed) {
    do {
        i ^= seed;
        i *= 0xe170893du;
        i ^= seed >> 16;
        i ^= (i & w) >> 4;
        i ^= seed >> 8;
        i *= 0x0929eb3fu;
        i ^= seed >> 23;
        i ^= (i & w) >> 1;
        i *= 1u | (seed >> 27);
        i *= 0x6935fa69u;
        i ^= (i & w) >> 11;
        i *= 0x74dcb303u;
        i ^= (i & w) >> 2;
        i *= 0x9e501cc3u;
        i ^= (i & w) >> 2;
        i *= 0xc860a3dfu;
        i &= w;
        i ^= i >> 5;
    } while (i >= n);
    // (i + seed) mod n; a mask when n is a power of two (n == w + 1).
    return n == w + 1 ? (i + seed) & w : (i + seed) % n;
}

/// Element i of a pseudo-random permutation of {0, ..., n-1} selected by seed; i < n.
inline uint32_t permutation_element(uint32_t i, uint32_t n, uint32_t seed) {
    return permutation_element(i, n, permutation_mask(n), seed);
}

/// Bit reversal (bit k goes to bit 31 - k): swaps of adjacent bits, bit pairs and nibbles
/// reverse the bits within each byte, and one byte swap (a single bswap instruction) reverses
/// the bytes: 3 mask-and-shift steps instead of 5.
constexpr uint32_t reverse_bits32(uint32_t v) {
    v = ((v >> 1) & 0x55555555u) | ((v & 0x55555555u) << 1);
    v = ((v >> 2) & 0x33333333u) | ((v & 0x33333333u) << 2);
    v = ((v >> 4) & 0x0f0f0f0fu) | ((v & 0x0f0f0f0fu) << 4);
    return __builtin_bswap32(v);
}

/// 64-bit bit reversal, the same way; reverses two 32-bit values at once as well:
/// reverse_bits64((uint64_t(a) << 32) | b) == (uint64_t(reverse_bits32(b)) << 32) |
/// reverse_bits32(a).
constexpr uint64_t reverse_bits64(uint64_t v) {
    v = ((v >> 1) & 0x5555555555555555ULL) | ((v & 0x5555555555555555ULL) << 1);
    v = ((v >> 2) & 0x3333333333333333ULL) | ((v & 0x3333333333333333ULL) << 2);
    v = ((v >> 4) & 0x0f0f0f0f0f0f0f0fULL) | ((v & 0x0f0f0f0f0f0f0f0fULL) << 4);
    return __builtin_bswap64(v);
}

/// Laine-Karras style permutation (Laine & Karras 2011, "Stratified Sampling for Stochastic
/// Transparency") with the improved constants of Burley 2020, "Practical Hash-based Owen
/// Scrambling", JCGT 9(4), Listing 4. Every step (xor with an even multiple, add, odd
/// multiply) changes bit k only as a function of bits <= k, and is bijective.
/// The even multipliers of laine_karras_permutation's three xor steps (also used by the
/// vector forms in sobol.h).
inline constexpr uint32_t kLaineKarrasMul[3] = {0x3d20adeau, 0x05526c56u, 0x53a22864u};
constexpr uint32_t laine_karras_permutation(uint32_t x, uint32_t seed) {
    x ^= x * kLaineKarrasMul[0];
    x += seed;
    x *= (seed >> 16) | 1u;
    x ^= x * kLaineKarrasMul[1];
    x ^= x * kLaineKarrasMul[2];
    return x;
}

/// Hash-based Owen scrambling of a 0.32 fixed-point value (Burley 2020, Listing 5): each bit
/// is flipped as a function of the seed and the more significant bits only, so every
/// elementary interval [k 2^-j, (k+1) 2^-j) is mapped onto another one (stratification and
/// (t,m,s)-net properties are preserved). Bijective on uint32.
constexpr uint32_t owen_scramble(uint32_t v, uint32_t seed) {
    return reverse_bits32(laine_karras_permutation(reverse_bits32(v), seed));
}

/// owen_scramble(reverse_bits32(a), seed) with one bit reversal instead of three: the
/// Owen-scrambled radical inverse in base 2 of a (Sobol dimension 0 is reverse_bits32), and
/// in general the Owen scrambling of any value given bit-reversed.
constexpr uint32_t owen_scrambled_reversed(uint32_t a, uint32_t seed) {
    return reverse_bits32(laine_karras_permutation(a, seed));
}

/// Nested uniform shuffle of a sample index (Burley 2020, Sec. 3): the same scrambling
/// applied to the index, read with its least significant bit as the most significant digit.
/// The first 2^m indices map onto an aligned block of 2^m indices, so a (0,2)-sequence
/// keeps yielding (0,m,2)-nets.
constexpr uint32_t nested_uniform_shuffle(uint32_t index, uint32_t seed) {
    return owen_scramble(index, seed);
}

}  // namespace sr
