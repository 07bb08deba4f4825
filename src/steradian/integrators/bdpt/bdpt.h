#pragma once
/// Bidirectional estimators: pbrt-v4's "bdpt" (Veach 1997, ch. 10; every (s, t) strategy,
/// combined by the power heuristic with weights computed in O(s + t) by Veach's recursion)
/// and "lightpath" (particle tracing from the lights, splatted onto the film through the
/// camera's importance). Plain functions of one pixel sample, as path_li is: the caller
/// (integrators/render.cpp) owns tiles, passes and the order in which splats are reduced.
#include <cstdint>
#include <memory>
#include <vector>

#include "steradian/core/math.h"
#include "steradian/integrators/path/path.h"
#include "steradian/sampling/sampler.h"
#include "steradian/spectrum/sampled.h"

namespace sr {

class Scene;

/// Where the contributions of strategies that reach the camera through its importance
/// (t = 1) land: a film position (raster space) and radiance at the sample's wavelengths.
/// With BidirContext::visualize, strategy() receives every strategy's unweighted
/// contribution and its MIS weight, for visualizestrategies / visualizeweights (p_raster:
/// the camera sample's film position for t >= 2).
class SplatSink {
public:
    virtual ~SplatSink() = default;
    virtual void splat(Point2 p_raster, const SampledSpectrum& L) = 0;
    virtual void strategy(int s, int t, Point2 p_raster, const SampledSpectrum& L, Float weight) {
        (void)s, (void)t, (void)p_raster, (void)L, (void)weight;
    }
};

/// What the estimators need besides the scene.
struct BidirContext {
    explicit BidirContext(const Scene& scene);
    const Scene& scene;
    /// The film area camera samples cover (raster space): the crop window's pixels widened
    /// by the filter's radius. Importance is zero outside it.
    Float bounds[4] = {0, 0, 0, 0};
    /// Full resolution / crop window pixels: light paths are traced per pixel sample of the
    /// crop window but land anywhere on the film (pbrt-v4 issue 347).
    Float crop_factor = 1;
    int max_depth = 5;
    bool regularize = false;
    bool visualize = false;  ///< call SplatSink::strategy for each strategy's contribution
    /// Tests: give each strategy weight 1 (every strategy an estimator of its own), and
    /// count only paths of this many scattering vertices (-1: every length).
    bool unweighted = false;
    int only_depth = -1;
    Point3 scene_center;
    Float scene_radius = 1;  ///< the infinite lights' disk radius
    bool inside(Point2 p) const {
        return p.x >= bounds[0] && p.x < bounds[2] && p.y >= bounds[1] && p.y < bounds[3];
    }
};

/// Throws sr::Error (naming the integrator) when the scene has something the bidirectional
/// estimators cannot trace: a camera without importance (orthographic), an emissive medium or
/// a subsurface material (pbrt-v4's bdpt ignores both), a light that cannot emit particles
/// (an environment map with a portal). Other media are traced.
void check_bidir_scene(const Scene& scene, const char* integrator);

/// Per-thread storage of the subpaths (kept between samples to avoid allocations).
struct BdptScratch;
struct BdptScratchDeleter {
    void operator()(BdptScratch* p) const;
};
using BdptScratchPtr = std::unique_ptr<BdptScratch, BdptScratchDeleter>;
BdptScratchPtr make_bdpt_scratch();

/// One bdpt sample: the camera subpath from `camera_ray` (film position p_film), a light
/// subpath, and every connection. Returns the sum of the strategies with t >= 2 (the pixel's
/// sample); t = 1 contributions go to `sink`.
SampledSpectrum bdpt_li(const BidirContext& ctx, BdptScratch& scratch, const Ray& camera_ray,
                        Point2 p_film, SampledWavelengths& lambda, Sampler& sampler,
                        PathCounters& counters, SplatSink& sink);

/// One strategy (s, t) of bdpt alone, for Metropolis light transport (integrators/mlt/;
/// pbrt-v4's MLTIntegrator::L): a camera subpath of exactly t vertices from `camera_ray`,
/// whose random numbers come from `camera`, a light subpath of exactly s vertices from
/// `light`, and the connection's numbers from `connection` (separate streams, so that a
/// change of one subpath does not shift the numbers of the other). Returns the connection's
/// contribution times its MIS weight (as bdpt_li weighs it), zero when a subpath ends before
/// its length; for t = 1, p_raster is set to where the connection meets the film.
SampledSpectrum bdpt_strategy(const BidirContext& ctx, BdptScratch& scratch, int s, int t,
                              const Ray& camera_ray, SampledWavelengths& lambda, Sampler& camera,
                              Sampler& light, Sampler& connection, PathCounters& counters,
                              Point2& p_raster);

/// One lightpath sample: a light subpath whose every vertex (the light's own included) is
/// connected to the camera and splatted (unweighted: the only strategy).
void lightpath_sample(const BidirContext& ctx, BdptScratch& scratch, SampledWavelengths& lambda,
                      Sampler& sampler, PathCounters& counters, SplatSink& sink);

namespace bdpt_test {
/// For tests of the MIS weights: traces a camera subpath and a light subpath as bdpt_li
/// does, then returns for each (s, t) with s + t = n_vertices the power-heuristic weight
/// the O(s + t) recursion gives the path made of the first s light and first t camera
/// vertices, and the weight computed directly from the full path's densities (Veach's
/// eq. 10.9 with exponent 2), for every split of one complete camera path that ends on an
/// emitter. Entries: {s, recursive weight, direct weight}; empty if the camera path does
/// not end on an emitter within the depth.
struct WeightCheck {
    int s;
    double recursive, direct;
    int medium_vertices = 0;  ///< the path's scattering vertices in media
};
std::vector<WeightCheck> mis_weights_of_camera_path(const BidirContext& ctx, const Ray& ray,
                                                    SampledWavelengths& lambda, Sampler& sampler,
                                                    int n_vertices);
}  // namespace bdpt_test

}  // namespace sr
