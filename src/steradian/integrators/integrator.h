#pragma once
/// Orchestration of rendering (tiles, TBB, passes, progress, time budget), separate from
/// the per-path kernels (path/path.h). Every sample is a pure function of (pixel, sample
/// index, dimension, seed) and each pixel accumulates its samples in index order, so the
/// image does not depend on the number of threads.
#include <atomic>
#include <cstdint>
#include <functional>
#include <string>
#include <utility>
#include <vector>

#include "steradian/film/film.h"

namespace sr {

class Scene;
class RadiositySolution;
class WorkCoordinator;

struct RenderOptions {
    int spp = 0;               ///< samples per pixel; <= 0: the scene's Sampler value
    int threads = 0;           ///< 0: all hardware threads
    uint64_t seed = 0;         ///< added to the scene's sampler seed
    double time_budget = 0;    ///< seconds; 0: none. Stops after the last full pass
                               ///< within it, but completes the first pass (1 spp) always.
    bool progress = false;     ///< draw a progress bar on stderr
    /// When this becomes true (a signal handler sets it), the pass in flight completes and
    /// rendering stops there: the film holds every completed pass. Null: never.
    const std::atomic<bool>* stop = nullptr;
    /// Checkpoints: when set, called at a pass boundary once `checkpoint_every` seconds have
    /// passed since the last call (0: at every boundary), and at the last boundary, with the
    /// statistics so far (the film holds samples [0, stats.spp) of every pixel). Passes are
    /// then sized to end within about `checkpoint_every` seconds.
    std::function<void(const struct RenderStats& so_far)> checkpoint;
    double checkpoint_every = 0;
    /// Resuming: the film already holds samples [0, resume->spp) of every pixel (a
    /// checkpoint's sums, Film::set_sums), and `resume` the statistics of that work.
    const struct RenderStats* resume = nullptr;
    /// Integrator "radiosity": the solution to gather from (render() solves the scene itself
    /// when null).
    const RadiositySolution* radiosity = nullptr;
    /// For tests of "bdpt" (BidirContext): every strategy with weight 1, and only the paths
    /// of this many scattering vertices (-1: all).
    bool bidir_unweighted = false;
    int bidir_only_depth = -1;
    /// Distributed rendering (integrators/distributed.h): when set and there are other
    /// processes, each pass's tiles are shared with them (this process is the coordinator;
    /// they run serve_work()). The image is the same bit for bit.
    WorkCoordinator* distribute = nullptr;
};

/// Largest pass, in samples per pixel: the film takes a pass at a time, so this bounds the
/// work lost to an interruption and the wait for the pass in flight.
inline constexpr int kMaxPassSpp = 64;
/// Pass boundaries (in samples per pixel) are multiples of this, except the total and the
/// 1-spp first pass of a time-budgeted render: a pixel's samples are traced in packets of
/// this many from a multiple of it, so that every schedule of passes that keeps to it traces
/// the same packets, and (each pixel summing its samples in index order whatever the passes)
/// gives the same image bit for bit, a checkpointed and resumed render included.
inline constexpr int kPassAlign = 8;

struct RenderStats {
    double wall_seconds = 0;
    double cpu_seconds = 0;
    int spp = 0;               ///< samples per pixel actually completed
    bool time_limited = false; ///< stopped early by the time budget
    bool interrupted = false;  ///< stopped early by RenderOptions::stop
    uint64_t camera_paths = 0;
    uint64_t rays = 0;         ///< closest-hit plus shadow rays
    uint64_t nonfinite = 0;    ///< NaN/Inf samples zeroed before reaching the film
    size_t peak_rss_bytes = 0;
    /// bdpt's visualizestrategies / visualizeweights images, named as pbrt-v4 names them
    /// (bdpt_dDD_sSS_tTT.exr).
    std::vector<std::pair<std::string, Image>> strategy_images;
    /// Distributed bdpt / lightpath (the splat reduction, docs/distributed.md): the splats
    /// of the completed passes, which the coordinator added in tile order; the bytes of the
    /// workers' splat lists it received and the CPU seconds its thread spent adding splats
    /// (an abandoned pass's included).
    uint64_t dist_splats = 0, dist_splat_bytes = 0;
    double dist_splat_seconds = 0;
};

/// Renders `scene` into `film` with the scene's integrator. Throws sr::Error for
/// unsupported settings.
RenderStats render(const Scene& scene, Film& film, const RenderOptions& options);

/// The samples per pixel render() takes: options.spp if positive, else the scene's
/// Sampler's (for "stratified", xsamples * ysamples).
int render_samples_per_pixel(const Scene& scene, const RenderOptions& options);

/// Process CPU time (user + system) in seconds, and peak resident set size in bytes.
double process_cpu_seconds();
/// The calling thread's CPU time (user + system) in seconds.
double thread_cpu_seconds();
size_t peak_rss_bytes();

}  // namespace sr
