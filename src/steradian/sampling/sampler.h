#pragma once
/// Pixel samplers: the source of every random number a path uses.
///
/// Contract (ARCHITECTURE.md Sec. 3): every value is a pure function of (pixel, sample index,
/// dimension, seed). A sampler holds no state that survives start_pixel_sample() except its
/// configuration and memoized values that are themselves pure functions of (pixel, dimension,
/// seed) (the Sobol samplers keep the per-dimension keys of the current pixel, so consecutive
/// samples of one pixel reuse them) or of (pixel, sample index, dimension, seed) (ZSobolSampler's
/// per-pixel tables of the samples a start_pixel() hint announces), so images do not depend on the
/// number of threads, on the order in which pixels are visited, or on how work is scheduled. A
/// Sampler object is not thread-safe: each worker clone()s its own.
///
/// Dimensions: the first kPixelDimensions = 3 dimensions of every pixel sample are reserved for
/// the film-plane offset returned by get_pixel_2d() (dimensions 0 and 1) and the wavelength
/// sample returned by get_pixel_1d() (dimension 2). The Sobol-type samplers draw these three
/// from one index, Sobol dimensions 0, 1 and 2, so that each pixel's samples form a
/// (1,m,3)-net: the samples that land on one side of an edge inside the pixel still have
/// stratified wavelengths (with independently shuffled indices they are a random subset, and
/// the colour noise of a pixel straddling a bright emitter's edge is about twice as large).
/// get_1d() consumes one further dimension
/// and get_2d() two, in call order, starting at kPixelDimensions + the `dimension` argument of
/// start_pixel_sample(). Consumers (camera lens, wavelengths, BSDF and light samples) must
/// request dimensions in a fixed order per path vertex so that the same sample of the same
/// pixel always sees the same numbers.
///
/// Low-discrepancy samplers (ZSobolSampler, PaddedSobolSampler) use their construction for
/// the first kLowDiscrepancyDimensions dimensions (counting the pixel dimensions; a get_2d()
/// counts as low-discrepancy if its first dimension does). Later dimensions, reached only by
/// long paths, are hashed pseudo-random numbers: the splitmix64 stream of a key hashed from
/// (pixel, sample index, seed), read at the dimension. Quasi-Monte Carlo gains nothing
/// measurable that deep in a path, and this keeps every dimension a cheap pure function of
/// (pixel, sample index, dimension, seed).
#include <array>
#include <cstdint>
#include <memory>
#include <string>
#include <vector>

#include "steradian/core/math.h"
#include "steradian/sampling/rng.h"
#include "steradian/sampling/sobol.h"

namespace sr {

/// Dimensions [0, kLowDiscrepancyDimensions) of a pixel sample are low-discrepancy in the
/// Sobol-type samplers; later ones are hashed pseudo-random (see the file comment). 64 covers
/// the camera's 5 dimensions and 11 path vertices of 5 dimensions each.
inline constexpr int kLowDiscrepancyDimensions = 64;

class Sampler {
  public:
    /// Dimensions reserved for get_pixel_2d() and get_pixel_1d().
    static constexpr int kPixelDimensions = 3;

    explicit Sampler(int samples_per_pixel) : m_spp(samples_per_pixel) {}
    virtual ~Sampler();

    int samples_per_pixel() const { return m_spp; }

    /// Positions the sampler on sample `sample_index` (0 <= sample_index < samples_per_pixel())
    /// of `pixel`; the next get_1d()/get_2d() returns dimension kPixelDimensions + dimension.
    virtual void start_pixel_sample(Vec2i pixel, int sample_index, int dimension = 0) = 0;
    /// Optional hint that the next start_pixel_sample() calls are for samples
    /// [first_sample, end_sample) of `pixel`. A sampler may compute per-pixel tables of those
    /// samples' values from it; the values never depend on it (start_pixel_sample() alone
    /// positions the sampler, and a call outside the hinted range still gets its values).
    virtual void start_pixel(Vec2i pixel, int first_sample, int end_sample) {
        (void)pixel, (void)first_sample, (void)end_sample;
    }
    /// Next dimension: a value in [0, 1).
    virtual Float get_1d() = 0;
    /// Next two dimensions: a point in [0, 1)^2, stratified jointly where the sampler can.
    virtual Point2 get_2d() = 0;
    /// Consumes the dimension get_1d() would, without computing it, for a sample the caller
    /// has no use for (a single-lobe BSDF's lobe choice): later dimensions are unchanged.
    virtual void skip_1d() = 0;
    /// Consumes the two dimensions get_2d() would, without computing them, for a sample the
    /// caller has no use for (a pinhole camera's lens sample): later dimensions are unchanged.
    virtual void skip_2d() = 0;
    /// The film-plane offset sample in [0, 1)^2 (the reserved dimensions 0 and 1); does not
    /// advance the dimension counter and may be called at any time after start_pixel_sample().
    virtual Point2 get_pixel_2d() = 0;
    /// The wavelength sample in [0, 1) (the reserved dimension 2), jointly stratified with
    /// get_pixel_2d() where the sampler can; like it, does not advance the dimension counter.
    virtual Float get_pixel_1d() = 0;
    /// A copy with the same configuration (for another thread).
    virtual std::unique_ptr<Sampler> clone() const = 0;
    /// The pbrt-v4 style name of the sampler ("independent", "zsobol", ...).
    virtual std::string name() const = 0;

  protected:
    Sampler(const Sampler&) = default;
    Sampler& operator=(const Sampler&) = default;

  private:
    int m_spp;
};

/// Independent uniform random samples: a PCG32 stream per pixel (selected by a hash of pixel
/// and seed), positioned at sample_index * 65536 + dimension. Supports up to 65536 dimensions
/// per sample. The baseline every other sampler must agree with in expectation.
class IndependentSampler final : public Sampler {
  public:
    IndependentSampler(int samples_per_pixel, uint64_t seed = 0);
    void start_pixel_sample(Vec2i pixel, int sample_index, int dimension = 0) override;
    Float get_1d() override { return m_rng.next_float(); }
    Point2 get_2d() override {
        Float x = m_rng.next_float();
        return {x, m_rng.next_float()};
    }
    void skip_1d() override { m_rng.next_u32(); }
    void skip_2d() override {
        m_rng.next_u32();
        m_rng.next_u32();
    }
    Point2 get_pixel_2d() override;
    Float get_pixel_1d() override;
    std::unique_ptr<Sampler> clone() const override;
    std::string name() const override { return "independent"; }

    static constexpr int64_t kDimensionsPerSample = 65536;

  private:
    uint64_t m_seed;
    Pcg32 m_pixel_rng;  // positioned at the sample's dimension 0
    Pcg32 m_rng;        // positioned at the next dimension
};

/// Stratified (jittered) sampling as in pbrt: x_samples * y_samples samples per pixel; in
/// every dimension (1D: samples_per_pixel strata of [0,1); 2D: an x_samples by y_samples grid)
/// each stratum receives exactly one sample. The sample-to-stratum assignment is a random
/// permutation per (pixel, dimension, seed) (Kensler 2013), so dimensions are decorrelated;
/// jitter places each sample uniformly inside its stratum (otherwise at its centre).
class StratifiedSampler final : public Sampler {
  public:
    StratifiedSampler(int x_samples, int y_samples, bool jitter = true, uint64_t seed = 0);
    void start_pixel_sample(Vec2i pixel, int sample_index, int dimension = 0) override;
    Float get_1d() override;
    Point2 get_2d() override;
    void skip_1d() override { ++m_dimension; }
    void skip_2d() override { m_dimension += 2; }
    Point2 get_pixel_2d() override { return sample_2d(0); }
    Float get_pixel_1d() override { return sample_1d(2); }
    std::unique_ptr<Sampler> clone() const override;
    std::string name() const override { return "stratified"; }

    int x_samples() const { return m_x_samples; }
    int y_samples() const { return m_y_samples; }

  private:
    Float sample_1d(int dimension) const;
    Point2 sample_2d(int dimension) const;

    int m_x_samples, m_y_samples;
    bool m_jitter;
    uint64_t m_seed;
    uint64_t m_pixel_key = 0;
    int m_sample_index = 0;
    int m_dimension = kPixelDimensions;
};

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

/// Creates a sampler from a pbrt-v4 sampler name:
///   "independent"  IndependentSampler
///   "stratified"   StratifiedSampler, jittered, with samples_per_pixel factored into the most
///                  nearly square grid x_samples * y_samples (use make_stratified_sampler to
///                  choose the grid)
///   "zsobol"       ZSobolSampler (Owen scrambling)
///   "halton"       mapped to ZSobolSampler: both are low-discrepancy samplers with screen-space
///                  decorrelation; steradian implements no Halton sequence
///   "sobol"        PaddedSobolSampler, nested uniform shuffle + Owen scrambling (pbrt-v4's
///                  global Sobol sequence is replaced by the padded Owen-scrambled Sobol)
///   "paddedsobol"  PaddedSobolSampler, permutation shuffle + Owen scrambling
///   "pmj02bn"      mapped to "paddedsobol": Owen-scrambled Sobol 2D points are (0,2)-nets
///                  like pmj02 points (without the blue-noise optimization)
/// Throws sr::Error for an unknown name or samples_per_pixel < 1.
std::unique_ptr<Sampler> make_sampler(const std::string& name, int samples_per_pixel,
                                      Vec2i resolution, uint64_t seed = 0);

/// A StratifiedSampler with an explicit grid (pbrt's "xsamples"/"ysamples"). Throws sr::Error
/// if either count is < 1.
std::unique_ptr<Sampler> make_stratified_sampler(int x_samples, int y_samples, bool jitter = true,
                                                 uint64_t seed = 0);

}  // namespace sr
