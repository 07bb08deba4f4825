#pragma once
/// Illuminance grids by light tracing (`steradian measure --method light`; docs/photometry.md):
/// particles from the lights, traced as `lightpath` traces them, and every cell of every
/// cell-averaged grid estimated at once from the particles that cross it.
///
/// A grid is a virtual receiver: a plane that blocks nothing. A particle carries flux (its
/// path throughput: the emitted radiance times the cosine over the densities that chose it);
/// the flux that crosses a cell from its front (against the grid's normal) over the cell's
/// area is an unbiased estimate of the cell's mean irradiance, E = dPhi / dA. Point meters
/// cannot be light-traced (a particle never meets a point), nor can luminance meters.
#include <atomic>
#include <cstdint>
#include <vector>

#include "steradian/integrators/measure.h"

namespace sr {

class Scene;

/// Whether meter m can be measured by light tracing: an illuminance or irradiance grid of
/// cell averages (`"bool cellaverage" true`), in vacuum, and not a glare meter.
bool light_traceable(const Scene& scene, const Meter& m);

struct LightMeterOptions {
    double rel_error = 0.01;  ///< target relative standard error per cell
    int replicas = 16;        ///< independent batches; their spread gives the standard error
    uint64_t first_paths = 1 << 14;  ///< particles per replica in the first round
    uint64_t max_paths = uint64_t(1) << 26;  ///< per replica, beyond which rounds stop
    uint64_t seed = 0;
    int threads = 0;
    const std::atomic<bool>* stop = nullptr;  ///< polled between chunks; abandons a round
    double time_budget = 0;  ///< seconds (0: none); no round starts that would not fit
};

struct LightMeterStats {
    uint64_t paths = 0, rays = 0, nonfinite = 0;
    bool time_limited = false;
};

/// Measures meters `which` (indices into scene.meters, each light_traceable) by light
/// tracing, in rounds that double the particles of every replica until every cell's
/// relative standard error meets the target (a cell that stays dark is converged once its
/// error is under the target times the grid's mean). Fills readings[which[k]]: values,
/// stderrs, samples (particles per cell: all of them), converged, estimator, and the grid's
/// avg (with its standard error from the replicas' grid means), min, max and U0. The same on
/// any number of threads.
void light_trace_meters(const Scene& scene, const std::vector<int>& which,
                        const LightMeterOptions& options, std::vector<MeterReading>& readings,
                        LightMeterStats& stats);

}  // namespace sr
