#pragma once
/// Helpers shared by the samplers' implementations (internal to src/steradian/sampling/): the
/// hashed dimensions, the samples-per-pixel check and the Sobol dimension-1 digit table.
#include <array>
#include <cstdint>

#include "steradian/core/error.h"
#include "steradian/core/math.h"
#include "steradian/sampling/hash.h"
#include "steradian/sampling/rng.h"
#include "steradian/sampling/sobol.h"

namespace sr::sampler_detail {

/// Key of the hashed (pseudo-random) dimensions of a pixel sample; distinct from the
/// hash_combine(pixel_key, dimension) keys (their second argument is below 2^32).
inline uint64_t hashed_dimensions_key(uint64_t pixel_key, int sample_index) {
    return hash_combine(pixel_key, (uint64_t(1) << 32) + uint32_t(sample_index));
}

/// Dimension d >= kLowDiscrepancyDimensions: output d of the splitmix64 generator started at
/// the sample's key (Steele, Lea, Flood 2014), 32 bits per value.
[[gnu::noinline]] inline Float hashed_1d(uint64_t sample_key, int d) {
    return u32_to_unit_float(uint32_t(mix_bits(sample_key + kGolden64 * uint64_t(d)) >> 32));
}
[[gnu::noinline]] inline Point2 hashed_2d(uint64_t sample_key, int d) {
    uint64_t bits = mix_bits(sample_key + kGolden64 * uint64_t(d));
    return {u32_to_unit_float(uint32_t(bits >> 32)), u32_to_unit_float(uint32_t(bits))};
}

inline void check_spp(int spp) {
    if (spp < 1) throw Error(fmt::format("samples per pixel must be at least 1, not {}", spp));
}

/// Sobol dimension-1 digits (pascal_mod2_transform) of the indices below 256. The transform is
/// linear over GF(2) and maps bits below 2^k to bits below 2^k, so the digits of an index whose
/// high bits are shared by a pixel's samples split into a memoized high part and this table.
constexpr std::array<uint8_t, 256> make_pascal8() {
    std::array<uint8_t, 256> t{};
    for (std::size_t i = 0; i < 256; ++i) t[i] = uint8_t(pascal_mod2_transform(i));
    return t;
}
inline constexpr auto kPascal8 = make_pascal8();

}  // namespace sr::sampler_detail
