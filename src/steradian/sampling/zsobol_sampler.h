#pragma once
/// ZSobolSampler: Morton-ordered, Owen-scrambled Sobol samples (pbrt-v4's "zsobol").
#include <array>
#include <cstddef>
#include <cstdint>
#include <memory>
#include <string>
#include <vector>

#include "steradian/core/math.h"
#include "steradian/sampling/hash.h"
#include "steradian/sampling/sampler.h"
#include "steradian/sampling/sobol.h"

namespace sr {

/// Morton-ordered, Owen-scrambled Sobol sampler ("zsobol" in pbrt-v4), after Ahmed & Wonka
/// 2020, "Screen-Space Blue-Noise Diffusion of Monte Carlo Sampling Error via Hierarchical
/// Ordering of Pixels", ACM TOG 39(6).
///
/// Pixels are laid out along a Z (Morton) curve over the square of side 2^k covering the image;
/// pixel p owns the consecutive global indices [morton(p) 2^m, (morton(p) + 1) 2^m) of the 2D
/// Sobol (0,2)-sequence, with 2^m = samples_per_pixel rounded up to a power of two. Hence every
/// pixel's first 2^m samples form a (0,m,2)-net, and so does the union of every aligned
/// 2x2, 4x4, ... block of pixels: the error is distributed as blue noise across the screen.
/// The base-4 digits of the index are shuffled per dimension, keeping blocks aligned (a nested
/// shuffle), and each dimension pair's point is scrambled (default: Burley's hash-based Owen
/// scrambling) with a key hashed from the dimension and seed:
///   - the sample digits and the lowest kHashedPixelLevels pixel levels (2x2 up to 16x16
///     blocks) by per-node random permutations of {0,1,2,3} hashed from the higher digits, the
///     dimension and the seed (Owen-style, as in the paper and pbrt-v4);
///   - the digits above (the position of the 16x16 block) by XOR with a per-dimension random
///     constant. These digits only choose which aligned block of the sequence each 16x16 block
///     of pixels uses: any choice keeps every net (per pixel and per aligned block of pixels),
///     and the pixel's points are decorrelated across dimensions and from its neighbours by the
///     hashed levels below (whose nodes include these digits) and the scrambling. Per-node
///     permutations here would only shuffle the arrangement of whole 16x16 blocks, at a cost
///     that grows with the resolution.
/// Every get_1d() uses Sobol dimension 0, every get_2d() Sobol dimensions 0 and 1: the padding
/// of pbrt-v4, decorrelated across dimensions by the shuffles and scramblings.
/// Dimensions from kLowDiscrepancyDimensions on are hashed pseudo-random numbers.
/// Requires sample_index < samples_per_pixel() (larger indices would alias into the next
/// pixel's block) and pixels inside the resolution given here (others still work but lose the
/// screen-space structure).
///
/// Cost: everything that depends on (pixel, dimension, seed) only -- the shuffled pixel digits,
/// the permutation of the highest sample digit (its node is the pixel) and their Sobol
/// dimension-1 digits -- is computed once per pixel and dimension and reused by the pixel's
/// further samples (the renderer visits a pixel's samples consecutively within each pass); a
/// get then hashes the remaining sample digits (2 multiplies at 64 spp) and scrambles.
/// After a start_pixel() hint for a run of at least 8 samples (and 8 <= 2^m <= 256), the
/// first kTableDimensions dimensions are instead computed for the whole run at once, the
/// first time one of its samples asks for them: each node of the sample digits' quadtree is
/// hashed once per dimension instead of once per sample, and the scrambling runs 8 samples
/// per vector instruction. A get then reads its sample's entry. The values are the same.
class ZSobolSampler final : public Sampler {
  public:
    /// Pixel levels (from 2x2 blocks up) whose digits get per-node hashed permutations.
    static constexpr int kHashedPixelLevels = 4;

    /// resolution: the film's pixel count (x, y); pixels should lie in [0, resolution).
    ZSobolSampler(int samples_per_pixel, Vec2i resolution, uint64_t seed = 0,
                  Randomization randomize = Randomization::kOwen);
    /// Dimensions [0, this) are tabulated per pixel after a start_pixel() hint: the camera's 5
    /// and 3 path vertices of 7. Deeper dimensions are reached by too few of a pixel's samples
    /// to repay a table: a column of the Cornell box at 64 spp (callgrind) ran 2,173, 2,171,
    /// 2,176 and 2,184 M instructions with 19, 26, 33 and 40.
    static constexpr int kTableDimensions = 26;
    static_assert(kTableDimensions <= 64 && kTableDimensions > kPixelDimensions);

    void start_pixel(Vec2i pixel, int first_sample, int end_sample) override;
    void start_pixel_sample(Vec2i pixel, int sample_index, int dimension = 0) override;
    Float get_1d() override;
    Point2 get_2d() override;
    void skip_1d() override { ++m_dimension; }
    void skip_2d() override { m_dimension += 2; }
    Point2 get_pixel_2d() override { return sample_2d(0); }
    /// Sobol dimension 2 of get_pixel_2d()'s index, scrambled with dimension 2's key.
    Float get_pixel_1d() override;
    std::unique_ptr<Sampler> clone() const override;
    std::string name() const override { return "zsobol"; }

    /// The shuffled global Sobol index of the current pixel sample for `dimension`, computed
    /// from scratch (the values of dimensions < kLowDiscrepancyDimensions are the randomized
    /// Sobol points of these indices).
    uint64_t sobol_index(int dimension);

  private:
    static constexpr int kMaxDigits = 32;  // base-4 digits of a 64-bit index

    Point2 sample_2d(int dimension);
    Float get_1d_slow();
    Point2 get_2d_slow();
    // Kernels of get_1d() and sample_2d() for dimension d < kLowDiscrepancyDimensions,
    // specialized on log2(samples per pixel) (kLog2Spp < 0: any m > 8).
    using Get1dFn = Float (*)(ZSobolSampler&, int);
    using Sample2dFn = Point2 (*)(ZSobolSampler&, int);
    void select_kernels();
    template <int kLog2Spp>
    static Float get_1d_impl(ZSobolSampler& s, int d);
    template <int kLog2Spp>
    static Float fill_and_get_1d(ZSobolSampler& s, int d);
    template <int kLog2Spp>
    Float value_1d(int d) const;
    template <int kLog2Spp>
    static Point2 sample_2d_impl(ZSobolSampler& s, int d);
    template <int kLog2Spp>
    static Point2 fill_and_sample_2d(ZSobolSampler& s, int d);
    template <int kLog2Spp>
    Point2 value_2d(int d) const;
    template <int kLog2Spp>
    static Float pixel_1d_impl(ZSobolSampler& s, int);
    /// The shuffled sample digits (the low m bits of the index) for a dimension's key, given
    /// the permutation of the highest sample digit (top_sample_choice()). kLog2Spp < 0: m from
    /// m_log2_spp.
    template <int kLog2Spp>
    uint64_t sample_digits(uint64_t dim_key, uint8_t top_choice) const;
    /// Computes and memoizes the per-(pixel, dimension) values of dimension d.
    void fill_pixel_dimension(int d);
    /// Positions the sampler on a pixel: its Morton index and the hashes of the pixel-level
    /// nodes; forgets the memoized dimensions and the tables.
    void set_pixel(Vec2i pixel);
    /// The current sample's Morton index, hashed-dimension key and sample-node hashes (deferred
    /// while the sample is served from the tables, which need none of them).
    void compute_sample_nodes();
    /// The hashes of every sample-level node of the current pixel, for the tables.
    void fill_level_hashes();
    /// The shuffled sample digits of dimension d for the samples of the table run.
    void table_sample_digits(int d, uint8_t* low) const;
    /// Fills table slot `slot` (a dimension; slot 2, which no get reaches, holds get_pixel_1d())
    /// for the table run: its first coordinate, and its second if need_y.
    void build_table(int slot, bool need_y);
    bool use_table(int d) const { return m_table_sample && d < kTableDimensions; }
    /// Where the current sample's entry of table slot d is.
    std::size_t table_index(int d) const {
        return (std::size_t(d) << m_log2_spp) + std::size_t(m_sample_index);
    }
    Point2 table_2d(int d) {
        if (!((m_table_valid_y >> d) & 1)) [[unlikely]]
            build_table(d, true);
        return {m_table_x[table_index(d)], m_table_y[table_index(d)]};
    }
    /// The shuffled digits above the sample digits (pixel digits and bits above them).
    uint64_t pixel_digits(uint64_t dim_key, uint64_t dim_xor) const;
    /// The permutation (or, for a single-bit digit, the flip) of the highest sample digit.
    uint8_t top_sample_choice(uint64_t dim_key) const;
    uint64_t dimension_key(int dimension) const {
        return hash_combine(m_seed_key, uint64_t(dimension));
    }
    uint64_t dimension_xor(uint64_t dim_key) const {
        return mix_bits(dim_key + kGolden64) & m_xor_mask;
    }

    // Configuration.
    uint64_t m_seed;
    uint64_t m_seed_key;
    Randomization m_randomize;
    int m_log2_spp;
    int m_num_base4_digits;
    int m_num_sample_digits;  // ceil(m / 2): the digits below the pixel digits
    int m_hashed_digits_end;  // digits [m_num_sample_digits, this) are hashed pixel digits
    uint64_t m_xor_mask = 0;  // the index bits of the digits shuffled by XOR
    std::array<uint64_t, kLowDiscrepancyDimensions> m_dim_key{};       // dimension_key(d)
    std::array<uint64_t, kLowDiscrepancyDimensions> m_scramble_key{};  // point scrambling key
    Get1dFn m_get_1d_fn = nullptr;
    Sample2dFn m_sample_2d_fn = nullptr;
    Get1dFn m_pixel_1d_fn = nullptr;

    // Current pixel; memoized per-dimension values.
    bool m_have_pixel = false;
    Vec2i m_pixel{0, 0};
    uint64_t m_pixel_key = 0;        // hash(pixel, seed), for the hashed dimensions
    uint64_t m_pixel_index = 0;      // morton(pixel) << m
    uint64_t m_index_high_bits = 0;  // Morton bits above the permuted digits (pixels off-film)
    uint64_t m_prefix_valid = 0;     // bit d: the values of dimension d are filled
    std::array<uint64_t, kLowDiscrepancyDimensions> m_prefix{};         // pixel_digits()
    std::array<uint32_t, kLowDiscrepancyDimensions> m_prefix_pascal{};  // their dim-1 digits
    std::array<uint8_t, kLowDiscrepancyDimensions> m_top_choice{};      // top_sample_choice()

    // Tables of the current pixel (start_pixel()): slot d holds dimension d's values of the
    // samples i in [m_table_lo, m_table_hi) at (d << m) + i.
    bool m_table_pixel = false;  // tables are set up for this pixel
    int m_table_lo = 0, m_table_hi = 0;
    uint64_t m_table_valid_x = 0, m_table_valid_y = 0;  // bit d: slot d's coordinate is filled
    bool m_level_hashes_valid = false;
    std::vector<float> m_table_x, m_table_y;
    std::vector<uint64_t> m_level_hash;            // sample-level node hashes, by level
    std::array<int, kMaxDigits> m_level_offset{};  // where level i's nodes start

    // Current pixel sample.
    int m_sample_index = 0;
    bool m_table_sample = false;        // served from the tables
    bool m_sample_nodes_valid = false;  // compute_sample_nodes() done
    uint64_t m_morton_index = 0;
    uint64_t m_sample_key = 0;                       // key of the hashed dimensions
    std::array<uint64_t, kMaxDigits> m_node_hash{};  // per base-4 digit: hash of the digits above
    std::array<const uint8_t*, kMaxDigits> m_sample_column{};  // per sample digit: its images
    int m_dimension = kPixelDimensions;
};

}  // namespace sr
