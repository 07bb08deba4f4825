#pragma once
/// The volumetric path tracer (internal to integrators/path/): path_li and its friends call
/// it for a scene whose integrator is volumetric (Integrator "volpath" with media).
#include "steradian/integrators/path/path.h"

namespace sr {

struct SurfaceHit;

/// Radiance along `ray`, which starts in `medium` (-1: vacuum) and whose first surface hit is
/// `hit` if `found`, by delta tracking against the media's majorants, ratio-tracking
/// transmittance on shadow rays, and spectral MIS over the path's wavelengths with rescaled
/// path probabilities (Miller, Georgiev and Jarosz 2019, as pbrt-v4's VolPathIntegrator).
SampledSpectrum volpath_li(const Scene& scene, const Ray& ray, int medium, bool found,
                           SurfaceHit& hit, SampledWavelengths& lambda, Sampler& sampler,
                           PathCounters& counters);

}  // namespace sr
