#pragma once
/// The volumetric path tracer (internal to integrators/path/): path_li and its friends call
/// it for a scene whose integrator is volumetric (Integrator "volpath" with media).
#include "steradian/integrators/path/path.h"

namespace sr {

struct SurfaceHit;
class Bsdf;

/// Radiance along `ray`, which starts in `medium` (-1: vacuum) and whose first surface hit is
/// `hit` if `found`, by delta tracking against the media's majorants, ratio-tracking
/// transmittance on shadow rays, and spectral MIS over the path's wavelengths with rescaled
/// path probabilities (Miller, Georgiev and Jarosz 2019, as pbrt-v4's VolPathIntegrator).
/// `limits` as path_li's, with one difference from a render's own (kSceneDepth) limit: a
/// medium's emission after k vertices counts where k <= max_depth, as a surface's does
/// (pbrt-v4's volpath, whose rule a render keeps, counts it only where k < maxdepth).
SampledSpectrum volpath_li(const Scene& scene, const Ray& ray, int medium, bool found,
                           SurfaceHit& hit, SampledWavelengths& lambda, Sampler& sampler,
                           PathCounters& counters, const PathLimits& limits = {});

/// path_lo() in a scene rendered by the volumetric kernel: the vertex (not one of the scene's
/// surfaces) scatters with `bsdf` and sits in `medium` on both sides.
SampledSpectrum volpath_lo(const Scene& scene, const SurfaceHit& vertex, const Bsdf& bsdf,
                           int medium, SampledWavelengths& lambda, Sampler& sampler,
                           PathCounters& counters, const PathLimits& limits);

}  // namespace sr
