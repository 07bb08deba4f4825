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
#include <cstdint>
#include <string>

#include "steradian/sampling/hash.h"

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

}  // namespace sr
