#pragma once
/// Pixel samplers: the source of every random number a path uses.
///
/// Contract (docs/architecture.md, "The sampler's dimension discipline"): every value is a pure
/// function of (pixel, sample index, dimension, seed). A sampler holds no state that survives
/// start_pixel_sample() except its configuration and memoized values that are themselves pure
/// functions of (pixel, dimension, seed) (the Sobol samplers keep the per-dimension keys of the
/// current pixel, so consecutive samples of one pixel reuse them) or of (pixel, sample index,
/// dimension, seed) (ZSobolSampler's per-pixel tables of the samples a start_pixel() hint
/// announces), so images do not depend on the number of threads, on the order in which pixels are
/// visited, or on how work is scheduled. A Sampler object is not thread-safe: each worker clone()s
/// its own.
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
///
/// The samplers: IndependentSampler (independent_sampler.h), StratifiedSampler
/// (stratified_sampler.h), ZSobolSampler (zsobol_sampler.h) and PaddedSobolSampler
/// (padded_sobol_sampler.h); make_sampler() below creates any of them by name.
#include <cstdint>
#include <memory>
#include <string>

#include "steradian/core/math.h"

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
