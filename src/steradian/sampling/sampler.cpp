#include "steradian/sampling/sampler.h"

#include <algorithm>
#include <array>
#include <bit>

#include "steradian/core/error.h"
#include "steradian/sampling/hash.h"

namespace sr {

// ---- randomization names ----------------------------------------------------------------------

Randomization randomization_from_string(const std::string& name) {
    if (name == "none") return Randomization::kNone;
    if (name == "permutedigits") return Randomization::kXor;
    if (name == "fastowen" || name == "owen") return Randomization::kOwen;
    throw Error(fmt::format(
        "unknown sample randomization \"{}\" (expected none, permutedigits, fastowen or owen)",
        name));
}

std::string to_string(Randomization r) {
    switch (r) {
        case Randomization::kNone:
            return "none";
        case Randomization::kXor:
            return "permutedigits";
        case Randomization::kOwen:
            return "owen";
    }
    return "?";
}

namespace {

/// Point in [0,1)^2 of the (0,2)-sequence at index a, each coordinate randomized with its own
/// 32-bit half of key.
Point2 sobol_2d(uint64_t a, Randomization r, uint64_t key) {
    return {u32_to_unit_float(randomize(sobol_u32_dim0(a), r, uint32_t(key))),
            u32_to_unit_float(randomize(sobol_u32_dim1(a), r, uint32_t(key >> 32)))};
}

/// A value in stratum `stratum` of n equal strata of [0, 1), at fraction delta in [0, 1) of
/// the stratum. Nudged by an ulp if float rounding would put it in a neighbouring stratum (or
/// on 1), so stratification holds exactly for the returned floats.
Float stratum_sample(int stratum, double delta, int n) {
    auto f = Float((double(stratum) + delta) / double(n));
    while (f > 0 && double(f) * n >= double(stratum) + 1) f = std::nextafter(f, Float(0));
    while (double(f) * n < double(stratum)) f = std::nextafter(f, Float(1));
    return f;
}

/// Jitter fraction in [0, 1) from 32 hash bits, or the stratum centre.
double jitter_fraction(bool jitter, uint32_t bits) { return jitter ? double(bits) * 0x1p-32 : 0.5; }

void check_spp(int spp) {
    if (spp < 1) throw Error(fmt::format("samples per pixel must be at least 1, not {}", spp));
}

/// The 24 permutations of {0, 1, 2, 3} in lexicographic order.
constexpr std::array<std::array<uint8_t, 4>, 24> make_base4_permutations() {
    std::array<std::array<uint8_t, 4>, 24> perms{};
    std::array<uint8_t, 4> p{0, 1, 2, 3};
    for (auto& out : perms) {
        out = p;
        std::next_permutation(p.begin(), p.end());
    }
    return perms;
}
constexpr auto kBase4Permutations = make_base4_permutations();

}  // namespace

Sampler::~Sampler() = default;

// ---- IndependentSampler -----------------------------------------------------------------------

IndependentSampler::IndependentSampler(int samples_per_pixel, uint64_t seed)
    : Sampler(samples_per_pixel), m_seed(seed) {
    check_spp(samples_per_pixel);
}

void IndependentSampler::start_pixel_sample(Vec2i pixel, int sample_index, int dimension) {
    m_pixel_rng.set_sequence(hash(pixel, m_seed));
    m_pixel_rng.advance(int64_t(sample_index) * kDimensionsPerSample);
    m_rng = m_pixel_rng;
    m_rng.advance(kPixelDimensions + dimension);
}

Point2 IndependentSampler::get_pixel_2d() {
    Pcg32 rng = m_pixel_rng;
    Float x = rng.next_float();
    return {x, rng.next_float()};
}

std::unique_ptr<Sampler> IndependentSampler::clone() const {
    return std::make_unique<IndependentSampler>(*this);
}

// ---- StratifiedSampler ------------------------------------------------------------------------

StratifiedSampler::StratifiedSampler(int x_samples, int y_samples, bool jitter, uint64_t seed)
    : Sampler(x_samples * y_samples),
      m_x_samples(x_samples),
      m_y_samples(y_samples),
      m_jitter(jitter),
      m_seed(seed) {
    if (x_samples < 1 || y_samples < 1) {
        throw Error(fmt::format("stratified sampler needs at least 1 x 1 samples, not {} x {}",
                                x_samples, y_samples));
    }
}

void StratifiedSampler::start_pixel_sample(Vec2i pixel, int sample_index, int dimension) {
    m_pixel_key = hash(pixel, m_seed);
    m_sample_index = sample_index;
    m_dimension = kPixelDimensions + dimension;
}

Float StratifiedSampler::get_1d() {
    uint64_t key = hash_combine(m_pixel_key, uint64_t(m_dimension));
    ++m_dimension;
    int n = samples_per_pixel();
    auto stratum = int(permutation_element(uint32_t(m_sample_index), uint32_t(n), uint32_t(key)));
    uint64_t jitter_bits = hash_combine(key, uint64_t(m_sample_index));
    return stratum_sample(stratum, jitter_fraction(m_jitter, uint32_t(jitter_bits)), n);
}

Point2 StratifiedSampler::get_2d() {
    Point2 p = sample_2d(m_dimension);
    m_dimension += 2;
    return p;
}

Point2 StratifiedSampler::sample_2d(int dimension) const {
    uint64_t key = hash_combine(m_pixel_key, uint64_t(dimension));
    auto stratum = int(permutation_element(uint32_t(m_sample_index), uint32_t(samples_per_pixel()),
                                           uint32_t(key)));
    uint64_t jitter_bits = hash_combine(key, uint64_t(m_sample_index));
    int sx = stratum % m_x_samples, sy = stratum / m_x_samples;
    return {
        stratum_sample(sx, jitter_fraction(m_jitter, uint32_t(jitter_bits)), m_x_samples),
        stratum_sample(sy, jitter_fraction(m_jitter, uint32_t(jitter_bits >> 32)), m_y_samples)};
}

std::unique_ptr<Sampler> StratifiedSampler::clone() const {
    return std::make_unique<StratifiedSampler>(*this);
}

// ---- ZSobolSampler ----------------------------------------------------------------------------

ZSobolSampler::ZSobolSampler(int samples_per_pixel, Vec2i resolution, uint64_t seed,
                             Randomization randomize)
    : Sampler(samples_per_pixel), m_seed_key(mix_bits(seed)), m_randomize(randomize) {
    check_spp(samples_per_pixel);
    if (resolution.x < 1 || resolution.y < 1) {
        throw Error(
            fmt::format("zsobol sampler: invalid resolution {} x {}", resolution.x, resolution.y));
    }
    m_log2_spp = int(std::bit_width(uint32_t(samples_per_pixel) - 1));  // ceil(log2(spp))
    int log2_res = int(std::bit_width(uint32_t(std::max(resolution.x, resolution.y)) - 1));
    m_num_base4_digits = log2_res + (m_log2_spp + 1) / 2;
    if (2 * log2_res + m_log2_spp > 64) {
        throw Error("zsobol sampler: resolution x samples per pixel exceed 64-bit sample indices");
    }
}

void ZSobolSampler::start_pixel_sample(Vec2i pixel, int sample_index, int dimension) {
    m_morton_index = (encode_morton2(uint32_t(pixel.x), uint32_t(pixel.y)) << m_log2_spp) |
                     uint64_t(uint32_t(sample_index));
    m_dimension = kPixelDimensions + dimension;
    // Digits are base 4 from the top; if log2(spp) is odd, the lowest digit is a single bit, so
    // that the boundary between pixel bits and sample bits is always a digit boundary. Each
    // digit is a node of the quadtree over (pixels, samples), identified by the digits above it
    // and its level; hash those once per pixel sample, leaving one multiply per digit and
    // dimension for sobol_index().
    int odd = m_log2_spp & 1;
    int top_shift = 2 * m_num_base4_digits - odd;
    m_index_high_bits = top_shift < 64 ? (m_morton_index >> top_shift) << top_shift : 0;
    for (int i = odd; i < m_num_base4_digits; ++i) {
        int shift = 2 * i - odd;
        uint64_t higher = shift + 2 < 64 ? m_morton_index >> (shift + 2) : 0;
        m_node_hash[std::size_t(i)] = mix_bits((higher ^ m_seed_key) + kGolden64 * uint64_t(i + 1));
    }
    if (odd) m_node_hash[0] = mix_bits((m_morton_index >> 1) ^ m_seed_key);
}

uint64_t ZSobolSampler::sobol_index(int dimension) const {
    // Per-node random permutation of the four quadrants (Ahmed & Wonka 2020, Sec. 4: a nested,
    // Owen-style shuffle of the Morton index in base 4), chosen from the node's hash and the
    // dimension's key by an odd multiply (a bijection whose top bits depend on all bits).
    constexpr uint64_t kMul = 0xd6e8feb86659fd93ULL;
    uint64_t key = dimension_key(dimension);
    int odd = m_log2_spp & 1;
    uint64_t result = m_index_high_bits;
    for (int i = odd; i < m_num_base4_digits; ++i) {
        int shift = 2 * i - odd;
        uint64_t digit = (m_morton_index >> shift) & 3;
        uint64_t t = (m_node_hash[std::size_t(i)] ^ key) * kMul;
        auto perm = std::size_t(((t >> 32) * 24) >> 32);
        result |= uint64_t(kBase4Permutations[perm][digit]) << shift;
    }
    if (odd) {
        uint64_t flip = ((m_node_hash[0] ^ key) * kMul) >> 63;
        result |= (m_morton_index & 1) ^ flip;
    }
    return result;
}

Float ZSobolSampler::get_1d() {
    uint64_t a = sobol_index(m_dimension);
    uint64_t scramble_key = mix_bits(dimension_key(m_dimension));
    ++m_dimension;
    return u32_to_unit_float(randomize(sobol_u32_dim0(a), m_randomize, uint32_t(scramble_key)));
}

Point2 ZSobolSampler::get_2d() {
    Point2 p = sample_2d(m_dimension);
    m_dimension += 2;
    return p;
}

Point2 ZSobolSampler::sample_2d(int dimension) const {
    return sobol_2d(sobol_index(dimension), m_randomize, mix_bits(dimension_key(dimension)));
}

std::unique_ptr<Sampler> ZSobolSampler::clone() const {
    return std::make_unique<ZSobolSampler>(*this);
}

// ---- PaddedSobolSampler -----------------------------------------------------------------------

PaddedSobolSampler::PaddedSobolSampler(int samples_per_pixel, uint64_t seed,
                                       SobolIndexShuffle shuffle, Randomization randomize)
    : Sampler(samples_per_pixel), m_seed(seed), m_shuffle(shuffle), m_randomize(randomize) {
    check_spp(samples_per_pixel);
}

void PaddedSobolSampler::start_pixel_sample(Vec2i pixel, int sample_index, int dimension) {
    m_pixel_key = hash(pixel, m_seed);
    m_sample_index = sample_index;
    m_dimension = kPixelDimensions + dimension;
}

uint32_t PaddedSobolSampler::shuffled_index(uint64_t key) const {
    if (m_shuffle == SobolIndexShuffle::kPermutation) {
        return permutation_element(uint32_t(m_sample_index), uint32_t(samples_per_pixel()),
                                   uint32_t(key));
    }
    return nested_uniform_shuffle(uint32_t(m_sample_index), uint32_t(key));
}

Float PaddedSobolSampler::get_1d() {
    uint64_t key = hash_combine(m_pixel_key, uint64_t(m_dimension));
    ++m_dimension;
    uint32_t a = shuffled_index(key);
    uint64_t scramble_key = mix_bits(key);
    return u32_to_unit_float(randomize(sobol_u32_dim0(a), m_randomize, uint32_t(scramble_key)));
}

Point2 PaddedSobolSampler::get_2d() {
    Point2 p = sample_2d(m_dimension);
    m_dimension += 2;
    return p;
}

Point2 PaddedSobolSampler::sample_2d(int dimension) const {
    uint64_t key = hash_combine(m_pixel_key, uint64_t(dimension));
    return sobol_2d(shuffled_index(key), m_randomize, mix_bits(key));
}

std::unique_ptr<Sampler> PaddedSobolSampler::clone() const {
    return std::make_unique<PaddedSobolSampler>(*this);
}

std::string PaddedSobolSampler::name() const {
    return m_shuffle == SobolIndexShuffle::kPermutation ? "paddedsobol" : "sobol";
}

// ---- factories --------------------------------------------------------------------------------

std::unique_ptr<Sampler> make_stratified_sampler(int x_samples, int y_samples, bool jitter,
                                                 uint64_t seed) {
    return std::make_unique<StratifiedSampler>(x_samples, y_samples, jitter, seed);
}

std::unique_ptr<Sampler> make_sampler(const std::string& name, int samples_per_pixel,
                                      Vec2i resolution, uint64_t seed) {
    check_spp(samples_per_pixel);
    if (name == "independent") return std::make_unique<IndependentSampler>(samples_per_pixel, seed);
    if (name == "stratified") {
        // Most nearly square factorization spp = x * y with x <= y.
        int x = 1;
        for (int d = 1; d * d <= samples_per_pixel; ++d) {
            if (samples_per_pixel % d == 0) x = d;
        }
        return make_stratified_sampler(x, samples_per_pixel / x, true, seed);
    }
    if (name == "zsobol" || name == "halton") {
        return std::make_unique<ZSobolSampler>(samples_per_pixel, resolution, seed);
    }
    if (name == "sobol") {
        return std::make_unique<PaddedSobolSampler>(samples_per_pixel, seed,
                                                    SobolIndexShuffle::kNestedUniform);
    }
    if (name == "paddedsobol" || name == "pmj02bn") {
        return std::make_unique<PaddedSobolSampler>(samples_per_pixel, seed,
                                                    SobolIndexShuffle::kPermutation);
    }
    throw Error(fmt::format(
        "unknown sampler \"{}\" (expected independent, stratified, zsobol, halton, sobol, "
        "paddedsobol or pmj02bn)",
        name));
}

}  // namespace sr
