#include "steradian/integrators/light_meters.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <optional>
#include <thread>

#include <tbb/parallel_for.h>
#include <tbb/task_arena.h>

#include "steradian/bsdf/bsdf.h"
#include "steradian/lights/light.h"
#include "steradian/material/material.h"
#include "steradian/sampling/hash.h"
#include "steradian/sampling/rng.h"
#include "steradian/scene/scene.h"

namespace sr {

bool light_traceable(const Scene& scene, const Meter& m) {
    return m.kind == MeterKind::Grid && m.cell_average && !m.glare && m.medium < 0 &&
           scene.media.empty() && m.nu > 0 && m.nv > 0 && !m.directions.empty();
}

namespace {

/// A grid as a plane: the corner of its first cell, the normal it faces, and what turns a
/// point of the plane into cell coordinates (a along cell_u, b along cell_v).
struct GridPlane {
    int reading = 0;  ///< index into the readings
    Point3 origin;
    Vec3 n, u, v;
    double g00 = 0, g01 = 0, g11 = 0, det = 0;  ///< the Gram matrix of u, v
    int nu = 0, nv = 0;
    double cell_area = 0;
    MeterComponent component = MeterComponent::All;
    int max_depth = -1;
    size_t first = 0;  ///< its first cell in the accumulators
    const Meter* meter = nullptr;
};

/// The particles are made in chunks of this many; each chunk's sums are kept apart and added
/// in chunk order, so the sums do not depend on the threads.
constexpr uint64_t kChunk = 2048;

/// Adds to `sums` what the segment from o along d (t in (0, t_end]) carries across the grids:
/// beta's weighted value for each cell it crosses from the front.
void add_crossings(const std::vector<GridPlane>& grids, const Ray& ray, Float t_end, int depth,
           const SampledSpectrum& beta, const SampledWavelengths& lambda, double* sums) {
    for (const GridPlane& g : grids) {
        if (g.component == MeterComponent::Direct && depth > 0) continue;
        if (g.component == MeterComponent::Indirect && depth == 0) continue;
        if (g.max_depth >= 0 && depth > g.max_depth) continue;
        const double dn = double(dot(g.n, ray.d));
        if (!(dn < 0)) continue;  // arrives at the front face only when moving against n
        const double t = double(dot(g.n, g.origin - ray.o)) / dn;
        // The end point counts (light that reaches a grid lying on a surface).
        if (!(t > 0) || !(t <= double(t_end) * (1 + 1e-5))) continue;
        const Vec3 x = (ray.o + ray.d * Float(t)) - g.origin;
        const double xu = double(dot(x, g.u)), xv = double(dot(x, g.v));
        const double a = (g.g11 * xu - g.g01 * xv) / g.det;
        const double b = (g.g00 * xv - g.g01 * xu) / g.det;
        if (!(a >= 0 && a < g.nu && b >= 0 && b < g.nv)) continue;
        const int i = std::min(int(a), g.nu - 1), j = std::min(int(b), g.nv - 1);
        sums[g.first + size_t(j) * size_t(g.nu) + size_t(i)] += meter_weigh(*g.meter, beta, lambda);
    }
}

/// One particle: its crossings added to `sums`; returns the rays traced, counts a
/// non-finite weight in `nonfinite` (and drops the particle).
uint64_t trace_particle(const Scene& scene, const std::vector<GridPlane>& grids, int max_depth,
                        Pcg32& rng, double* sums, uint64_t& nonfinite) {
    SampledWavelengths lambda = SampledWavelengths::sample_visible(rng.next_float());
    const Float ul = rng.next_float();
    const Point2 u_pos(rng.next_float(), rng.next_float());
    const Point2 u_dir(rng.next_float(), rng.next_float());
    Float pmf = 0;
    const int li = scene.light_sampler.sample(ul, pmf);
    if (li < 0 || !(pmf > 0)) return 0;
    const Light& light = scene.lights[size_t(li)];
    const auto les = sample_le(light, u_pos, u_dir, lambda);
    if (!les) return 0;
    // As bdpt's light subpath: the emitted radiance, times the cosine at an area light, over
    // the densities of the light, its point and its direction.
    const bool on_surface = les->n.x != 0 || les->n.y != 0 || les->n.z != 0;
    const Float cos = on_surface ? absdot(les->n, les->ray.d) : 1;
    SampledSpectrum beta = les->L * (cos / (pmf * les->pdf_pos * les->pdf_dir));
    if (beta.has_nonfinite()) {
        ++nonfinite;
        return 0;
    }
    if (beta.is_zero()) return 0;
    const Float beta0 = beta.max_value();
    const MaterialContext mctx = scene.material_context();
    Ray ray = les->ray;
    SurfaceHit hit;
    uint64_t rays = 0;
    int depth = 0, crossings = 0;
    while (true) {
        ++rays;
        const bool found = scene.intersect(ray, hit);
        add_crossings(grids, ray, found ? hit.t : kInfinity, depth, beta, lambda, sums);
        if (!found) return rays;
        std::optional<Bsdf> bsdf =
            hit.material >= 0 ? make_bsdf(scene.materials[size_t(hit.material)], mctx, hit, lambda)
                              : std::nullopt;
        if (!bsdf) {  // an interface: the particle passes on
            if (++crossings > 256) return rays;
            ray = spawn_ray(hit, ray.d);
            ray.t_max = kInfinity;
            continue;
        }
        if (max_depth >= 0 && depth >= max_depth) return rays;
        const Float uc = rng.next_float();
        const Point2 u(rng.next_float(), rng.next_float());
        const auto bs = bsdf->sample(hit.wo, uc, u, TransportMode::Importance);
        if (!bs || !(bs->pdf_sa > 0)) return rays;
        beta *= bs->f * (absdot(bs->wi, hit.ns) / bs->pdf_sa);
        ++depth;
        // Russian roulette after three bounces, by the weight left of the first one's.
        if (depth >= 3) {
            const Float q = std::min(Float(0.95), beta.max_value() / beta0);
            if (!(rng.next_float() < q)) return rays;
            beta = beta / q;
        }
        if (beta.is_zero()) return rays;
        if (beta.has_nonfinite()) {
            ++nonfinite;
            return rays;
        }
        ray = spawn_ray(hit, bs->wi);
    }
}

}  // namespace

void light_trace_meters(const Scene& scene, const std::vector<int>& which,
                        const LightMeterOptions& opt, std::vector<MeterReading>& readings,
                        LightMeterStats& stats) {
    using Clock = std::chrono::steady_clock;
    const auto t0 = Clock::now();
    if (which.empty()) return;
    std::vector<GridPlane> grids;
    size_t cells = 0;
    int max_depth = 0;
    for (int mi : which) {
        const Meter& m = scene.meters[size_t(mi)];
        GridPlane g;
        g.reading = mi;
        g.meter = &m;
        g.n = normalize(m.directions[0]);
        g.u = m.cell_u;
        g.v = m.cell_v;
        g.origin = m.points[0] - m.cell_u * Float(0.5) - m.cell_v * Float(0.5);
        g.g00 = double(dot(g.u, g.u));
        g.g01 = double(dot(g.u, g.v));
        g.g11 = double(dot(g.v, g.v));
        g.det = g.g00 * g.g11 - g.g01 * g.g01;
        g.nu = m.nu;
        g.nv = m.nv;
        g.cell_area = double(length(cross(g.u, g.v)));
        g.component = m.component;
        g.max_depth = m.max_depth;
        g.first = cells;
        cells += size_t(m.nu) * size_t(m.nv);
        max_depth = m.max_depth < 0 || max_depth < 0 ? -1 : std::max(max_depth, m.max_depth);
        grids.push_back(g);
    }

    const int R = std::max(2, opt.replicas);
    const int threads = opt.threads > 0 ? opt.threads : int(std::thread::hardware_concurrency());
    tbb::task_arena arena(threads);
    // Per replica, the sums over its particles so far (cell by cell).
    std::vector<std::vector<double>> sum(size_t(R), std::vector<double>(cells, 0.0));
    // The round's sums, added to `sum` once the round is complete (an abandoned round adds
    // nothing).
    std::vector<std::vector<double>> round_sum(size_t(R), std::vector<double>(cells, 0.0));
    uint64_t n = 0;  // particles per replica so far
    uint64_t next = std::max<uint64_t>(kChunk, opt.first_paths / kChunk * kChunk);
    std::vector<double> mean(cells, 0), se(cells, 0);
    std::vector<uint8_t> conv(cells, 0);
    double round_seconds = 0;  // of the last round, which had last_round particles a replica
    uint64_t last_round = 1;
    while (true) {
        // A round: particles [n, next) of every replica, in chunks.
        const uint64_t chunks_per_replica = (next - n) / kChunk;
        const size_t chunks = size_t(chunks_per_replica) * size_t(R);
        if (opt.time_budget > 0 && n > 0) {
            const double spent = std::chrono::duration<double>(Clock::now() - t0).count();
            if (spent + round_seconds * double(next - n) / double(last_round) >
                opt.time_budget) {
                stats.time_limited = true;
                break;
            }
        }
        const auto round_start = Clock::now();
        // The round's chunks in blocks: a block's chunks in parallel, each with sums of its
        // own, then added in chunk order (memory: a block's sums, not the round's).
        constexpr size_t kBlock = 64;
        std::vector<std::vector<double>> part(std::min(kBlock, chunks));
        std::vector<uint64_t> chunk_rays(part.size()), chunk_nonfinite(part.size());
        std::atomic<bool> abandoned{false};
        for (size_t b0 = 0; b0 < chunks && !abandoned.load(); b0 += kBlock) {
            const size_t nb = std::min(kBlock, chunks - b0);
            arena.execute([&] {
                tbb::parallel_for(size_t(0), nb, [&](size_t i) {
                    if (abandoned.load()) return;
                    if (opt.stop && opt.stop->load()) {
                        abandoned = true;
                        return;
                    }
                    const size_t c = b0 + i;
                    const int r = int(c / size_t(chunks_per_replica));
                    const uint64_t first = n + uint64_t(c % size_t(chunks_per_replica)) * kChunk;
                    std::vector<double>& ps = part[i];
                    ps.assign(cells, 0.0);
                    chunk_rays[i] = chunk_nonfinite[i] = 0;
                    for (uint64_t k = first; k < first + kChunk; ++k) {
                        Pcg32 rng(hash(opt.seed, uint64_t(r), k));
                        chunk_rays[i] += trace_particle(scene, grids, max_depth, rng, ps.data(),
                                                        chunk_nonfinite[i]);
                    }
                });
            });
            if (abandoned.load()) break;
            for (size_t i = 0; i < nb; ++i) {
                const size_t r = (b0 + i) / size_t(chunks_per_replica);
                for (size_t k = 0; k < cells; ++k) round_sum[r][k] += part[i][k];
                stats.rays += chunk_rays[i];
                stats.nonfinite += chunk_nonfinite[i];
            }
        }
        if (abandoned.load()) {
            stats.time_limited = true;
            break;
        }
        for (int r = 0; r < R; ++r)
            for (size_t k = 0; k < cells; ++k) {
                sum[size_t(r)][k] += round_sum[size_t(r)][k];
                round_sum[size_t(r)][k] = 0;
            }
        stats.paths += uint64_t(chunks) * kChunk;
        round_seconds = std::chrono::duration<double>(Clock::now() - round_start).count();
        last_round = next - n;
        n = next;
        // The cells' means and standard errors over the replicas.
        bool all = true;
        for (const GridPlane& g : grids) {
            const size_t nc = size_t(g.nu) * size_t(g.nv);
            double grid_mean = 0;
            for (size_t k = g.first; k < g.first + nc; ++k) {
                double m = 0, m2 = 0;
                for (int r = 0; r < R; ++r) {
                    const double x = sum[size_t(r)][k] / (double(n) * g.cell_area);
                    m += x;
                    m2 += x * x;
                }
                m /= R;
                mean[k] = m;
                se[k] = std::sqrt(std::max(0.0, (m2 / R - m * m) * R / (R - 1)) / R);
                grid_mean += m / double(nc);
            }
            for (size_t k = g.first; k < g.first + nc; ++k) {
                conv[k] = se[k] <= opt.rel_error * std::max(std::abs(mean[k]), grid_mean) &&
                          (mean[k] != 0 || grid_mean > 0);
                all = all && conv[k];
            }
        }
        if (all || next >= opt.max_paths) break;
        next = std::min(opt.max_paths, 2 * next);
    }

    for (const GridPlane& g : grids) {
        MeterReading& rd = readings[size_t(g.reading)];
        const size_t nc = size_t(g.nu) * size_t(g.nv);
        rd.values.assign(mean.begin() + long(g.first), mean.begin() + long(g.first + nc));
        rd.stderrs.assign(se.begin() + long(g.first), se.begin() + long(g.first + nc));
        rd.samples.assign(nc, int64_t(n) * R);
        rd.converged.assign(conv.begin() + long(g.first), conv.begin() + long(g.first + nc));
        rd.exact.assign(nc, 0);
        rd.estimator = "light tracing";
        if (nc == 0 || n == 0) continue;
        // The grid's mean and its standard error from the replicas' grid means (the cells of
        // one replica share its particles, so their errors are correlated).
        double m = 0, m2 = 0;
        for (int r = 0; r < R; ++r) {
            double x = 0;
            for (size_t k = g.first; k < g.first + nc; ++k) x += sum[size_t(r)][k];
            x /= double(n) * g.cell_area * double(nc);
            m += x;
            m2 += x * x;
        }
        m /= R;
        rd.avg = m;
        rd.avg_stderr = std::sqrt(std::max(0.0, (m2 / R - m * m) * R / (R - 1)) / R);
        rd.min = *std::min_element(rd.values.begin(), rd.values.end());
        rd.max = *std::max_element(rd.values.begin(), rd.values.end());
        rd.uniformity = rd.avg > 0 ? rd.min / rd.avg : 0;
    }
}

}  // namespace sr
