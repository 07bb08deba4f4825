#include "steradian/sampling/sampler.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <functional>
#include <vector>

#include "steradian/core/error.h"
#include "steradian/sampling/hash.h"
#include "steradian/sampling/independent_sampler.h"
#include "steradian/sampling/padded_sobol_sampler.h"
#include "steradian/sampling/rng.h"
#include "steradian/sampling/sobol.h"
#include "steradian/sampling/stats.h"
#include "steradian/sampling/stratified_sampler.h"
#include "steradian/sampling/test_util.h"
#include "steradian/sampling/zsobol_sampler.h"

namespace sr {
namespace {

constexpr double kAlpha = 1e-4;
const Vec2i kResolution{64, 48};

struct Config {
    std::string label;
    std::function<std::unique_ptr<Sampler>(int spp, uint64_t seed)> make;
    bool net = false;  // (0,m,2)-nets per pixel for power-of-two spp
};

std::vector<Config> all_configs() {
    return {
        {"independent",
         [](int spp, uint64_t seed) { return std::make_unique<IndependentSampler>(spp, seed); }},
        {"stratified",
         [](int spp, uint64_t seed) {
             int x = 1;
             while ((x * 2) * (x * 2) <= spp) x *= 2;
             return std::make_unique<StratifiedSampler>(x, spp / x, true, seed);
         }},
        {"zsobol_owen",
         [](int spp, uint64_t seed) {
             return std::make_unique<ZSobolSampler>(spp, kResolution, seed, Randomization::kOwen);
         },
         true},
        {"zsobol_xor",
         [](int spp, uint64_t seed) {
             return std::make_unique<ZSobolSampler>(spp, kResolution, seed, Randomization::kXor);
         },
         true},
        {"zsobol_none",
         [](int spp, uint64_t seed) {
             return std::make_unique<ZSobolSampler>(spp, kResolution, seed, Randomization::kNone);
         },
         true},
        {"sobol",
         [](int spp, uint64_t seed) {
             return std::make_unique<PaddedSobolSampler>(spp, seed,
                                                         SobolIndexShuffle::kNestedUniform);
         },
         true},
        {"paddedsobol",
         [](int spp, uint64_t seed) {
             return std::make_unique<PaddedSobolSampler>(spp, seed,
                                                         SobolIndexShuffle::kPermutation);
         },
         true},
    };
}

/// The first `dims` dimensions (pixel 2D, then get_1d's) of one pixel sample.
std::vector<Float> sample_vector(Sampler& s, Vec2i p, int index, int dims) {
    s.start_pixel_sample(p, index);
    Point2 pp = s.get_pixel_2d();
    std::vector<Float> v = {pp.x, pp.y};
    for (int d = 2; d < dims; ++d) v.push_back(s.get_1d());
    return v;
}

TEST(Sampler, DeterministicAndIndependentOfVisitOrder) {
    for (const Config& c : all_configs()) {
        const int spp = 16, dims = 12;
        std::vector<Vec2i> pixels;
        for (int y = 0; y < 6; ++y)
            for (int x = 0; x < 7; ++x) pixels.push_back({x * 5, y * 3});
        // Raster order, one sampler.
        auto a = c.make(spp, 42);
        std::vector<std::vector<Float>> ref;
        for (Vec2i p : pixels)
            for (int i = 0; i < spp; ++i) ref.push_back(sample_vector(*a, p, i, dims));
        // Shuffled pixel and sample order, interleaved over two clones (as two threads would).
        auto b = a->clone();
        auto b2 = c.make(spp, 42);
        std::vector<int> order(pixels.size() * spp);
        for (std::size_t k = 0; k < order.size(); ++k) order[k] = int(k);
        Pcg32 rng(99);
        for (std::size_t k = order.size(); k > 1; --k)
            std::swap(order[k - 1], order[rng.next_u32(uint32_t(k))]);
        for (std::size_t k = 0; k < order.size(); ++k) {
            int o = order[k];
            Sampler& s = (k & 1) ? *b : *b2;
            EXPECT_EQ(sample_vector(s, pixels[std::size_t(o / spp)], o % spp, dims),
                      ref[std::size_t(o)])
                << c.label << " pixel " << o / spp << " sample " << o % spp;
        }
        EXPECT_EQ(a->samples_per_pixel(), spp);
    }
}

TEST(Sampler, DimensionArgumentSkipsDimensions) {
    for (const Config& c : all_configs()) {
        auto s = c.make(16, 3);
        for (int k : {0, 1, 5}) {
            s->start_pixel_sample({4, 9}, 7);
            for (int i = 0; i < k; ++i) s->get_1d();
            Float expected1 = s->get_1d();
            Point2 expected2 = s->get_2d();
            s->start_pixel_sample({4, 9}, 7, k);
            EXPECT_EQ(s->get_1d(), expected1) << c.label << " k " << k;
            EXPECT_EQ(s->get_2d(), expected2) << c.label << " k " << k;
        }
        // get_pixel_2d does not depend on when it is called.
        s->start_pixel_sample({4, 9}, 7);
        Point2 first = s->get_pixel_2d();
        s->get_1d();
        s->get_2d();
        EXPECT_EQ(s->get_pixel_2d(), first) << c.label;
        s->start_pixel_sample({4, 9}, 7, 10);
        EXPECT_EQ(s->get_pixel_2d(), first) << c.label;
    }
}

TEST(Sampler, Skip2dConsumesWhatGet2dWould) {
    // Including across the last low-discrepancy dimensions into the hashed ones.
    for (const Config& c : all_configs()) {
        auto s = c.make(16, 3);
        for (int k : {0, 1, 14, 15, 16, 40}) {
            s->start_pixel_sample({4, 9}, 7, k);
            s->get_2d();
            Float expected1 = s->get_1d();
            Point2 expected2 = s->get_2d();
            s->start_pixel_sample({4, 9}, 7, k);
            s->skip_2d();
            EXPECT_EQ(s->get_1d(), expected1) << c.label << " k " << k;
            EXPECT_EQ(s->get_2d(), expected2) << c.label << " k " << k;
        }
    }
}

TEST(Sampler, Skip1dConsumesWhatGet1dWould) {
    // Including across the last low-discrepancy dimension into the hashed ones
    // (kPixelDimensions + 60 = 63 is the last low-discrepancy one).
    for (const Config& c : all_configs()) {
        auto s = c.make(16, 3);
        for (int k : {0, 1, 14, 15, 40, 59, 60, 61}) {
            s->start_pixel_sample({4, 9}, 7, k);
            s->get_1d();
            Float expected1 = s->get_1d();
            Point2 expected2 = s->get_2d();
            s->start_pixel_sample({4, 9}, 7, k);
            s->skip_1d();
            EXPECT_EQ(s->get_1d(), expected1) << c.label << " k " << k;
            EXPECT_EQ(s->get_2d(), expected2) << c.label << " k " << k;
        }
    }
}

TEST(Sampler, ValuesInHalfOpenUnitIntervalWithMeanOneHalf) {
    for (const Config& c : all_configs()) {
        for (int spp : {1, 12, 64}) {
            auto s = c.make(spp, 5);
            double sum = 0;
            int n = 0;
            for (int y = 0; y < kResolution.y; y += 3) {
                for (int x = 0; x < kResolution.x; x += 3) {
                    for (int i = 0; i < spp; ++i) {
                        s->start_pixel_sample({x, y}, i);
                        Point2 pp = s->get_pixel_2d();
                        std::vector<Float> v = {pp.x, pp.y};
                        for (int d = 0; d < 6; ++d) v.push_back(s->get_1d());
                        for (int d = 0; d < 3; ++d) {
                            Point2 q = s->get_2d();
                            v.push_back(q.x);
                            v.push_back(q.y);
                        }
                        for (Float u : v) {
                            ASSERT_GE(u, 0.0f) << c.label;
                            ASSERT_LT(u, 1.0f) << c.label;
                            sum += u;
                            ++n;
                        }
                    }
                }
            }
            // U(0,1) has variance 1/12; stratified and low-discrepancy samples can only do
            // better within a pixel, and dimensions and pixels are decorrelated.
            EXPECT_GT(z_test_p(sum / n, 0.5, std::sqrt(1.0 / 12 / n)), kAlpha)
                << c.label << " spp " << spp << " mean " << sum / n;
        }
    }
}

TEST(Sampler, DimensionsAndPixelsAreDecorrelated) {
    // Pearson correlation between pairs of dimensions over many pixels and samples, and between
    // the same dimension of horizontally adjacent pixels; |r| ~ N(0, 1/N) for independent
    // values (Sidak over all tested pairs).
    for (const Config& c : all_configs()) {
        const int spp = 16;
        auto s = c.make(spp, 11);
        std::vector<std::vector<double>> dims(8);
        std::vector<double> left, right;
        for (int y = 0; y < 32; ++y) {
            for (int x = 0; x < 32; x += 2) {
                for (int i = 0; i < spp; ++i) {
                    s->start_pixel_sample({x, y}, i);
                    Point2 pp = s->get_pixel_2d();
                    dims[0].push_back(pp.x);
                    dims[1].push_back(pp.y);
                    for (int d = 2; d < 8; ++d) dims[std::size_t(d)].push_back(s->get_1d());
                    s->start_pixel_sample({x + 1, y}, i);
                    left.push_back(dims[4].back());
                    s->get_1d();
                    s->get_1d();
                    right.push_back(s->get_1d());
                }
            }
        }
        auto correlation = [](const std::vector<double>& a, const std::vector<double>& b) {
            double n = double(a.size()), ma = 0, mb = 0;
            for (std::size_t i = 0; i < a.size(); ++i) ma += a[i], mb += b[i];
            ma /= n;
            mb /= n;
            double sab = 0, saa = 0, sbb = 0;
            for (std::size_t i = 0; i < a.size(); ++i) {
                sab += (a[i] - ma) * (b[i] - mb);
                saa += (a[i] - ma) * (a[i] - ma);
                sbb += (b[i] - mb) * (b[i] - mb);
            }
            return sab / std::sqrt(saa * sbb);
        };
        const double n = double(left.size());
        const double alpha = sidak_alpha(kAlpha, 29);
        for (std::size_t i = 0; i < 8; ++i) {
            for (std::size_t j = i + 1; j < 8; ++j) {
                double r = correlation(dims[i], dims[j]);
                EXPECT_GT(normal_two_sided_p(r * std::sqrt(n)), alpha)
                    << c.label << " dims " << i << "," << j << " r " << r;
            }
        }
        double r = correlation(left, right);
        EXPECT_GT(normal_two_sided_p(r * std::sqrt(n)), alpha) << c.label << " neighbours r " << r;
    }
}

TEST(Sampler, LowDiscrepancySamplersGiveZeroTwoNetsPerPixel) {
    // For spp = 2^m, the spp points of one pixel in dimensions (0,1) (get_pixel_2d) and in
    // each later dimension pair (get_2d) form a (0,m,2)-net: every elementary interval of area
    // 2^-m (e.g. for spp = 64: 1/64 x 1, 1/32 x 1/2, ..., 1/8 x 1/8, ..., 1 x 1/64) holds
    // exactly one point. Single dimensions (get_1d) are stratified into spp strata.
    for (const Config& c : all_configs()) {
        if (!c.net) continue;
        for (int spp : {1, 2, 16, 32, 64, 256}) {
            auto s = c.make(spp, 1234);
            for (Vec2i p : {Vec2i{0, 0}, Vec2i{1, 0}, Vec2i{17, 30}, Vec2i{63, 47}}) {
                std::vector<std::vector<Point2>> pairs(4);
                std::vector<std::vector<Float>> singles(2);
                for (int i = 0; i < spp; ++i) {
                    s->start_pixel_sample(p, i);
                    pairs[0].push_back(s->get_pixel_2d());
                    pairs[1].push_back(s->get_2d());
                    pairs[2].push_back(s->get_2d());
                    singles[0].push_back(s->get_1d());
                    singles[1].push_back(s->get_1d());
                    pairs[3].push_back(s->get_2d());
                }
                for (std::size_t k = 0; k < pairs.size(); ++k) {
                    EXPECT_EQ(testing::check_02_net(pairs[k]), "")
                        << c.label << " spp " << spp << " pixel " << p.x << "," << p.y << " pair "
                        << k;
                }
                for (std::size_t k = 0; k < singles.size(); ++k) {
                    EXPECT_TRUE(testing::is_stratified_1d(singles[k]))
                        << c.label << " spp " << spp << " 1D dimension " << k;
                }
            }
        }
    }
}

TEST(Sampler, PixelAndWavelengthDimensionsFormOneMThreeNets) {
    // get_pixel_2d() and get_pixel_1d() are Sobol dimensions 0, 1 and 2 of one index, so the
    // 2^m samples of a pixel form a (1,m,3)-net (Sobol's t for these three dimensions is 1):
    // whichever part of the pixel an edge covers, the wavelengths of the samples there stay
    // stratified. The value does not depend on when it is requested.
    for (const Config& c : all_configs()) {
        if (!c.net) continue;
        for (int spp : {2, 8, 64, 256}) {
            auto s = c.make(spp, 4321);
            for (Vec2i p : {Vec2i{0, 0}, Vec2i{5, 3}, Vec2i{63, 47}}) {
                std::vector<Point3> pts;
                for (int i = 0; i < spp; ++i) {
                    s->start_pixel_sample(p, i);
                    s->get_2d();
                    Float w = s->get_pixel_1d();
                    Point2 pp = s->get_pixel_2d();
                    pts.push_back({pp.x, pp.y, w});
                    s->start_pixel_sample(p, i, 7);
                    ASSERT_EQ(s->get_pixel_1d(), w) << c.label;
                }
                EXPECT_EQ(testing::check_net_3d(pts, 1), "")
                    << c.label << " spp " << spp << " pixel " << p.x << "," << p.y;
            }
        }
    }
    // The other samplers stratify it in one dimension.
    for (const Config& c : all_configs()) {
        if (c.net || c.label == "independent") continue;
        auto s = c.make(16, 5);
        std::vector<Float> w;
        for (int i = 0; i < 16; ++i) {
            s->start_pixel_sample({3, 3}, i);
            w.push_back(s->get_pixel_1d());
        }
        EXPECT_TRUE(testing::is_stratified_1d(w)) << c.label;
    }
}

TEST(Sampler, ZSobolPixelBlocksFormLargerNets) {
    // Ahmed & Wonka 2020: aligned 2x2 (4x4, ...) blocks of pixels own consecutive aligned blocks
    // of the (0,2)-sequence, so their union is again a net: the screen-space blue-noise
    // property.
    for (Randomization r : {Randomization::kOwen, Randomization::kNone}) {
        for (auto [spp, block] :
             {std::pair{16, 2}, std::pair{4, 4}, std::pair{8, 2}, std::pair{2, 8}}) {
            ZSobolSampler s(spp, kResolution, 77, r);
            for (Vec2i origin : {Vec2i{0, 0}, Vec2i{8, 16}, Vec2i{32, 40}}) {
                std::vector<Point2> pixel_pts, lens_pts;
                for (int y = 0; y < block; ++y) {
                    for (int x = 0; x < block; ++x) {
                        for (int i = 0; i < spp; ++i) {
                            s.start_pixel_sample({origin.x + x, origin.y + y}, i);
                            pixel_pts.push_back(s.get_pixel_2d());
                            s.get_1d();
                            lens_pts.push_back(s.get_2d());
                        }
                    }
                }
                EXPECT_EQ(testing::check_02_net(pixel_pts), "")
                    << "spp " << spp << " block " << block << " at " << origin.x << "," << origin.y;
                EXPECT_EQ(testing::check_02_net(lens_pts), "")
                    << "spp " << spp << " block " << block << " at " << origin.x << "," << origin.y;
            }
        }
    }
}

TEST(Sampler, PixelsGetDifferentPoints) {
    // Decorrelation across the screen: no two of a block of pixels share their point sets.
    for (const Config& c : all_configs()) {
        auto s = c.make(4, 0);
        std::vector<std::vector<Float>> sets;
        for (int y = 0; y < 4; ++y) {
            for (int x = 0; x < 4; ++x) {
                std::vector<Float> v;
                for (int i = 0; i < 4; ++i) {
                    s->start_pixel_sample({x, y}, i);
                    Point2 q = s->get_2d();
                    v.push_back(q.x);
                    v.push_back(q.y);
                }
                sets.push_back(v);
            }
        }
        for (std::size_t i = 0; i < sets.size(); ++i)
            for (std::size_t j = i + 1; j < sets.size(); ++j)
                EXPECT_NE(sets[i], sets[j]) << c.label;
        // And different seeds give different samples.
        auto s2 = c.make(4, 1);
        s->start_pixel_sample({2, 2}, 1);
        s2->start_pixel_sample({2, 2}, 1);
        EXPECT_NE(s->get_2d(), s2->get_2d()) << c.label;
    }
}

TEST(Sampler, StratifiedSamplerStratifiesEveryDimension) {
    for (auto [xs, ys] : {std::pair{4, 4}, std::pair{3, 5}, std::pair{1, 7}}) {
        for (bool jitter : {true, false}) {
            StratifiedSampler s(xs, ys, jitter, 9);
            const int spp = xs * ys;
            EXPECT_EQ(s.samples_per_pixel(), spp);
            for (Vec2i p : {Vec2i{0, 0}, Vec2i{5, 3}}) {
                std::vector<Point2> pix, pair;
                std::vector<Float> single;
                for (int i = 0; i < spp; ++i) {
                    s.start_pixel_sample(p, i);
                    pix.push_back(s.get_pixel_2d());
                    single.push_back(s.get_1d());
                    pair.push_back(s.get_2d());
                }
                EXPECT_TRUE(testing::is_stratified_1d(single)) << xs << "x" << ys;
                for (const auto& pts : {pix, pair}) {
                    std::vector<int> count(std::size_t(spp), 0);
                    for (Point2 q : pts) {
                        ASSERT_LT(q.x, 1.0f);
                        ASSERT_LT(q.y, 1.0f);
                        auto cx = int(std::floor(double(q.x) * xs));
                        auto cy = int(std::floor(double(q.y) * ys));
                        ++count[std::size_t(cy * xs + cx)];
                        if (!jitter) {
                            // Without jitter every sample sits at its stratum's centre.
                            EXPECT_NEAR(q.x, (cx + 0.5) / xs, 1e-6);
                            EXPECT_NEAR(q.y, (cy + 0.5) / ys, 1e-6);
                        }
                    }
                    EXPECT_TRUE(
                        std::all_of(count.begin(), count.end(), [](int k) { return k == 1; }))
                        << xs << "x" << ys << " jitter " << jitter;
                }
            }
        }
    }
}

TEST(Sampler, IndependentSamplerIsUniformIn2D) {
    IndependentSampler s(8, 3);
    const int bins = 16;
    std::vector<double> observed(bins * bins, 0.0);
    int n = 0;
    for (int y = 0; y < 40; ++y) {
        for (int x = 0; x < 40; ++x) {
            for (int i = 0; i < 8; ++i) {
                s.start_pixel_sample({x, y}, i);
                s.get_1d();
                Point2 q = s.get_2d();
                observed[std::size_t(int(q.y * bins) * bins + int(q.x * bins))] += 1;
                ++n;
            }
        }
    }
    std::vector<double> expected(observed.size(), double(n) / observed.size());
    EXPECT_GT(chi2_test(observed, expected).p_value, kAlpha);
}

TEST(Sampler, ZSobolIndexKeepsPixelBlocks) {
    // The shuffled index of a pixel's samples stays inside the pixel's block of 2^m indices
    // after the digit permutation (only the block's position changes).
    ZSobolSampler s(32, {16, 16}, 5);
    for (Vec2i p : {Vec2i{0, 0}, Vec2i{3, 7}, Vec2i{15, 15}}) {
        for (int dim : {0, 2, 9}) {
            std::vector<uint64_t> idx;
            for (int i = 0; i < 32; ++i) {
                s.start_pixel_sample(p, i);
                idx.push_back(s.sobol_index(dim));
            }
            std::sort(idx.begin(), idx.end());
            EXPECT_EQ(std::unique(idx.begin(), idx.end()), idx.end());
            EXPECT_EQ(idx.front() >> 5, idx.back() >> 5);
            EXPECT_EQ(idx.back() - idx.front(), 31u);
        }
    }
}

TEST(Sampler, ZSobolBlocksAboveTheHashedLevelsFormNets) {
    // The digits above ZSobolSampler::kHashedPixelLevels are shuffled by XOR: aligned blocks of
    // 32x32 and 64x64 pixels (beyond the hashed 16x16 levels) still form nets.
    for (auto [spp, block] : {std::pair{1, 32}, std::pair{4, 32}, std::pair{1, 64}}) {
        ZSobolSampler s(spp, {512, 512}, 5);
        for (Vec2i origin : {Vec2i{0, 0}, Vec2i{64, 128}, Vec2i{448, 448}}) {
            std::vector<Point2> pixel_pts, lens_pts;
            for (int y = 0; y < block; ++y) {
                for (int x = 0; x < block; ++x) {
                    for (int i = 0; i < spp; ++i) {
                        s.start_pixel_sample({origin.x + x, origin.y + y}, i);
                        pixel_pts.push_back(s.get_pixel_2d());
                        s.get_1d();
                        lens_pts.push_back(s.get_2d());
                    }
                }
            }
            EXPECT_EQ(testing::check_02_net(pixel_pts), "") << "spp " << spp << " block " << block;
            EXPECT_EQ(testing::check_02_net(lens_pts), "") << "spp " << spp << " block " << block;
        }
    }
}

TEST(Sampler, ZSobolTablesArePointsOfTheShuffledIndex) {
    // As below, with the per-pixel tables of a start_pixel() hint serving the samples: the
    // values are still the Sobol points (dimensions 0, 1 and 2 for the pixel sample) of the
    // index sobol_index() computes from scratch.
    for (int spp : {8, 9, 16, 32, 64, 128, 256}) {
        ZSobolSampler s(spp, {512, 512}, 3, Randomization::kNone);
        for (Vec2i p : {Vec2i{0, 0}, Vec2i{511, 511}, Vec2i{200, 77}}) {
            s.start_pixel(p, 0, spp);
            for (int i = 0; i < spp; ++i) {
                s.start_pixel_sample(p, i);
                uint64_t a0 = s.sobol_index(0);
                Point2 pp = s.get_pixel_2d();
                ASSERT_EQ(pp.x, u32_to_unit_float(sobol_u32_dim0(a0)));
                ASSERT_EQ(pp.y, u32_to_unit_float(sobol_u32_dim1(a0)));
                ASSERT_EQ(s.get_pixel_1d(), u32_to_unit_float(sobol_u32_dim2(a0)));
                for (int d = Sampler::kPixelDimensions; d < ZSobolSampler::kTableDimensions + 4;) {
                    uint64_t a = s.sobol_index(d);
                    if ((d + i) % 3 == 0) {
                        Point2 q = s.get_2d();
                        ASSERT_EQ(q.x, u32_to_unit_float(sobol_u32_dim0(a))) << spp << " " << d;
                        ASSERT_EQ(q.y, u32_to_unit_float(sobol_u32_dim1(a))) << spp << " " << d;
                        d += 2;
                    } else {
                        ASSERT_EQ(s.get_1d(), u32_to_unit_float(sobol_u32_dim0(a)))
                            << spp << " " << d;
                        d += 1;
                    }
                }
            }
        }
    }
}

TEST(Sampler, ZSobolTablesChangeNoValue) {
    // Randomized values with and without start_pixel() hints agree bit for bit, for whole and
    // partial runs, samples outside the hinted run, runs too short for tables, and pixels
    // revisited after another pixel.
    for (Randomization r : {Randomization::kOwen, Randomization::kXor}) {
        for (int spp : {1, 4, 8, 12, 16, 32, 64, 100, 128, 256, 512}) {
            ZSobolSampler plain(spp, kResolution, 11, r), hinted(spp, kResolution, 11, r);
            struct Run {
                Vec2i pixel;
                int first, end;
            };
            std::vector<Run> runs = {{{5, 7}, 0, spp},
                                     {{6, 7}, 3, std::min(spp, 21)},
                                     {{5, 7}, spp / 2, spp},
                                     {{63, 47}, 0, std::min(spp, 7)},
                                     {{0, 0}, 8, std::min(spp, 16)}};
            for (const Run& run : runs) {
                hinted.start_pixel(run.pixel, run.first, run.end);
                // The hinted run, then two samples outside it.
                std::vector<int> samples;
                for (int i = run.first; i < run.end; ++i) samples.push_back(i);
                samples.push_back(0);
                samples.push_back(spp - 1);
                for (int i : samples) {
                    plain.start_pixel_sample(run.pixel, i);
                    hinted.start_pixel_sample(run.pixel, i);
                    ASSERT_EQ(plain.get_pixel_2d(), hinted.get_pixel_2d()) << spp << " " << i;
                    ASSERT_EQ(plain.get_pixel_1d(), hinted.get_pixel_1d()) << spp << " " << i;
                    for (int d = Sampler::kPixelDimensions; d < kLowDiscrepancyDimensions + 6;) {
                        if ((d * 7 + i) % 5 < 2) {
                            ASSERT_EQ(plain.get_2d(), hinted.get_2d())
                                << spp << " " << i << " " << d;
                            d += 2;
                        } else {
                            ASSERT_EQ(plain.get_1d(), hinted.get_1d())
                                << spp << " " << i << " " << d;
                            d += 1;
                        }
                    }
                }
            }
        }
    }
}

TEST(Sampler, ZSobolValuesArePointsOfTheShuffledIndex) {
    // The samplers memoize per-pixel parts of the index; sobol_index() computes it from scratch.
    // Without randomization the values are the Sobol points of that index exactly.
    for (Vec2i res :
         {Vec2i{64, 48}, Vec2i{512, 512}, Vec2i{1, 1}, Vec2i{3, 700}, Vec2i{1 << 28, 3}}) {
        for (int spp : {1, 2, 3, 8, 16, 64, 256, 512, 2048}) {
            if (res.x == 1 << 28 && spp > 256) continue;  // 64-bit indices at most
            ZSobolSampler s(spp, res, 9, Randomization::kNone);
            for (Vec2i p :
                 {Vec2i{0, 0}, Vec2i{res.x - 1, res.y - 1}, Vec2i{res.x / 2, res.y / 3}}) {
                for (int i = 0; i < spp; i += std::max(1, spp / 16)) {
                    s.start_pixel_sample(p, i);
                    uint64_t a0 = s.sobol_index(0);
                    Point2 pp = s.get_pixel_2d();
                    ASSERT_EQ(pp.x, u32_to_unit_float(sobol_u32_dim0(a0)));
                    ASSERT_EQ(pp.y, u32_to_unit_float(sobol_u32_dim1(a0)));
                    int d = Sampler::kPixelDimensions;
                    while (d < kLowDiscrepancyDimensions - 1) {
                        uint64_t a = s.sobol_index(d);
                        if (d % 3 == 0) {
                            Point2 q = s.get_2d();
                            ASSERT_EQ(q.x, u32_to_unit_float(sobol_u32_dim0(a)))
                                << "spp " << spp << " dim " << d;
                            ASSERT_EQ(q.y, u32_to_unit_float(sobol_u32_dim1(a)))
                                << "spp " << spp << " dim " << d;
                            d += 2;
                        } else {
                            ASSERT_EQ(s.get_1d(), u32_to_unit_float(sobol_u32_dim0(a)))
                                << "spp " << spp << " dim " << d;
                            d += 1;
                        }
                    }
                }
            }
        }
    }
}

TEST(Sampler, PaddedSobolValuesFollowBurleysConstruction) {
    // Dimension d of sample i of a pixel: key = hash_combine(hash(pixel, seed), d); the index
    // shuffled with the low 32 bits of the key, the point randomized with mix_bits(key). The
    // samplers memoize keys and split the Sobol digits; this pins them to the definition.
    for (auto shuffle : {SobolIndexShuffle::kNestedUniform, SobolIndexShuffle::kPermutation}) {
        for (Randomization r : {Randomization::kOwen, Randomization::kXor, Randomization::kNone}) {
            for (int spp : {1, 2, 12, 16, 64, 512}) {
                const uint64_t seed = 31;
                PaddedSobolSampler s(spp, seed, shuffle, r);
                for (Vec2i p : {Vec2i{0, 0}, Vec2i{17, 5}, Vec2i{-3, 1000}}) {
                    uint64_t pixel_key = hash(p, seed);
                    for (int i = 0; i < spp; i += std::max(1, spp / 16)) {
                        auto point = [&](int d) {
                            uint64_t key = hash_combine(pixel_key, uint64_t(d));
                            uint32_t a = shuffle == SobolIndexShuffle::kNestedUniform
                                             ? nested_uniform_shuffle(uint32_t(i), uint32_t(key))
                                             : permutation_element(uint32_t(i), uint32_t(spp),
                                                                   uint32_t(key));
                            uint64_t scramble = mix_bits(key);
                            return Point2{u32_to_unit_float(
                                              randomize(sobol_u32_dim0(a), r, uint32_t(scramble))),
                                          u32_to_unit_float(randomize(sobol_u32_dim1(a), r,
                                                                      uint32_t(scramble >> 32)))};
                        };
                        s.start_pixel_sample(p, i);
                        ASSERT_EQ(s.get_pixel_2d(), point(0));
                        int d = Sampler::kPixelDimensions;
                        while (d < kLowDiscrepancyDimensions - 1) {
                            if (d % 3 == 0) {
                                ASSERT_EQ(s.get_2d(), point(d)) << "spp " << spp << " dim " << d;
                                d += 2;
                            } else {
                                ASSERT_EQ(s.get_1d(), point(d).x) << "spp " << spp << " dim " << d;
                                d += 1;
                            }
                        }
                    }
                }
            }
        }
    }
}

TEST(Sampler, HashedDimensionsAreDeterministicUniformAndDecorrelated) {
    // From kLowDiscrepancyDimensions on, the Sobol-type samplers return hashed pseudo-random
    // numbers: still a pure function of (pixel, sample index, dimension, seed), uniform, and
    // independent across dimensions and pixels.
    for (const Config& c : all_configs()) {
        if (!c.net) continue;
        const int spp = 16;
        auto s = c.make(spp, 21);
        auto tail = [&](Sampler& smp, Vec2i p, int i, int first_dimension) {
            smp.start_pixel_sample(p, i, first_dimension);
            std::vector<Float> v;
            for (int k = 0; k < 8; ++k) v.push_back(smp.get_1d());
            Point2 q = smp.get_2d();
            v.push_back(q.x);
            v.push_back(q.y);
            return v;
        };
        // Deterministic: the same values whether reached through all earlier dimensions or by
        // the dimension argument, from a clone, and in any order.
        const int first = kLowDiscrepancyDimensions + 3 - Sampler::kPixelDimensions;
        auto clone = s->clone();
        for (Vec2i p : {Vec2i{3, 4}, Vec2i{0, 0}, Vec2i{50, 7}}) {
            for (int i : {0, 5, 15}) {
                s->start_pixel_sample(p, i);
                for (int k = 0; k < first; ++k) s->get_1d();
                std::vector<Float> sequential;
                for (int k = 0; k < 8; ++k) sequential.push_back(s->get_1d());
                Point2 q = s->get_2d();
                sequential.push_back(q.x);
                sequential.push_back(q.y);
                EXPECT_EQ(tail(*clone, p, i, first), sequential) << c.label;
                EXPECT_EQ(tail(*s, p, i, first), sequential) << c.label;
            }
        }
        // Uniform: 1D histogram (64 bins) of 8 dimensions and 2D histogram (16 x 16) of a pair,
        // over 32 x 32 pixels; means; correlation of consecutive dimensions and of neighbours.
        const int bins = 64, bins2 = 16;
        std::vector<double> h1(bins, 0.0), h2(bins2 * bins2, 0.0);
        std::vector<double> a, b, left, right;
        double sum = 0;
        int n = 0;
        for (int y = 0; y < 32; ++y) {
            for (int x = 0; x < 32; ++x) {
                for (int i = 0; i < spp; ++i) {
                    std::vector<Float> v = tail(*s, {x, y}, i, first);
                    for (int k = 0; k < 8; ++k) {
                        ASSERT_GE(v[std::size_t(k)], 0.0f);
                        ASSERT_LT(v[std::size_t(k)], 1.0f);
                        h1[std::size_t(v[std::size_t(k)] * bins)] += 1;
                        sum += v[std::size_t(k)];
                        ++n;
                    }
                    h2[std::size_t(int(v[9] * bins2) * bins2 + int(v[8] * bins2))] += 1;
                    a.push_back(v[0]);
                    b.push_back(v[1]);
                    if (x % 2 == 0) {
                        left.push_back(v[2]);
                        right.push_back(tail(*s, {x + 1, y}, i, first)[2]);
                    }
                }
            }
        }
        std::vector<double> e1(h1.size(), double(n) / bins);
        std::vector<double> e2(h2.size(), double(a.size()) / (bins2 * bins2));
        EXPECT_GT(chi2_test(h1, e1).p_value, kAlpha) << c.label;
        EXPECT_GT(chi2_test(h2, e2).p_value, kAlpha) << c.label;
        EXPECT_GT(z_test_p(sum / n, 0.5, std::sqrt(1.0 / 12 / n)), kAlpha) << c.label;
        auto correlation = [](const std::vector<double>& u, const std::vector<double>& w) {
            double m = double(u.size()), mu = 0, mw = 0;
            for (std::size_t i = 0; i < u.size(); ++i) mu += u[i], mw += w[i];
            mu /= m;
            mw /= m;
            double suw = 0, suu = 0, sww = 0;
            for (std::size_t i = 0; i < u.size(); ++i) {
                suw += (u[i] - mu) * (w[i] - mw);
                suu += (u[i] - mu) * (u[i] - mu);
                sww += (w[i] - mw) * (w[i] - mw);
            }
            return suw / std::sqrt(suu * sww);
        };
        double r1 = correlation(a, b), r2 = correlation(left, right);
        EXPECT_GT(normal_two_sided_p(r1 * std::sqrt(double(a.size()))), kAlpha) << c.label;
        EXPECT_GT(normal_two_sided_p(r2 * std::sqrt(double(left.size()))), kAlpha) << c.label;
    }
}

TEST(Sampler, LastLowDiscrepancyPairIsStillANet) {
    // A get_2d() whose first dimension is kLowDiscrepancyDimensions - 2 (the last full pair)
    // is low-discrepancy; the next dimensions are hashed.
    for (const Config& c : all_configs()) {
        if (!c.net) continue;
        for (int spp : {16, 64}) {
            auto s = c.make(spp, 8);
            std::vector<Point2> pts;
            for (int i = 0; i < spp; ++i) {
                s->start_pixel_sample({6, 2}, i,
                                      kLowDiscrepancyDimensions - 2 - Sampler::kPixelDimensions);
                pts.push_back(s->get_2d());
            }
            EXPECT_EQ(testing::check_02_net(pts), "") << c.label << " spp " << spp;
        }
    }
}

TEST(Sampler, FactoryNames) {
    struct Case {
        const char* name;
        const char* expected;
    };
    for (Case c : {Case{"independent", "independent"}, Case{"stratified", "stratified"},
                   Case{"zsobol", "zsobol"}, Case{"halton", "zsobol"}, Case{"sobol", "sobol"},
                   Case{"paddedsobol", "paddedsobol"}, Case{"pmj02bn", "paddedsobol"}}) {
        auto s = make_sampler(c.name, 16, kResolution, 1);
        EXPECT_EQ(s->name(), c.expected) << c.name;
        EXPECT_EQ(s->samples_per_pixel(), 16);
        EXPECT_EQ(s->clone()->name(), c.expected);
    }
    auto st = make_sampler("stratified", 12, kResolution, 0);
    auto* strat = dynamic_cast<StratifiedSampler*>(st.get());
    ASSERT_NE(strat, nullptr);
    EXPECT_EQ(strat->x_samples(), 3);
    EXPECT_EQ(strat->y_samples(), 4);
    EXPECT_EQ(make_stratified_sampler(2, 5)->samples_per_pixel(), 10);

    EXPECT_THROW(make_sampler("lowdiscrepancy", 16, kResolution, 0), Error);
    EXPECT_THROW(make_sampler("zsobol", 0, kResolution, 0), Error);
    EXPECT_THROW(make_stratified_sampler(0, 4), Error);
    EXPECT_EQ(randomization_from_string("fastowen"), Randomization::kOwen);
    EXPECT_EQ(randomization_from_string("permutedigits"), Randomization::kXor);
    EXPECT_THROW(randomization_from_string("cranley"), Error);
}

}  // namespace
}  // namespace sr
