/// The Sampler interface's destructor and the factories that create a sampler by name.
#include "steradian/sampling/sampler.h"

#include "steradian/core/error.h"
#include "steradian/sampling/independent_sampler.h"
#include "steradian/sampling/padded_sobol_sampler.h"
#include "steradian/sampling/sampler_internal.h"
#include "steradian/sampling/stratified_sampler.h"
#include "steradian/sampling/zsobol_sampler.h"

namespace sr {

using namespace sampler_detail;

Sampler::~Sampler() = default;

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
