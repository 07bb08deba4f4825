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

class Bsdf;
struct SurfaceHit;
struct VisibleSurface;

/// Which light paths count. A path's vertex count is its number of scattering vertices
/// (emission seen directly by the camera: 0; a camera path's first bounce: 1; a meter's own
/// vertex is its first).
struct PathLimits {
    static constexpr int kSceneDepth = -2;
    /// Paths with fewer scattering vertices contribute nothing (their random numbers are
    /// still drawn, so components of one estimate share them).
    int min_vertices = 0;
    /// Largest number of scattering vertices: kSceneDepth = the integrator's maxdepth,
    /// any other negative value = unlimited (Russian roulette ends the path).
    int max_depth = kSceneDepth;
    /// path_lo only (surface path tracer): the vertex's direct light by one light sample
    /// alone, weighted 1/pdf, with no BSDF sample and no continuation (one shadow ray).
    bool light_sample_only = false;
};

/// The medium a path starts in when the caller does not name one: the camera's
/// (Scene::camera_medium).
inline constexpr int kCameraMedium = -3;

/// Radiance arriving along -ray.d at ray.o, at the wavelengths `lambda` (which a
/// dispersive interface may reduce to the hero wavelength). Uses the scene's integrator
/// settings (max depth, strategy). In a scene with media, ray.o is in `medium` (a
/// Scene::media index, -1: vacuum, or kCameraMedium).
SampledSpectrum path_li(const Scene& scene, Ray ray, SampledWavelengths& lambda, Sampler& sampler,
                        PathCounters& counters, const PathLimits& limits = {},
                        int medium = kCameraMedium);

/// The sample dimensions a camera ray takes after the pixel dimensions (Sampler's
/// kPixelDimensions): the lens sample, taken whether or not the camera has a lens, so that a
/// path's dimensions do not depend on the camera. A camera path's own dimensions start here.
inline constexpr int kCameraDimensions = 2;

/// The light sample of a path's first scattering vertex, whose shadow ray the caller tests:
/// `contribution` belongs to the path's radiance if `ray` is not blocked. (The renderer tests
/// those of a pixel's paths, which start close together and aim at the same lights, as one
/// packet.)
struct DeferredShadowRay {
    bool pending = false;
    Ray ray;
    SampledSpectrum contribution{0};
};

/// path_li() for a ray whose first intersection the caller has already found (camera rays
/// traced as packets): `hit` is that intersection if `found`, and is the path's hit record
/// from then on. With `first_shadow`, the first vertex's light sample is left to the caller
/// there (pending if it has a shadow ray to test) instead of being tested and added. The sum
/// of the result and an unblocked deferred contribution is path_li(scene, ray, ...). With
/// `visible`, the first surface that scatters is recorded there (its `set` false if none;
/// dpdx and dpdy are left to the caller).
///
/// With footprint_scale > 0 (a scene whose textures filter by footprint), `hit` carries the
/// camera ray's footprint (set_footprint_from_rays) and every later vertex gets the camera's
/// approximate one (Camera::approximate_dp_dxy) at that scale.
SampledSpectrum path_li_from(const Scene& scene, const Ray& ray, bool found, SurfaceHit& hit,
                             SampledWavelengths& lambda, Sampler& sampler, PathCounters& counters,
                             DeferredShadowRay* first_shadow = nullptr,
                             VisibleSurface* visible = nullptr, Float footprint_scale = 0);

/// Radiance leaving `vertex` towards vertex.wo, scattered by `bsdf` there (a surface the
/// scene does not contain, e.g. a meter's ideal Lambertian receiver): the path starts with
/// that vertex's light and BSDF samples. In a scene with media, the vertex is in `medium`
/// (a Scene::media index, -1: vacuum) on both sides.
SampledSpectrum path_lo(const Scene& scene, const SurfaceHit& vertex, const Bsdf& bsdf,
                        SampledWavelengths& lambda, Sampler& sampler, PathCounters& counters,
                        const PathLimits& limits = {}, int medium = -1);

}  // namespace sr
