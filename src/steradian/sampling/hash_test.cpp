#include "steradian/sampling/hash.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <bit>
#include <set>
#include <vector>

#include "steradian/sampling/rng.h"
#include "steradian/sampling/sobol.h"
#include "steradian/sampling/stats.h"
#include "steradian/sampling/test_util.h"

namespace sr {
namespace {

constexpr double kAlpha = 1e-3;

TEST(Hash, MixBitsIsTheSplitmix64Finalizer) {
    // First output of Vigna's reference splitmix64.c seeded with 1234567: the finalizer
    // applied to the seed plus one Weyl increment.
    EXPECT_EQ(mix_bits(1234567 + kGolden64), 6457827717110365317ULL);
    EXPECT_EQ(hash_combine(1234567, 0), 6457827717110365317ULL);
}

TEST(Hash, MixBitsAvalanche) {
    // Flipping any input bit flips each output bit with probability 1/2: count flips of
    // every (input bit, output bit) pair over random inputs and z-test each against n/2
    // (Sidak-corrected over the 4096 pairs).
    Pcg32 rng(3, 4);
    const int n = 4000;
    std::vector<int> flips(64 * 64, 0);
    for (int s = 0; s < n; ++s) {
        uint64_t x = (uint64_t(rng.next_u32()) << 32) | rng.next_u32();
        uint64_t hx = mix_bits(x);
        for (int i = 0; i < 64; ++i) {
            uint64_t d = hx ^ mix_bits(x ^ (uint64_t(1) << i));
            for (int j = 0; j < 64; ++j) flips[std::size_t(i * 64 + j)] += int((d >> j) & 1);
        }
    }
    double alpha = sidak_alpha(kAlpha, 64 * 64);
    for (int k = 0; k < 64 * 64; ++k) {
        EXPECT_GT(z_test_p(flips[std::size_t(k)] / double(n), 0.5, std::sqrt(0.25 / n)), alpha)
            << "input bit " << k / 64 << " output bit " << k % 64;
    }
}

TEST(Hash, HashOfBytesIsAFunctionOfAllArguments) {
    EXPECT_EQ(hash(Vec2i(3, 4), uint64_t(5)), hash(Vec2i(3, 4), uint64_t(5)));
    EXPECT_NE(hash(Vec2i(3, 4), uint64_t(5)), hash(Vec2i(4, 3), uint64_t(5)));
    EXPECT_NE(hash(Vec2i(3, 4), uint64_t(5)), hash(Vec2i(3, 4), uint64_t(6)));
    EXPECT_NE(hash(1, 2), hash(2, 1));
    // Same bytes, same hash, however they are split into arguments.
    EXPECT_EQ(hash(Vec2i(1, 2)), hash(int32_t(1), int32_t(2)));
    // Lengths not a multiple of 8 use the tail bytes.
    EXPECT_NE(hash(uint8_t(1), uint8_t(2), uint8_t(3)), hash(uint8_t(1), uint8_t(2), uint8_t(4)));
    // No collisions over a block of pixels.
    std::set<uint64_t> seen;
    for (int y = 0; y < 64; ++y)
        for (int x = 0; x < 64; ++x) seen.insert(hash(Vec2i(x, y), uint64_t(0)));
    EXPECT_EQ(seen.size(), 64u * 64u);
}

TEST(Hash, PermutationElementIsAPermutation) {
    for (uint32_t n : {1u, 2u, 3u, 5u, 16u, 17u, 100u, 255u, 256u, 1000u, 4097u}) {
        for (uint32_t seed : {0u, 1u, 0xdeadbeefu, 123456789u}) {
            std::vector<int> hit(n, 0);
            for (uint32_t i = 0; i < n; ++i) {
                uint32_t p = permutation_element(i, n, seed);
                ASSERT_LT(p, n);
                ++hit[p];
            }
            EXPECT_TRUE(std::all_of(hit.begin(), hit.end(), [](int h) { return h == 1; }))
                << "n " << n << " seed " << seed;
        }
    }
}

TEST(Hash, PermutationElementIsUniformOverSeeds) {
    // The image of a fixed element over random seeds is uniform on [0, n).
    Pcg32 rng(8, 8);
    const uint32_t n = 12;
    const int trials = 120000;
    for (uint32_t i : {0u, 5u, 11u}) {
        std::vector<double> observed(n, 0.0), expected(n, double(trials) / n);
        for (int t = 0; t < trials; ++t) observed[permutation_element(i, n, rng.next_u32())] += 1;
        EXPECT_GT(chi2_test(observed, expected).p_value, kAlpha) << "element " << i;
    }
}

TEST(Hash, ReverseBits) {
    EXPECT_EQ(reverse_bits32(1u), 0x80000000u);
    EXPECT_EQ(reverse_bits32(0x0000f00fu), 0xf00f0000u);
    EXPECT_EQ(reverse_bits64(1ULL), 0x8000000000000000ULL);
    Pcg32 rng(1, 1);
    for (int i = 0; i < 1000; ++i) {
        uint32_t v = rng.next_u32();
        EXPECT_EQ(reverse_bits32(reverse_bits32(v)), v);
        EXPECT_EQ(std::popcount(reverse_bits32(v)), std::popcount(v));
        // Bit k goes to bit 31 - k.
        for (int k = 0; k < 32; k += 7)
            EXPECT_EQ((v >> k) & 1, (reverse_bits32(v) >> (31 - k)) & 1);
    }
}

TEST(Hash, ReverseBits64ReversesTwoHalvesAtOnce) {
    Pcg32 rng(7, 1);
    for (int i = 0; i < 1000; ++i) {
        uint32_t a = rng.next_u32(), b = rng.next_u32();
        uint64_t v = (uint64_t(a) << 32) | b;
        EXPECT_EQ(reverse_bits64(v), (uint64_t(reverse_bits32(b)) << 32) | reverse_bits32(a));
        EXPECT_EQ(reverse_bits64(reverse_bits64(v)), v);
    }
}

TEST(Hash, OwenScrambledReversedSkipsTwoReversals) {
    Pcg32 rng(9, 2);
    for (int i = 0; i < 1000; ++i) {
        uint32_t a = rng.next_u32(), seed = rng.next_u32();
        EXPECT_EQ(owen_scrambled_reversed(a, seed), owen_scramble(reverse_bits32(a), seed));
    }
}

TEST(Hash, PermutationElementWithPrecomputedMask) {
    EXPECT_EQ(permutation_mask(1), 0u);
    EXPECT_EQ(permutation_mask(2), 1u);
    EXPECT_EQ(permutation_mask(16), 15u);
    EXPECT_EQ(permutation_mask(17), 31u);
    EXPECT_EQ(permutation_mask(100), 127u);
    // Kensler's Listing 3 as published (mask recomputed, final step with %): the precomputed
    // mask and the power-of-two shortcut (a mask instead of %) change nothing.
    auto kensler = [](uint32_t i, uint32_t l, uint32_t p) {
        uint32_t w = l - 1;
        w |= w >> 1;
        w |= w >> 2;
        w |= w >> 4;
        w |= w >> 8;
        w |= w >> 16;
        do {
            i ^= p;
            i *= 0xe170893du;
            i ^= p >> 16;
            i ^= (i & w) >> 4;
            i ^= p >> 8;
            i *= 0x0929eb3fu;
            i ^= p >> 23;
            i ^= (i & w) >> 1;
            i *= 1u | (p >> 27);
            i *= 0x6935fa69u;
            i ^= (i & w) >> 11;
            i *= 0x74dcb303u;
            i ^= (i & w) >> 2;
            i *= 0x9e501cc3u;
            i ^= (i & w) >> 2;
            i *= 0xc860a3dfu;
            i &= w;
            i ^= i >> 5;
        } while (i >= l);
        return (i + p) % l;
    };
    for (uint32_t n : {1u, 2u, 8u, 64u, 1024u, 12u, 100u}) {
        for (uint32_t seed : {0u, 77u, 0xfedcba98u}) {
            for (uint32_t i = 0; i < n; ++i) {
                EXPECT_EQ(permutation_element(i, n, permutation_mask(n), seed),
                          kensler(i, n, seed));
                EXPECT_EQ(permutation_element(i, n, seed), kensler(i, n, seed));
            }
        }
    }
}

TEST(Hash, OwenScrambleIsNestedAndBijective) {
    Pcg32 rng(21, 22);
    for (int trial = 0; trial < 20; ++trial) {
        uint32_t seed = rng.next_u32();
        // Bijective on each level of dyadic intervals: the top 12 bits of scrambled interval
        // starts are all distinct.
        std::set<uint32_t> tops;
        for (uint32_t k = 0; k < 4096; ++k) tops.insert(owen_scramble(k << 20, seed) >> 20);
        EXPECT_EQ(tops.size(), 4096u);
        // Nested: values sharing their top j bits (the same interval of size 2^-j) still share
        // their top j bits after scrambling.
        for (int s = 0; s < 200; ++s) {
            uint32_t a = rng.next_u32(), b = rng.next_u32();
            int j = int(rng.next_u32(31)) + 1;
            uint32_t mask = ~0u << (32 - j);
            b = (a & mask) | (b & ~mask);
            EXPECT_EQ(owen_scramble(a, seed) & mask, owen_scramble(b, seed) & mask);
        }
    }
}

TEST(Hash, OwenScrambleIsUniformOverSeeds) {
    // Owen scrambling makes every point uniformly distributed: the scrambled value of a fixed
    // point over random seeds, histogrammed in 64 bins.
    Pcg32 rng(5, 55);
    const int trials = 64000;
    for (uint32_t v : {0u, 0x80000000u, 0x12345678u}) {
        std::vector<double> observed(64, 0.0), expected(64, trials / 64.0);
        for (int t = 0; t < trials; ++t) observed[owen_scramble(v, rng.next_u32()) >> 26] += 1;
        EXPECT_GT(chi2_test(observed, expected).p_value, kAlpha) << std::hex << v;
    }
}

TEST(Hash, NestedUniformShuffleKeepsAlignedBlocks) {
    Pcg32 rng(31, 41);
    for (int m = 0; m <= 10; ++m) {
        uint32_t seed = rng.next_u32();
        std::set<uint32_t> out;
        for (uint32_t i = 0; i < (1u << m); ++i) out.insert(nested_uniform_shuffle(i, seed));
        ASSERT_EQ(out.size(), std::size_t(1) << m);
        // All in one aligned block of 2^m indices.
        EXPECT_EQ(*out.begin() >> m, *out.rbegin() >> m);
    }
}

TEST(Sobol, SecondDimensionIsPascalMod2) {
    // Column j of the generator matrix is the image of index 2^j. Build binom(j, i) mod 2 with
    // Pascal's rule binom(j, i) = binom(j-1, i-1) + binom(j-1, i) and compare (rows i < 32).
    std::vector<std::vector<int>> pascal(64, std::vector<int>(64, 0));
    for (int j = 0; j < 64; ++j) {
        pascal[std::size_t(j)][0] = 1;
        for (int i = 1; i <= j; ++i) {
            pascal[std::size_t(j)][std::size_t(i)] =
                (pascal[std::size_t(j - 1)][std::size_t(i - 1)] +
                 pascal[std::size_t(j - 1)][std::size_t(i)]) %
                2;
        }
    }
    for (int j = 0; j < 64; ++j) {
        uint32_t column = 0;
        for (int i = 0; i < 32; ++i) {
            if (pascal[std::size_t(j)][std::size_t(i)]) column |= 1u << (31 - i);
        }
        EXPECT_EQ(sobol_u32_dim1(uint64_t(1) << j), column) << "column " << j;
    }
    // Linear over GF(2).
    Pcg32 rng(2, 3);
    for (int t = 0; t < 1000; ++t) {
        uint64_t a = (uint64_t(rng.next_u32()) << 32) | rng.next_u32();
        uint64_t b = (uint64_t(rng.next_u32()) << 32) | rng.next_u32();
        EXPECT_EQ(sobol_u32_dim1(a ^ b), sobol_u32_dim1(a) ^ sobol_u32_dim1(b));
    }
}

TEST(Sobol, FirstDimensionIsVanDerCorput) {
    // Radical inverse in base 2: 1 -> 1/2, 2 -> 1/4, 3 -> 3/4, 6 -> 3/8.
    EXPECT_EQ(sobol_u32_dim0(1), 0x80000000u);
    EXPECT_EQ(sobol_u32_dim0(2), 0x40000000u);
    EXPECT_EQ(sobol_u32_dim0(3), 0xc0000000u);
    EXPECT_EQ(sobol_u32_dim0(6), 0x60000000u);
}

std::vector<Point2> sobol_block(uint64_t start, int m, Randomization r, uint64_t key) {
    std::vector<Point2> pts;
    for (uint64_t a = start; a < start + (uint64_t(1) << m); ++a) {
        pts.push_back({u32_to_unit_float(randomize(sobol_u32_dim0(a), r, uint32_t(key))),
                       u32_to_unit_float(randomize(sobol_u32_dim1(a), r, uint32_t(key >> 32)))});
    }
    return pts;
}

TEST(Sobol, AlignedBlocksAreZeroTwoNets) {
    Pcg32 rng(6, 7);
    for (Randomization r : {Randomization::kNone, Randomization::kXor, Randomization::kOwen}) {
        for (int m = 0; m <= 12; ++m) {
            for (uint64_t block : {uint64_t(0), uint64_t(1), uint64_t(37), uint64_t(1) << 20}) {
                uint64_t key = (uint64_t(rng.next_u32()) << 32) | rng.next_u32();
                EXPECT_EQ(testing::check_02_net(sobol_block(block << m, m, r, key)), "")
                    << "m " << m << " block " << block << " randomization " << to_string(r);
            }
        }
    }
    // An unaligned block is not a net in general: indices 1..4 put two points in [0, 1/2) in
    // x ((1/2, 1/2), (1/4, 3/4), (3/4, 1/4), (1/8, 5/8): x = 1/4 and 1/8 both below 1/2).
    EXPECT_NE(testing::check_02_net(sobol_block(1, 2, Randomization::kNone, 0)), "");
}

TEST(Sobol, FirstThreeDimensionsFormAOneThreeSequence) {
    // Sobol's bound t <= sum over the primitive polynomials (x, x + 1, x^2 + x + 1) of
    // (degree - 1) = 1: every aligned block of 2^m indices is a (1,m,3)-net, randomized or not
    // (digit scramblings map elementary boxes onto elementary boxes). t = 0 is impossible for
    // three dimensions in base 2 (Niederreiter 1992, Cor. 4.24), so some box must show it.
    Pcg32 rng(8, 9);
    for (Randomization r : {Randomization::kNone, Randomization::kXor, Randomization::kOwen}) {
        for (int m = 1; m <= 10; ++m) {
            for (uint64_t block : {uint64_t(0), uint64_t(1), uint64_t(37), uint64_t(1) << 20}) {
                uint32_t k0 = rng.next_u32(), k1 = rng.next_u32(), k2 = rng.next_u32();
                std::vector<Point3> pts;
                for (uint64_t a = block << m; a < (block + 1) << m; ++a) {
                    pts.push_back({u32_to_unit_float(randomize(sobol_u32_dim0(a), r, k0)),
                                   u32_to_unit_float(randomize(sobol_u32_dim1(a), r, k1)),
                                   u32_to_unit_float(randomize(sobol_u32_dim2(a), r, k2))});
                }
                EXPECT_EQ(testing::check_net_3d(pts, 1), "")
                    << "m " << m << " block " << block << " randomization " << to_string(r);
                if (m >= 2) {
                    EXPECT_NE(testing::check_net_3d(pts, 0), "") << "m " << m;
                }
            }
        }
    }
    // Dimension 2 alone is a (0,1)-sequence (its generator matrix is non-singular upper
    // triangular), and it is linear over GF(2).
    for (int j = 0; j < 32; ++j) {
        uint32_t column = kSobolDim2Columns[std::size_t(j)];
        EXPECT_EQ(column >> j, 1u) << "column " << j << " is not unit upper triangular";
    }
    for (int t = 0; t < 1000; ++t) {
        uint32_t a = rng.next_u32(), b = rng.next_u32();
        EXPECT_EQ(sobol_u32_dim2(a ^ b), sobol_u32_dim2(a) ^ sobol_u32_dim2(b));
    }
}

TEST(Sobol, FloatPointsMatchTheReferenceFormulas) {
    // sobol_1d_float and sobol_2d_float (SSE4.1 where compiled for it, scalar otherwise) against
    // the definitions: randomize the Sobol digits, then u32_to_unit_float.
    Pcg32 rng(12, 34);
    for (Randomization r : {Randomization::kNone, Randomization::kXor, Randomization::kOwen}) {
        for (int t = 0; t < 20000; ++t) {
            uint64_t a = (uint64_t(rng.next_u32()) << 32) | rng.next_u32();
            if (t % 3 == 0) a >>= rng.next_u32(64);
            uint64_t key = (uint64_t(rng.next_u32()) << 32) | rng.next_u32();
            Float x = u32_to_unit_float(randomize(sobol_u32_dim0(a), r, uint32_t(key)));
            Float y = u32_to_unit_float(randomize(sobol_u32_dim1(a), r, uint32_t(key >> 32)));
            ASSERT_EQ(sobol_1d_float(uint32_t(a), r, uint32_t(key)), x) << to_string(r);
            Point2 p = sobol_2d_float(uint32_t(a), uint32_t(pascal_mod2_transform(a)), r, key);
            ASSERT_EQ(p.x, x) << to_string(r);
            ASSERT_EQ(p.y, y) << to_string(r);
        }
    }
}

TEST(Morton, InterleavesBits) {
    Pcg32 rng(4, 4);
    for (int t = 0; t < 1000; ++t) {
        uint32_t x = rng.next_u32(), y = rng.next_u32();
        uint64_t expected = 0;
        for (int b = 0; b < 32; ++b) {
            expected |= uint64_t((x >> b) & 1) << (2 * b);
            expected |= uint64_t((y >> b) & 1) << (2 * b + 1);
        }
        EXPECT_EQ(encode_morton2(x, y), expected);
    }
}

}  // namespace
}  // namespace sr
