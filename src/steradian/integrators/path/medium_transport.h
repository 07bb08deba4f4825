#pragma once
/// What the volumetric kernels share (integrators/path/volpath.cpp and the bidirectional
/// kernels of integrators/bdpt/ and vcm/): the medium a ray is in after a surface, the
/// random-number stream of a tracking loop, a free flight by delta tracking, and the
/// transmittance of a segment through interfaces and media by ratio tracking.
#include <cstdint>

#include "steradian/core/math.h"
#include "steradian/integrators/path/path.h"
#include "steradian/sampling/rng.h"
#include "steradian/spectrum/sampled.h"

namespace sr {

class Scene;
struct SurfaceHit;

/// The random-number stream of a tracking loop, keyed by two values (sample values, or a
/// shadow ray's origin and direction), so the number of collisions does not shift the
/// sampler's dimensions.
Pcg32 tracking_rng(uint64_t a, uint64_t b);

/// The medium a ray leaving `hit` in direction w is in: the MediumInterface side w points to
/// if the surface is a transition, else `current` (the medium the ray arrived in).
int medium_after(const Scene& scene, const SurfaceHit& hit, Vec3 w, int current);

/// How a free flight ends: the path's end (absorbed, or a weight that became zero or not
/// finite), past the segment, or at a real scattering.
enum class FreeFlight { Absorbed, Passed, Scattered };

/// A free flight along `ray` in `medium` up to t_max by delta tracking against the medium's
/// majorant (pbrt-v4's SampleT_maj, as the bidirectional walks take it): absorption ends the
/// path, a real scattering is a medium vertex at p with phase asymmetry g, null collisions go
/// on; the hero wavelength's probabilities choose and the others are weighted by their ratio
/// to it (beta updated). u: the first flight; uk keys the stream of the later ones and of the
/// collisions' choices.
FreeFlight free_flight(const Scene& scene, int medium, const Ray& ray, Float t_max, Float u,
                       Float uk, const SampledWavelengths& lambda, SampledSpectrum& beta,
                       Point3& p, Float& g);

/// Transmittance along a shadow ray that starts in `medium` (-1: vacuum): zero if a surface
/// with a material blocks it, else the product over its segments (split at interfaces, which
/// change the medium) of ratio-tracking estimates against the media's majorants, with Russian
/// roulette on low values. `to_point`: the ray ends at ray.o + ray.d (t_max < 1) and each
/// segment after an interface is aimed at that point; otherwise it goes to infinity. r_l and
/// r_u are multiplied by the segments' rescaled null-collision probabilities (Miller,
/// Georgiev and Jarosz 2019): the transmittance of one wavelength alone, as pbrt-v4's
/// Integrator::Tr gives it, is the result divided by r_l.average() with r_l starting at 1.
/// `key` keys the ratio-tracking stream together with the ray.
SampledSpectrum shadow_transmittance(const Scene& scene, Ray ray, int medium, bool to_point,
                                     const SampledWavelengths& lambda, SampledSpectrum& r_l,
                                     SampledSpectrum& r_u, uint64_t key, PathCounters& counters);

}  // namespace sr
