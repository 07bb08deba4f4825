#pragma once
/// The path-tracing kernel: radiance along one camera ray, with BSDF sampling and
/// next-event estimation (the area form, with visibility) combined by multiple importance
/// sampling (power heuristic), and unbiased Russian roulette. A plain function, so tests
/// can call it on a single ray.
#include <cstdint>

#include "steradian/core/math.h"
#include "steradian/sampling/sampler.h"
#include "steradian/spectrum/sampled.h"

namespace sr {

class Scene;
struct IntegratorSettings;

struct PathCounters {
    uint64_t rays = 0;
};

/// Radiance arriving along -ray.d at ray.o, at the wavelengths `lambda` (which a
/// dispersive interface may reduce to the hero wavelength). Uses the scene's integrator
/// settings (max depth, strategy).
SampledSpectrum path_li(const Scene& scene, Ray ray, SampledWavelengths& lambda, Sampler& sampler,
                        PathCounters& counters);

}  // namespace sr
