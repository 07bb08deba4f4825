#pragma once
/// Meter readings (`steradian measure`, and `render` for scenes with meters): every value
/// to a target relative standard error, with an honest standard error.
///
/// Estimator: randomised quasi-Monte Carlo with independent replicas. A value is the mean
/// of R independent replicas, each the average of n samples of an Owen-scrambled Sobol
/// sampler (PaddedSobolSampler) keyed by (value, replica, round, seed); the standard error
/// is the standard deviation of the replica means over sqrt(R), which is valid because the
/// replicas are independent however the samples within one are correlated. While a value
/// misses its target, a new round doubles n with fresh scrambles (the previous round is
/// discarded: at most half the work). Every number is a pure function of (value, replica,
/// round, sample, dimension, seed) and the replica sums are reduced in a fixed order, so
/// readings do not depend on the number of threads.
///
/// Receiving meters (illuminance, irradiance, grids) place an ideal white Lambertian
/// receiver (f = 1/pi) at the point and estimate E = pi L_o with the path tracer (light
/// sampling and cosine sampling combined by MIS, then the full path); luminance meters
/// average the radiance over their acceptance cone (uniform in solid angle).
#include <atomic>
#include <cstdint>
#include <functional>
#include <string>
#include <vector>

#include "steradian/geometry/hit.h"
#include "steradian/integrators/glare.h"
#include "steradian/sensors/meter.h"
#include "steradian/spectrum/sampled.h"

namespace sr {

class Scene;
class Sampler;
class RadiositySolution;
class WorkCoordinator;
struct PathCounters;

/// A measurement's state between two batches of its work: what a checkpoint saves. Values
/// are the meters' points in order (meter 0's, then meter 1's, ...).
struct MeasureState {
    int round = 0;                   ///< the round in progress (or next)
    std::vector<int64_t> next_n;     ///< per value: samples per replica of that round; 0: done
    std::vector<double> values, stderrs;
    std::vector<int64_t> samples;
    std::vector<uint8_t> converged;
    /// The round in progress, per (pending value, replica) item in order: done, and its mean.
    /// Empty between rounds.
    std::vector<uint8_t> item_done;
    std::vector<double> replica_mean;
    bool time_limited = false;
    uint64_t paths = 0, rays = 0, nonfinite = 0;
    double wall_seconds = 0, cpu_seconds = 0;
};

struct MeasureOptions {
    double rel_error = 1e-3;  ///< target relative standard error of every value
    double time_budget = 0;   ///< seconds; 0 = none. A bound: a round after the pilot is
                              ///< abandoned when it runs out (its values keep their previous
                              ///< estimates, not converged); the pilot round always completes.
    int threads = 0;          ///< 0 = all hardware threads
    uint64_t seed = 0;
    /// When this becomes true, measuring stops as the time budget stops it (the pilot round
    /// completes; a later round is abandoned). Null: never.
    const std::atomic<bool>* stop = nullptr;
    /// Checkpoints: when set, called with the state once `checkpoint_every` seconds have
    /// passed since the last call (0: after every batch of work), and when measuring stops.
    /// The work is then done in batches sized to end about that often.
    std::function<void(const MeasureState&)> checkpoint;
    double checkpoint_every = 0;
    /// Resuming: continue from this state (a checkpoint's, of the same scene and options);
    /// the readings are those of an uninterrupted measurement, bit for bit.
    const MeasureState* resume = nullptr;
    int replicas = 32;        ///< independent randomisations per value (>= 2)
    int first_samples = 32;   ///< samples per replica in the pilot round (power of two)
    /// Samples per replica beyond which a value stops unconverged (a power of two).
    int max_samples = 1 << 22;
    /// Set: the readings by the radiosity method (integrators/radiosity/: direct light by
    /// the path tracer's first vertex, indirect by gather rays reading this solution);
    /// null: by the path tracer.
    const RadiositySolution* radiosity = nullptr;
    /// Distributed measuring (integrators/distributed.h): when set and there are other
    /// processes, each batch's (value, replica) items are shared with them. The readings are
    /// the same bit for bit.
    WorkCoordinator* distribute = nullptr;
    /// Direct light without Monte Carlo (integrators/direct_light.h) where a value's direct
    /// light can be computed so: delta lights exactly, area lights by adaptive quadrature;
    /// the indirect part, if any, stays Monte Carlo. false: every value by samples.
    bool deterministic_direct = true;
    /// Cell-averaged illuminance and irradiance grids by light tracing (light_meters.h;
    /// `--method light`), the other meters as without it. Not with checkpoints or several
    /// processes.
    bool light_trace = false;
};

struct MeterReading {
    Meter meter;  ///< a copy, so a result outlives its scene
    std::vector<double> values;
    std::vector<double> stderrs;
    std::vector<int64_t> samples;   ///< samples spent on the reported estimate
    std::vector<uint8_t> converged; ///< reached the target
    /// How the meter's direct light was computed: "monte carlo" (with the rest of the
    /// light), "deterministic" (the whole reading: direct light only, by closed forms and
    /// quadrature) or "deterministic + monte carlo indirect".
    std::string estimator = "monte carlo";
    /// Per value: no Monte Carlo and no quadrature error (delta lights only): stderr 0.
    std::vector<uint8_t> exact;
    /// Grids: mean, its standard error, minimum, maximum and uniformity U0 = min / mean.
    double avg = 0, avg_stderr = 0, min = 0, max = 0, uniformity = 0;
    /// Glare meters: per point, the rating's details (values and stderrs are the ratings).
    std::vector<GlareReading> glare;
};

struct MeasureResult {
    std::vector<MeterReading> readings;
    double rel_error_target = 0;
    double wall_seconds = 0, cpu_seconds = 0;
    uint64_t paths = 0, rays = 0, nonfinite = 0;
    bool time_limited = false;  ///< stopped early (time budget or MeasureOptions::stop)
    bool interrupted = false;   ///< MeasureOptions::stop was set
    bool all_converged = true;
    /// "path" or "radiosity", and for radiosity the solution's figures (JSON "radiosity").
    std::string method = "path";
    std::vector<std::pair<std::string, double>> method_figures;
};

/// Measures every meter of the scene.
MeasureResult measure(const Scene& scene, const MeasureOptions& options);

/// One sample of value `point` of meter `m` (the sampler positioned on its sample): the
/// meter's quantity in its unit. Exposed for tests.
double meter_sample(const Scene& scene, const Meter& m, size_t point, Sampler& sampler,
                    PathCounters& counters);

/// The pieces of a meter sample that every estimator of it shares (the path tracer's here,
/// the radiosity gather's in integrators/radiosity/gather.cpp):
/// the meter's spectral weighting of a sampled spectrum, the average over the path's
/// wavelengths of w(lambda) L(lambda) / p(lambda);
double meter_weigh(const Meter& m, const SampledSpectrum& L, const SampledWavelengths& lambda);
/// a luminance meter's viewing direction for the 2D sample u (uniform in its cone around dir);
Vec3 meter_view_direction(const Meter& m, Vec3 dir, Point2 u);
/// a receiving meter's vertex: an ideal receiver at p facing n, offset by a few parts per
/// million of |p| (its p_error).
SurfaceHit meter_receiver(Point3 p, Vec3 n);

/// JSON ({"meters": [...]}, docs/photometry.md) and CSV renderings of a result.
std::string meters_json(const MeasureResult& r);
std::string meters_csv(const MeasureResult& r);

}  // namespace sr
