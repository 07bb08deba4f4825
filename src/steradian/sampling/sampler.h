#pragma once
/// Pixel samplers: the source of every random number a path uses.
///
/// Contract (ARCHITECTURE.md Sec. 3): every value is a pure function of (pixel, sample index,
/// dimension, seed). A sampler holds no state that survives start_pixel_sample() except its
/// configuration, so images do not depend on the number of threads, on the order in which
/// pixels are visited, or on how work is scheduled. A Sampler object is not thread-safe:
/// each worker clone()s its own.
///
/// Dimensions: the first kPixelDimensions = 2 dimensions of every pixel sample are reserved for
/// the film-plane offset returned by get_pixel_2d(). get_1d() consumes one further dimension
/// and get_2d() two, in call order, starting at kPixelDimensions + the `dimension` argument of
/// start_pixel_sample(). Consumers (camera lens, wavelengths, BSDF and light samples) must
/// request dimensions in a fixed order per path vertex so that the same sample of the same
/// pixel always sees the same numbers.
#include <array>
#include <cstdint>
#include <memory>
#include <string>

#include "steradian/core/math.h"
#include "steradian/sampling/rng.h"
#include "steradian/sampling/sobol.h"

namespace sr {

class Sampler {
  public:
    /// Dimensions reserved for get_pixel_2d().
    static constexpr int kPixelDimensions = 2;

    explicit Sampler(int samples_per_pixel) : m_spp(samples_per_pixel) {}
    virtual ~Sampler();

    int samples_per_pixel() const { return m_spp; }

    /// Positions the sampler on sample `sample_index` (0 <= sample_index < samples_per_pixel())
    /// of `pixel`; the next get_1d()/get_2d() returns dimension kPixelDimensions + dimension.
    virtual void start_pixel_sample(Vec2i pixel, int sample_index, int dimension = 0) = 0;
    /// Next dimension: a value in [0, 1).
    virtual Float get_1d() = 0;
    /// Next two dimensions: a point in [0, 1)^2, stratified jointly where the sampler can.
    virtual Point2 get_2d() = 0;
    /// The film-plane offset sample in [0, 1)^2 (the reserved dimensions 0 and 1); does not
    /// advance the dimension counter and may be called at any time after start_pixel_sample().
    virtual Point2 get_pixel_2d() = 0;
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
    Point2 get_pixel_2d() override;
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
    Point2 get_pixel_2d() override { return sample_2d(0); }
    std::unique_ptr<Sampler> clone() const override;
    std::string name() const override { return "stratified"; }

    int x_samples() const { return m_x_samples; }
    int y_samples() const { return m_y_samples; }

  private:
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
/// The base-4 digits of the index are shuffled by per-level random permutations of {0,1,2,3}
/// hashed from the higher digits, the dimension and the seed (a nested, i.e. Owen-style, shuffle
/// that keeps blocks aligned), and each dimension pair's point is scrambled (default: Burley's
/// hash-based Owen scrambling) with a key hashed from the dimension and seed.
/// Every get_1d() uses Sobol dimension 0, every get_2d() Sobol dimensions 0 and 1: the padding
/// of pbrt-v4, decorrelated across dimensions by the shuffles and scramblings.
/// Requires sample_index < samples_per_pixel() (larger indices would alias into the next
/// pixel's block) and pixels inside the resolution given here (others still work but lose the
/// screen-space structure).
class ZSobolSampler final : public Sampler {
  public:
    /// resolution: the film's pixel count (x, y); pixels should lie in [0, resolution).
    ZSobolSampler(int samples_per_pixel, Vec2i resolution, uint64_t seed = 0,
                  Randomization randomize = Randomization::kOwen);
    void start_pixel_sample(Vec2i pixel, int sample_index, int dimension = 0) override;
    Float get_1d() override;
    Point2 get_2d() override;
    Point2 get_pixel_2d() override { return sample_2d(0); }
    std::unique_ptr<Sampler> clone() const override;
    std::string name() const override { return "zsobol"; }

    /// The shuffled global Sobol index of the current pixel sample for `dimension`.
    uint64_t sobol_index(int dimension) const;

  private:
    Point2 sample_2d(int dimension) const;
    uint64_t dimension_key(int dimension) const {
        return hash_combine(m_seed_key, uint64_t(dimension));
    }

    uint64_t m_seed_key;
    Randomization m_randomize;
    int m_log2_spp;
    int m_num_base4_digits;
    uint64_t m_morton_index = 0;
    uint64_t m_index_high_bits = 0;  // Morton bits above the permuted digits (pixels off-film)
    std::array<uint64_t, 32> m_node_hash{};  // per base-4 digit: hash of the digits above it
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
class PaddedSobolSampler final : public Sampler {
  public:
    PaddedSobolSampler(int samples_per_pixel, uint64_t seed = 0,
                       SobolIndexShuffle shuffle = SobolIndexShuffle::kNestedUniform,
                       Randomization randomize = Randomization::kOwen);
    void start_pixel_sample(Vec2i pixel, int sample_index, int dimension = 0) override;
    Float get_1d() override;
    Point2 get_2d() override;
    Point2 get_pixel_2d() override { return sample_2d(0); }
    std::unique_ptr<Sampler> clone() const override;
    /// "sobol" for the nested uniform shuffle, "paddedsobol" for the permutation shuffle.
    std::string name() const override;

  private:
    uint32_t shuffled_index(uint64_t key) const;
    Point2 sample_2d(int dimension) const;

    uint64_t m_seed;
    SobolIndexShuffle m_shuffle;
    Randomization m_randomize;
    uint64_t m_pixel_key = 0;
    int m_sample_index = 0;
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
