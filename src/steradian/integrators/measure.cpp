#include "steradian/integrators/measure.h"

#include <chrono>
#include <cmath>
#include <thread>

#include <fmt/format.h>
#include <nlohmann/json.hpp>
#include <tbb/global_control.h>
#include <tbb/parallel_for.h>
#include <tbb/task_arena.h>

#include "steradian/bsdf/bsdf.h"
#include "steradian/integrators/direct_light.h"
#include "steradian/integrators/distributed.h"
#include "steradian/integrators/integrator.h"
#include "steradian/integrators/path/path.h"
#include "steradian/integrators/light_meters.h"
#include "steradian/integrators/radiosity/radiosity.h"
#include "steradian/sampling/hash.h"
#include "steradian/sampling/padded_sobol_sampler.h"
#include "steradian/sampling/sampler.h"
#include "steradian/sampling/warp.h"
#include "steradian/scene/scene.h"

namespace sr {

// (Terminated secondary wavelengths have pdf 0, and the hero's pdf already carries the 1/N.)
double meter_weigh(const Meter& m, const SampledSpectrum& L, const SampledWavelengths& lambda) {
    double sum = 0;
    for (int i = 0; i < kSpectrumSamples; ++i)
        if (lambda.pdf[i] > 0)
            sum += double(L[i]) * double(m.spectral_weight(lambda.lambda[i])) / double(lambda.pdf[i]);
    return sum / kSpectrumSamples;
}

Vec3 meter_view_direction(const Meter& m, Vec3 dir, Point2 u) {
    if (!(m.cone_half_angle > 0)) return dir;
    return Frame::from_z(dir).to_world(sample_uniform_cone(u, std::cos(m.cone_half_angle)));
}

SurfaceHit meter_receiver(Point3 p, Vec3 n) {
    SurfaceHit v;
    v.p = p;
    Float err = (std::abs(p.x) + std::abs(p.y) + std::abs(p.z) + 1) * Float(2e-6);
    v.p_error = Vec3(err, err, err);
    v.ng = v.ns = v.wo = n;
    v.dpdu = Frame::from_z(n).s;
    return v;
}

namespace {

PathLimits limits_of(const Meter& m, MeterComponent component) {
    PathLimits lim;
    lim.max_depth = m.max_depth < 0 ? -1 : m.max_depth;
    if (component == MeterComponent::Direct) lim.max_depth = 1;
    if (component == MeterComponent::Indirect) lim.min_vertices = 2;
    return lim;
}

/// meter_sample counting `component` of the light (the meter's own, or its indirect part
/// where the direct part is computed deterministically).
double meter_sample_of(const Scene& scene, const Meter& m, size_t point, Sampler& sampler,
                       PathCounters& counters, MeterComponent component);

/// Below this fraction of its meter's largest value, a deterministic value's target is
/// absolute (measure(), below).
constexpr double kDarkFraction = 1e-3;

/// How a meter's value is computed (MeasureOptions::deterministic_direct).
enum class DirectPlan : uint8_t {
    MonteCarlo,     ///< all of it by samples
    Deterministic,  ///< all of it is direct light: closed forms and quadrature
    Split,          ///< direct light deterministic, indirect by samples
};

std::vector<DirectPlan> direct_plans(const Scene& scene, const MeasureOptions& opt) {
    std::vector<DirectPlan> plans(scene.meters.size(), DirectPlan::MonteCarlo);
    if (!opt.deterministic_direct || !direct_light_deterministic(scene)) return plans;
    const bool scatters = scene_may_scatter(scene);
    for (size_t i = 0; i < plans.size(); ++i) {
        const Meter& m = scene.meters[i];
        if ((m.kind != MeterKind::Point && m.kind != MeterKind::Grid) || m.cell_average || m.medium >= 0 ||
            m.component == MeterComponent::Indirect || m.max_depth == 0)
            continue;
        if (m.component == MeterComponent::Direct || m.max_depth == 1 || !scatters)
            plans[i] = DirectPlan::Deterministic;
        else  // by either method: the radiosity gather then reads only the indirect part
            plans[i] = DirectPlan::Split;
    }
    return plans;
}

}  // namespace

double meter_sample(const Scene& scene, const Meter& m, size_t point, Sampler& sampler,
                    PathCounters& counters) {
    return meter_sample_of(scene, m, point, sampler, counters, m.component);
}

namespace {

double meter_sample_of(const Scene& scene, const Meter& m, size_t point, Sampler& sampler,
                       PathCounters& counters, MeterComponent component) {
    SampledWavelengths lambda = SampledWavelengths::sample_visible(sampler.get_1d());
    const Vec3 dir = m.directions[point];
    Point3 p = m.points[point];
    if (m.kind == MeterKind::Luminance) {
        const Vec3 d = meter_view_direction(m, dir, sampler.get_2d());
        PathLimits lim;
        lim.max_depth = m.max_depth < 0 ? -1 : m.max_depth;
        SampledSpectrum L =
            path_li(scene, Ray{p, d, kInfinity}, lambda, sampler, counters, lim, m.medium);
        return meter_weigh(m, L, lambda);
    }
    if (m.cell_average) {
        Point2 u = sampler.get_2d();
        p = p + m.cell_u * (u.x - Float(0.5)) + m.cell_v * (u.y - Float(0.5));
    }
    // An ideal white Lambertian receiver facing `dir`: E = pi L_o.
    const SurfaceHit v = meter_receiver(p, dir);
    Bsdf receiver(Frame::from_z(dir), dir, LambertLobe{SampledSpectrum(1)});
    SampledSpectrum L =
        path_lo(scene, v, receiver, lambda, sampler, counters, limits_of(m, component), m.medium);
    return kPi * meter_weigh(m, L, lambda);
}

/// A value: point `point` of meter `meter`. Values are numbered meter by meter.
struct Value {
    int meter;
    size_t point;
};

/// The values of every meter but those `skip` marks.
std::vector<Value> values_of(const Scene& scene, const std::vector<uint8_t>& skip = {}) {
    std::vector<Value> values;
    for (size_t mi = 0; mi < scene.meters.size(); ++mi) {
        if (mi < skip.size() && skip[mi]) continue;
        for (size_t k = 0; k < scene.meters[mi].points.size(); ++k) values.push_back({int(mi), k});
    }
    return values;
}

struct ReplicaResult {
    bool done = false;  ///< false: abandoned (`stop`)
    double mean = 0;
    uint64_t paths = 0, rays = 0, nonfinite = 0;
};

/// Replica `replica` of value `vi` in the round keyed by `round_seed`: the mean of n samples.
/// `stop` (may be null) is polled every 256 samples; when it says so the replica is abandoned.
ReplicaResult replica_mean(const Scene& scene, const std::vector<Value>& values, size_t vi,
                           int replica, int n, uint64_t round_seed,
                           const std::function<bool()>* stop,
                           const RadiositySolution* radiosity = nullptr,
                           bool indirect_only = false) {
    const Value& val = values[vi];
    const Meter& m = scene.meters[size_t(val.meter)];
    PaddedSobolSampler sampler(n, round_seed);
    PathCounters counters;
    ReplicaResult r;
    double sum = 0;
    for (int i = 0; i < n; ++i) {
        if (stop && (i & 255) == 0 && (*stop)()) return r;
        sampler.start_pixel_sample(Vec2i(int(vi), replica), i);
        const MeterComponent component = indirect_only ? MeterComponent::Indirect : m.component;
        double v = radiosity ? radiosity_meter_sample(scene, *radiosity, m, val.point, sampler,
                                                      counters, component)
                             : meter_sample_of(scene, m, val.point, sampler, counters, component);
        if (!std::isfinite(v)) {
            ++r.nonfinite;
            v = 0;
        }
        sum += v;
    }
    r.done = true;
    r.mean = sum / n;
    r.paths = uint64_t(n);
    r.rays = counters.rays;
    return r;
}

}  // namespace

MeasureResult measure(const Scene& scene, const MeasureOptions& opt) {
    using Clock = std::chrono::steady_clock;
    const auto t0 = Clock::now();
    const double cpu0 = process_cpu_seconds();
    auto elapsed = [&] { return std::chrono::duration<double>(Clock::now() - t0).count(); };
    if (opt.replicas < 2) throw Error("measure: need at least 2 replicas");

    MeasureResult res;
    res.rel_error_target = opt.rel_error;
    if (opt.light_trace) res.method = "light";
    if (opt.radiosity) {
        const RadiosityStats& rs = opt.radiosity->stats();
        res.method = "radiosity";
        res.method_figures = {{"patches", double(rs.patches)},
                              {"unknowns", double(rs.unknowns)},
                              {"form_factor_pairs", double(rs.pairs)},
                              {"solves", double(rs.solves)},
                              {"iterations", double(rs.iterations)},
                              {"residual", rs.residual},
                              {"solve_seconds", rs.seconds},
                              {"mesh_seconds", rs.seconds_mesh},
                              {"direct_seconds", rs.seconds_direct},
                              {"exchange_seconds", rs.seconds_exchange},
                              {"sweep_seconds", rs.seconds_sweeps}};
    }
    // The grids measured by light tracing, if asked for (after the others).
    std::vector<int> traced;
    std::vector<uint8_t> skip(scene.meters.size(), 0);
    if (opt.light_trace) {
        if (opt.checkpoint || opt.resume)
            throw Error("measure --method light: checkpoints are not supported with light "
                        "tracing yet");
        if (opt.distribute && opt.distribute->workers() > 0)
            throw Error("measure --method light: light tracing does not run on several "
                        "processes yet");
        for (size_t mi = 0; mi < scene.meters.size(); ++mi)
            if (light_traceable(scene, scene.meters[mi])) {
                traced.push_back(int(mi));
                skip[mi] = 1;
            }
    }
    // Flatten (meter, point) into value indices.
    const std::vector<Value> values = values_of(scene, skip);
    for (size_t mi = 0; mi < scene.meters.size(); ++mi) {
        MeterReading r;
        r.meter = scene.meters[mi];
        res.readings.push_back(std::move(r));
    }
    const size_t nv = values.size();
    const int R = opt.replicas;

    MeasureState st;
    if (opt.resume) {
        st = *opt.resume;
        st.time_limited = false;  // a new run, with its own budget
        const bool fits = st.round >= 0 && st.next_n.size() == nv && st.values.size() == nv &&
                          st.stderrs.size() == nv && st.samples.size() == nv &&
                          st.converged.size() == nv &&
                          st.item_done.size() == st.replica_mean.size();
        if (!fits) throw Error(fmt::format("resume: a state of another measurement ({} values, "
                                           "this one has {})", st.next_n.size(), nv));
    } else {
        // Per value: the samples per replica of its next round (0 = finished).
        st.next_n.assign(nv, std::max(1, opt.first_samples));
        st.values.assign(nv, 0);
        st.stderrs.assign(nv, 0);
        st.samples.assign(nv, 0);
        st.converged.assign(nv, 0);
    }
    const MeasureState before = opt.resume ? *opt.resume : MeasureState{};
    auto state_so_far = [&] {
        MeasureState s = st;
        s.wall_seconds = before.wall_seconds + elapsed();
        s.cpu_seconds = before.cpu_seconds + process_cpu_seconds() - cpu0;
        return s;
    };
    double last_checkpoint = 0;
    auto checkpoint = [&](bool now) {
        if (!opt.checkpoint || (!now && elapsed() - last_checkpoint < opt.checkpoint_every))
            return;
        opt.checkpoint(state_so_far());
        last_checkpoint = elapsed();
    };

    int threads = opt.threads > 0 ? opt.threads : int(std::thread::hardware_concurrency());
    tbb::global_control gc(tbb::global_control::max_allowed_parallelism, size_t(threads));
    tbb::task_arena arena(threads);
    WorkCoordinator* const coord =
        opt.distribute && opt.distribute->workers() > 0 ? opt.distribute : nullptr;
    // Items computed at once: this process's threads, and as many per other process (an
    // estimate, for sizing the batches between checkpoints).
    const int slots = threads * (coord ? coord->workers() + 1 : 1);

    // Direct light without Monte Carlo where it can be (direct_light.h): a deterministic
    // value is final at once; a split value's samples count only its indirect light, and its
    // direct part is added at the end. Recomputed on resume (it is a pure function of the
    // scene), so a checkpoint need not hold it.
    const std::vector<DirectPlan> plans = direct_plans(scene, opt);
    std::vector<double> direct_value(nv, 0), direct_error(nv, 0);
    std::vector<uint8_t> direct_exact(nv, 0), direct_converged(nv, 1);
    std::vector<int64_t> direct_nodes(nv, 0);
    std::vector<uint8_t> split(nv, 0);
    uint64_t direct_rays = 0;
    {
        std::vector<std::unique_ptr<DirectLightQuadrature>> quad(scene.meters.size());
        for (size_t mi = 0; mi < scene.meters.size(); ++mi)
            if (plans[mi] != DirectPlan::MonteCarlo)
                quad[mi] = std::make_unique<DirectLightQuadrature>(scene, scene.meters[mi]);
        std::vector<uint64_t> rays(nv, 0);
        // First every value roughly (each area light's first cell), for each meter's
        // largest value: a value below
        // kDarkFraction of it (a grid's dark corner, the far field of a narrow beam) is
        // computed to an absolute error of the target times kDarkFraction times the largest,
        // not to a relative one (which could cost more nodes than the rest together).
        std::vector<DirectEstimate> rough(nv);
        std::vector<double> largest(scene.meters.size(), 0);
        arena.execute([&] {
            tbb::parallel_for(size_t(0), nv, [&](size_t vi) {
                const DirectLightQuadrature* q = quad[size_t(values[vi].meter)].get();
                if (q) rough[vi] = q->irradiance(values[vi].point, 0.1, 0, 1);
            });
        });
        for (size_t vi = 0; vi < nv; ++vi) {
            double& l = largest[size_t(values[vi].meter)];
            l = std::max(l, std::abs(rough[vi].value));
        }
        arena.execute([&] {
            tbb::parallel_for(size_t(0), nv, [&](size_t vi) {
                const DirectLightQuadrature* q = quad[size_t(values[vi].meter)].get();
                if (!q) return;
                // Half the target: the estimate bounds the 2x2 rule's error, so the 3x3
                // value kept is usually far closer. A rough value that meets it is final.
                const double rel = opt.rel_error / 2;
                const double abs_tol = rel * kDarkFraction * largest[size_t(values[vi].meter)];
                DirectEstimate e = rough[vi];
                if (!(e.error <= std::max(rel * std::abs(e.value), abs_tol)))
                    e = q->irradiance(values[vi].point, rel, abs_tol);
                else
                    e.converged = true;
                direct_value[vi] = e.value;
                direct_error[vi] = e.error;
                direct_exact[vi] = e.exact;
                direct_converged[vi] = e.converged;
                rays[vi] = e.rays;
                direct_nodes[vi] = int64_t(e.nodes);
            });
        });
        for (size_t vi = 0; vi < nv; ++vi) {
            direct_rays += rays[vi];
            const DirectPlan plan = plans[size_t(values[vi].meter)];
            split[vi] = plan == DirectPlan::Split;
            if (plan != DirectPlan::Deterministic || opt.resume) continue;
            st.next_n[vi] = 0;
            st.values[vi] = direct_value[vi];
            st.stderrs[vi] = direct_error[vi];
            st.converged[vi] = direct_converged[vi];
            st.samples[vi] = direct_nodes[vi];
        }
    }

    const int first_round = st.round;  // this run's first round always completes
    double seconds_per_sample = 0;      // wall, of the batches so far
    for (;; ++st.round) {
        const int round = st.round;
        std::vector<size_t> pending;
        for (size_t i = 0; i < nv; ++i)
            if (st.next_n[i] > 0) pending.push_back(i);
        if (pending.empty()) break;
        const size_t items = pending.size() * size_t(R);
        if (st.item_done.empty()) {
            st.item_done.assign(items, 0);
            st.replica_mean.assign(items, 0);
        } else if (st.item_done.size() != items) {
            throw Error(fmt::format("resume: round {} has {} items, the state {}", round, items,
                                    st.item_done.size()));
        }
        const uint64_t round_seed = hash(opt.seed, uint64_t(round), uint64_t(0x6d65746572));
        // The time budget is a bound: a round after the pilot (which every value needs for a
        // standard error) is abandoned as soon as the budget is spent, checked every 256
        // samples, and its values keep the previous round's estimates. (Rounds grow up to
        // 64-fold, so waiting for the round to end could overrun the budget many times.)
        const bool may_abandon = (opt.time_budget > 0 || opt.stop) && round > first_round;
        auto must_stop = [&] {
            return (opt.time_budget > 0 && elapsed() > opt.time_budget) ||
                   (opt.stop && opt.stop->load(std::memory_order_relaxed));
        };
        std::atomic<bool> abandoned{false};
        // The items left, in batches: one without checkpoints, else batches sized from the
        // time the previous ones took to end about at the next checkpoint. Each item is a
        // pure function of (value, replica, round, seed), so batches change nothing.
        std::vector<size_t> todo;
        for (size_t item = 0; item < items; ++item)
            if (!st.item_done[item]) todo.push_back(item);
        size_t batch = opt.checkpoint ? size_t(2 * slots) : todo.size();
        const std::function<bool()> stop_check = [&] {
            return abandoned.load(std::memory_order_relaxed) || must_stop();
        };
        for (size_t b0 = 0; b0 < todo.size() && !abandoned;) {
            if (opt.checkpoint && seconds_per_sample > 0) {
                const double per_item = seconds_per_sample * double(st.next_n[pending[todo[b0] / R]]);
                batch = size_t(std::clamp(std::max(opt.checkpoint_every, 0.5) * slots / per_item,
                                          1.0, double(todo.size())));
            }
            const size_t b1 = std::min(todo.size(), b0 + batch);
            const double batch_t0 = elapsed();
            std::atomic<uint64_t> paths{0}, rays{0}, nonfinite{0};
            auto take = [&](size_t item, const ReplicaResult& r) {
                if (!r.done) {
                    abandoned = true;
                    return;
                }
                st.replica_mean[item] = r.mean;
                st.item_done[item] = 1;
                paths += r.paths;
                rays += r.rays;
                nonfinite += r.nonfinite;
            };
            auto compute = [&](size_t item) {
                take(item, replica_mean(scene, values, pending[item / R], int(item % R),
                                        int(st.next_n[pending[item / R]]), round_seed,
                                        may_abandon ? &stop_check : nullptr, opt.radiosity,
                                        split[pending[item / R]] != 0));
            };
            if (!coord) {
                arena.execute([&] {
                    tbb::parallel_for(b0, b1, [&](size_t t) { compute(todo[t]); });
                });
            } else {
                // The batch's items shared with the other processes: each is a pure function of
                // (value, replica, samples, round seed), which its input carries, with the time
                // left of the budget (the worker's clock then bounds it).
                WorkCoordinator::Phase ph;
                ph.kind = kMeasureItems;
                ByteWriter hw(ph.header);
                hw.put(round_seed);
                hw.put(uint8_t(opt.radiosity ? 1 : 0));  // the method: 0 path, 1 radiosity
                ph.items = b1 - b0;
                ph.input = [&](size_t j, ByteWriter& bw) {
                    const size_t item = todo[b0 + j];
                    const size_t vi = pending[item / R];
                    bw.put(uint64_t(vi));
                    bw.put(int32_t(item % R));
                    bw.put(int64_t(st.next_n[vi]));
                    double left = kInfinity;
                    if (may_abandon && opt.time_budget > 0) left = opt.time_budget - elapsed();
                    bw.put(left);
                    bw.put(uint8_t(split[vi]));
                };
                ph.output = [&](size_t j, ByteReader& br) {
                    ReplicaResult r;
                    r.done = br.get<uint8_t>() != 0;
                    r.mean = br.get<double>();
                    r.paths = br.get<uint64_t>();
                    r.rays = br.get<uint64_t>();
                    r.nonfinite = br.get<uint64_t>();
                    take(todo[b0 + j], r);
                };
                ph.local = [&](const std::function<std::optional<size_t>()>& claim,
                               const std::function<void(size_t)>&) {
                    run_local_share(
                        arena, threads, claim,
                        [&] { return abandoned.load(std::memory_order_relaxed); },
                        [&](size_t j) { compute(todo[b0 + j]); });
                };
                ph.abandon = [&] {
                    return abandoned.load() || (may_abandon && must_stop());
                };
                if (!coord->run(ph)) abandoned = true;
            }
            st.paths += paths;
            st.rays += rays;
            st.nonfinite += nonfinite;
            if (paths > 0) seconds_per_sample = (elapsed() - batch_t0) * slots / double(paths);
            b0 = b1;
            if (!abandoned && b0 < todo.size()) checkpoint(false);
        }
        if (abandoned) {
            st.time_limited = true;
            checkpoint(true);
            break;
        }
        const bool out_of_time = must_stop();
        for (size_t j = 0; j < pending.size(); ++j) {
            const size_t vi = pending[j];
            const double* rm = &st.replica_mean[j * R];
            double mean = 0;
            for (int r = 0; r < R; ++r) mean += rm[r];
            mean /= R;
            double var = 0;
            for (int r = 0; r < R; ++r) var += sqr(rm[r] - mean);
            var /= R - 1;
            const double se = std::sqrt(var / R);
            const int64_t n = st.next_n[vi];
            st.values[vi] = mean;
            st.stderrs[vi] = se;
            st.samples[vi] = n * R;
            // A split value's target is relative to the whole reading, and its direct
            // part's quadrature error counts against it.
            const double target = opt.rel_error * std::abs(mean + (split[vi] ? direct_value[vi] : 0));
            const bool ok = std::hypot(se, split[vi] ? direct_error[vi] : 0) <= target;
            st.converged[vi] = ok;
            // The first round is a pilot: it only sizes the next one, so the reported
            // estimate never comes from the round whose variance decided the sample count.
            if ((ok && round > 0) || se == 0) {
                st.converged[vi] = 1;
                st.next_n[vi] = 0;
                continue;
            }
            // Size the next round for the target with a 20% margin, assuming the error falls
            // as 1/sqrt(n) (conservative for RQMC): at least as many and at most 64 times as
            // many as this round's, rounded up to a multiple of 8 (a value the pilot already
            // measured to the target gets a second round of the pilot's size, since the
            // reported estimate never comes from the round that sized it). Rounding up to a
            // power of two (at least double), as before, cost the office's radiosity gather
            // 1.5 times the samples (1.24 M against 0.83 M) for no measurable gain from the
            // Sobol points' power-of-two balance (its grid took as many samples for its
            // target with 8 replicas of 4 times the samples as with 32).
            const double grow = target > 0 ? std::clamp(sqr(se / (0.8 * target)), 1.0, 64.0) : 64;
            const int64_t want = (int64_t(std::ceil(double(n) * grow)) + 7) / 8 * 8;
            st.next_n[vi] = want > opt.max_samples ? 0 : want;
        }
        st.item_done.clear();
        st.replica_mean.clear();
        // Stopped (budget or signal): the values short of their target keep their next round
        // in the state, so that a checkpoint resumes it.
        const bool finished =
            std::none_of(st.next_n.begin(), st.next_n.end(), [](int64_t n) { return n > 0; });
        if (out_of_time && !finished) st.time_limited = true;
        ++st.round;  // the state saved is between this round and the next
        checkpoint(finished || out_of_time);
        if (out_of_time) break;
        --st.round;
    }

    for (size_t vi = 0; vi < nv; ++vi) {
        MeterReading& rd = res.readings[values[vi].meter];
        const DirectPlan plan = plans[size_t(values[vi].meter)];
        rd.estimator = plan == DirectPlan::Deterministic ? "deterministic"
                       : plan == DirectPlan::Split       ? "deterministic + monte carlo indirect"
                                                         : "monte carlo";
        if (split[vi]) {
            rd.values.push_back(st.values[vi] + direct_value[vi]);
            rd.stderrs.push_back(std::hypot(st.stderrs[vi], direct_error[vi]));
            rd.converged.push_back(st.converged[vi] && direct_converged[vi]);
        } else {
            rd.values.push_back(st.values[vi]);
            rd.stderrs.push_back(st.stderrs[vi]);
            rd.converged.push_back(st.converged[vi]);
        }
        rd.samples.push_back(st.samples[vi]);
        rd.exact.push_back(plan == DirectPlan::Deterministic && direct_exact[vi]);
    }
    res.time_limited = st.time_limited;
    LightMeterStats light_stats;
    if (!traced.empty()) {
        LightMeterOptions lo;
        lo.rel_error = opt.rel_error;
        lo.seed = opt.seed;
        lo.threads = opt.threads;
        lo.stop = opt.stop;
        if (opt.time_budget > 0) lo.time_budget = std::max(1e-3, opt.time_budget - elapsed());
        light_trace_meters(scene, traced, lo, res.readings, light_stats);
        res.time_limited = res.time_limited || light_stats.time_limited;
        for (int mi : traced)
            for (uint8_t c : res.readings[size_t(mi)].converged)
                res.all_converged = res.all_converged && c;
    }
    for (MeterReading& r : res.readings) {
        if (r.estimator == "light tracing") continue;
        for (uint8_t c : r.converged) res.all_converged = res.all_converged && c;
        if (r.meter.kind != MeterKind::Grid || r.values.empty()) continue;
        double sum = 0, var = 0;
        r.min = r.max = r.values[0];
        for (size_t k = 0; k < r.values.size(); ++k) {
            sum += r.values[k];
            var += sqr(r.stderrs[k]);
            r.min = std::min(r.min, r.values[k]);
            r.max = std::max(r.max, r.values[k]);
        }
        double cnt = double(r.values.size());
        r.avg = sum / cnt;
        r.avg_stderr = std::sqrt(var) / cnt;
        r.uniformity = r.avg > 0 ? r.min / r.avg : 0;
    }
    apply_glare(scene, res);  // glare meters: E_ind -> UGR
    res.interrupted = opt.stop && opt.stop->load();
    const MeasureState total = state_so_far();
    res.paths = total.paths + light_stats.paths;
    res.rays = total.rays + direct_rays + light_stats.rays;
    res.nonfinite = total.nonfinite + light_stats.nonfinite;
    res.wall_seconds = total.wall_seconds;
    res.cpu_seconds = total.cpu_seconds;
    return res;
}

JobHandler measure_job_handler(const Scene& scene, int threads,
                               const RadiositySolution* radiosity) {
    struct Worker {
        std::vector<Value> values;
        tbb::task_arena arena;
        Worker(const Scene& s, int n)
            : values(values_of(s)), arena(n > 0 ? n : int(std::thread::hardware_concurrency())) {}
    };
    auto wk = std::make_shared<Worker>(scene, threads);
    return [&scene, wk, radiosity](ByteReader& header, size_t count, ByteReader& inputs,
                                   ByteWriter& outputs) {
        const uint64_t round_seed = header.get<uint64_t>();
        const uint8_t method = header.get<uint8_t>();
        if (method > 1) throw Error("distributed: a meter round of an unknown method");
        if (method == 1 && !radiosity)
            throw Error("distributed: a radiosity round, and no radiosity solution here");
        struct Item {
            uint64_t id, vi;
            int32_t replica;
            int64_t n;
            double seconds_left;
            uint8_t indirect_only;
        };
        std::vector<Item> items(count);
        for (Item& it : items) {
            it.id = inputs.get<uint64_t>();
            it.vi = inputs.get<uint64_t>();
            it.replica = inputs.get<int32_t>();
            it.n = inputs.get<int64_t>();
            it.seconds_left = inputs.get<double>();
            it.indirect_only = inputs.get<uint8_t>();
            if (it.vi >= wk->values.size() || it.n <= 0 || it.n > (int64_t(1) << 40))
                throw Error("distributed: a meter item of another scene");
        }
        const auto t0 = std::chrono::steady_clock::now();
        std::vector<ReplicaResult> results(count);
        wk->arena.execute([&] {
            tbb::parallel_for(size_t(0), count, [&](size_t j) {
                const Item& it = items[j];
                const std::function<bool()> late = [&] {
                    return std::chrono::duration<double>(std::chrono::steady_clock::now() - t0)
                               .count() > it.seconds_left;
                };
                results[j] = replica_mean(scene, wk->values, size_t(it.vi), it.replica, int(it.n),
                                          round_seed,
                                          std::isfinite(it.seconds_left) ? &late : nullptr,
                                          method == 1 ? radiosity : nullptr,
                                          it.indirect_only != 0);
            });
        });
        for (size_t j = 0; j < count; ++j) {
            outputs.put(items[j].id);
            outputs.put(uint8_t(results[j].done));
            outputs.put(results[j].mean);
            outputs.put(results[j].paths);
            outputs.put(results[j].rays);
            outputs.put(results[j].nonfinite);
        }
    };
}

namespace {

const char* to_string(MeterWeighting w) {
    switch (w) {
        case MeterWeighting::Photopic: return "photopic";
        case MeterWeighting::Scotopic: return "scotopic";
        case MeterWeighting::Radiometric: return "radiometric";
    }
    return "";
}

const char* to_string(MeterComponent c) {
    switch (c) {
        case MeterComponent::All: return "all";
        case MeterComponent::Direct: return "direct";
        case MeterComponent::Indirect: return "indirect";
    }
    return "";
}

}  // namespace

std::string meters_json(const MeasureResult& res) {
    nlohmann::ordered_json root;
    root["rel_error_target"] = res.rel_error_target;
    root["converged"] = res.all_converged;
    root["time_limited"] = res.time_limited;
    if (res.interrupted) root["interrupted"] = true;
    root["wall_seconds"] = res.wall_seconds;
    root["cpu_seconds"] = res.cpu_seconds;
    root["paths"] = res.paths;
    root["nonfinite"] = res.nonfinite;
    root["method"] = res.method;
    if (!res.method_figures.empty()) {
        nlohmann::ordered_json fig;
        for (const auto& [k, v] : res.method_figures) fig[k] = v;
        root[res.method] = std::move(fig);
    }
    nlohmann::ordered_json meters = nlohmann::ordered_json::array();
    for (const MeterReading& r : res.readings) {
        const Meter& m = r.meter;
        nlohmann::ordered_json j;
        j["name"] = m.name;
        j["type"] = m.type;
        j["unit"] = m.unit();
        j["vision"] = to_string(m.weighting);
        if (m.kind != MeterKind::Luminance) j["component"] = to_string(m.component);
        j["estimator"] = r.estimator;
        j["values"] = r.values;
        j["stderr"] = r.stderrs;
        j["samples"] = r.samples;
        std::vector<bool> conv(r.converged.begin(), r.converged.end());
        j["converged"] = conv;
        if (r.estimator != "monte carlo")
            j["exact"] = std::vector<bool>(r.exact.begin(), r.exact.end());
        nlohmann::ordered_json pts = nlohmann::ordered_json::array();
        for (Point3 p : m.points) pts.push_back({p.x, p.y, p.z});
        j["points"] = pts;
        if (m.kind == MeterKind::Grid) {
            j["resolution"] = {m.nu, m.nv};
            j["cellaverage"] = m.cell_average;
            j["avg"] = r.avg;
            j["avg_stderr"] = r.avg_stderr;
            j["min"] = r.min;
            j["max"] = r.max;
            j["uniformity"] = r.uniformity;
        }
        if (m.glare) {
            j["up"] = {m.glare_up.x, m.glare_up.y, m.glare_up.z};
            nlohmann::ordered_json gs = nlohmann::ordered_json::array();
            for (const GlareReading& g : r.glare) {
                nlohmann::ordered_json gj;
                gj["defined"] = g.defined;
                gj["in_cie117_range"] = g.in_range;
                gj["indirect_illuminance"] = g.indirect_illuminance;
                gj["indirect_stderr"] = g.indirect_stderr;
                gj["background_luminance"] = g.background_luminance;
                if (!g.note.empty()) gj["note"] = g.note;
                nlohmann::ordered_json srcs = nlohmann::ordered_json::array();
                for (const GlareSource& s : g.sources) {
                    nlohmann::ordered_json sj;
                    sj["file"] = s.file;
                    sj["position"] = {s.position.x, s.position.y, s.position.z};
                    sj["counted"] = s.counted;
                    sj["distance"] = s.distance;
                    sj["intensity"] = s.intensity;
                    sj["projected_area"] = s.projected_area;
                    sj["solid_angle"] = s.solid_angle;
                    sj["luminance"] = s.luminance;
                    sj["position_index"] = s.position_index;
                    sj["term"] = s.term;
                    if (!s.note.empty()) sj["note"] = s.note;
                    srcs.push_back(std::move(sj));
                }
                gj["luminaires"] = std::move(srcs);
                gs.push_back(std::move(gj));
            }
            j["glare"] = std::move(gs);
        }
        meters.push_back(std::move(j));
    }
    root["meters"] = std::move(meters);
    return root.dump(2) + "\n";
}

std::string meters_csv(const MeasureResult& res) {
    std::string out = "meter,type,unit,index,x,y,z,value,stderr,samples,converged\n";
    for (const MeterReading& r : res.readings) {
        const Meter& m = r.meter;
        for (size_t k = 0; k < r.values.size(); ++k) {
            Point3 p = m.points[k];
            out += fmt::format("{},{},{},{},{:.9g},{:.9g},{:.9g},{:.9g},{:.6g},{},{}\n", m.name, m.type,
                               m.unit(), k, p.x, p.y, p.z, r.values[k], r.stderrs[k], r.samples[k],
                               int(r.converged[k]));
        }
    }
    return out;
}

}  // namespace sr
