#include "steradian/integrators/mlt/mlt.h"

#include <algorithm>
#include <array>
#include <atomic>
#include <chrono>
#include <condition_variable>
#include <memory>
#include <mutex>
#include <cmath>
#include <thread>
#include <vector>

#include <tbb/blocked_range.h>
#include <tbb/enumerable_thread_specific.h>
#include <tbb/global_control.h>
#include <tbb/parallel_for.h>
#include <tbb/task_arena.h>

#include "steradian/core/error.h"
#include "steradian/film/film.h"
#include "steradian/integrators/bdpt/bdpt.h"
#include "steradian/integrators/distributed.h"
#include "steradian/integrators/mlt/mlt_sampler.h"
#include "steradian/integrators/progress.h"
#include "steradian/sampling/distribution.h"
#include "steradian/sampling/hash.h"
#include "steradian/scene/scene.h"
#include "steradian/spectrum/spectrum.h"

namespace sr {

namespace {

/// pbrt-v4's stream indices of the MLT sampler.
constexpr int kCameraStream = 0, kLightStream = 1, kConnectionStream = 2, kStreams = 3;

/// A state of a chain as the film sees it: the strategy's contribution L at its wavelengths,
/// where it lands on the film, and its luminance c (the function the chains sample).
struct PathState {
    Float c = 0;
    Point2 p;
    SampledWavelengths lambda;
    SampledSpectrum L{0};
};

/// Per-thread scratch space and counts.
struct MltThread {
    BdptScratchPtr scratch = make_bdpt_scratch();
    PathCounters counters;
    uint64_t paths = 0, nonfinite = 0;
};

/// Counts of a piece of work (distributed: what a worker reports with each item).
struct ItemCounts {
    uint64_t paths = 0, rays = 0, nonfinite = 0;
};

/// CIE Y of L at the sampled wavelengths (pbrt-v4's SampledSpectrum::y): MLT's c.
double luminance(const SampledSpectrum& L, const SampledWavelengths& lambda) {
    const DenselySampledSpectrum& y = cie_y();
    double sum = 0;
    for (int i = 0; i < kSpectrumSamples; ++i)
        if (lambda.pdf[size_t(i)] != 0)
            sum += double(y(lambda[i])) * double(L[i]) / double(lambda.pdf[size_t(i)]);
    return sum / kSpectrumSamples / double(kCieYIntegral);
}

/// pbrt-v4's MLTIntegrator::L: the state of `sampler` as a path of `depth` scattering
/// vertices.
void evaluate(const Scene& scene, const Film& film, const BidirContext& ctx, MltSampler& sampler,
              int depth, MltThread& th, PathState& out) {
    MltStream cam(sampler, kCameraStream), light(sampler, kLightStream),
        conn(sampler, kConnectionStream);
    ++th.paths;
    out.c = 0;
    out.L = SampledSpectrum(0);
    // The strategy: depth + 2 of them (s = 0 .. depth + 1), one at depth 0 ((1, 1) is none).
    int s = 0, t = 2, n = 1;
    if (depth > 0) {
        n = depth + 2;
        s = std::min(int(cam.get_1d() * Float(n)), n - 1);
        t = n - s;
    }
    out.lambda = film.sample_wavelengths(cam.get_1d());
    // The film position, uniform over the film's sample bounds, and the lens.
    const Point2 u = cam.get_2d();
    out.p = Point2(ctx.bounds[0] + u.x * (ctx.bounds[2] - ctx.bounds[0]),
                   ctx.bounds[1] + u.y * (ctx.bounds[3] - ctx.bounds[1]));
    const Point2 u_lens = cam.get_2d();
    if (scene.light_sampler.empty()) return;
    const Ray ray = scene.camera->generate_ray(
        out.p, scene.camera->uses_lens_sample() ? u_lens : Point2(0.5f, 0.5f));
    const SampledSpectrum L = bdpt_strategy(ctx, *th.scratch, s, t, ray, out.lambda, cam, light,
                                            conn, th.counters, out.p) *
                              Float(n);
    const double c = luminance(L, out.lambda);
    if (L.has_nonfinite() || !std::isfinite(float(c))) {
        ++th.nonfinite;
        return;
    }
    out.L = L;
    out.c = std::max(Float(0), Float(c));
}

/// A chain: its sampler, its generator of acceptances, its depth and its state.
struct Chain {
    MltSampler sampler;
    Pcg32 rng;
    int depth = 0;
    PathState current, proposed;
};

/// How many of the mutations [a, b) go to chain i of n: those j with j mod n == i.
int64_t chain_share(int64_t i, int64_t n, int64_t a, int64_t b) {
    auto upto = [&](int64_t x) { return x > i ? (x - i - 1) / n + 1 : 0; };
    return upto(b) - upto(a);
}

struct Splat {
    Point2 p;
    std::array<double, 3> xyz;
};

/// What every process needs to evaluate states and run chains: the same on each (the
/// scene, the film's parameters, the seed), so that a state does not depend on the process
/// that computes it.
struct MltSetup {
    MltSetup(const Scene& s, const Film& f, uint64_t seed_)
        : scene(s), film(f), ctx(s), mp(s.integrator.mlt), max_depth(s.integrator.max_depth),
          seed(seed_) {
        const FilmParams& fp = f.params();
        // Primary sample space holds film positions uniform over the sample bounds; a light
        // subpath connected to the camera (t = 1) lands anywhere on them, and is one sample of
        // the full film's light tracing (importance is normalised to the full film), so it is
        // scaled by the full film's pixels over the bounds' area.
        area = double(ctx.bounds[2] - ctx.bounds[0]) * double(ctx.bounds[3] - ctx.bounds[1]);
        ctx.crop_factor = Float(double(fp.resolution.x) * double(fp.resolution.y) / area);
    }
    const Scene& scene;
    const Film& film;
    BidirContext ctx;
    const IntegratorSettings::Mlt& mp;
    int max_depth;
    uint64_t seed;
    double area = 0;

    /// Bootstrap sample i: the first state of the sampler of index i, at depth i mod
    /// (maxdepth + 1); its c.
    Float bootstrap(int64_t i, MltThread& th) const {
        MltSampler smp(mp.sigma, mp.large_step_probability, kStreams, uint64_t(i), seed);
        PathState st;
        evaluate(scene, film, ctx, smp, int(i % (max_depth + 1)), th, st);
        return st.c;
    }

    /// n mutations of `ch`, its splats appended to `out` in mutation order (`bad`: those
    /// with non-finite sensor values, dropped).
    void run_chain(Chain& ch, int64_t n, MltThread& th, std::vector<Splat>& out,
                   uint64_t& bad) const {
        auto eval = [&](PathState& st) {
            evaluate(scene, film, ctx, ch.sampler, ch.depth, th, st);
        };
        auto splat = [&](const PathState& st, Float w) {
            const std::array<double, 3> xyz = film.to_sensor(st.L * w, st.lambda);
            if (!std::isfinite(xyz[0]) || !std::isfinite(xyz[1]) || !std::isfinite(xyz[2])) {
                ++bad;
                return;
            }
            if (xyz[0] == 0 && xyz[1] == 0 && xyz[2] == 0) return;
            out.push_back({st.p, xyz});
        };
        for (int64_t j = 0; j < n; ++j)
            metropolis_step(ch.sampler, ch.rng, ch.current, ch.proposed, eval, splat);
    }
};

// ---- distributed (docs/distributed.md, "Metropolis light transport") ----------------------

/// The stages of a distributed render (the header's first byte).
enum : uint8_t { kStageBootstrap = 0, kStageRound = 1 };
/// Bootstrap samples per distributed item.
constexpr int64_t kBootBlock = 1024;

/// A chain's state (all of it but the proposal, which every step overwrites) in a message,
/// and back: the chain continues on the receiving process exactly as it would have here.
void put_chain(ByteWriter& bw, const Chain& ch) {
    static_assert(std::is_trivially_copyable_v<PathState> &&
                  std::is_trivially_copyable_v<Pcg32>);
    ch.sampler.save(bw);
    bw.put(ch.rng);
    bw.put(int32_t(ch.depth));
    bw.put(ch.current);
}

void get_chain(ByteReader& br, Chain& ch, int max_depth) {
    ch.sampler.load(br);
    ch.rng = br.get<Pcg32>();
    ch.depth = br.get<int32_t>();
    if (ch.depth < 0 || ch.depth > max_depth)
        throw Error("distributed: a Metropolis chain of another depth than the scene's");
    ch.current = br.get<PathState>();
}

/// A chain's splats in a message (32 bytes each), and back, exactly.
void put_splats(ByteWriter& bw, const std::vector<Splat>& v) {
    bw.put(uint64_t(v.size()));
    for (const Splat& sp : v) {
        bw.put(sp.p.x);
        bw.put(sp.p.y);
        bw.put_array(sp.xyz.data(), 3);
    }
}

void get_splats(ByteReader& br, std::vector<Splat>& v) {
    const uint64_t n = br.get<uint64_t>();
    if (n > br.left() / 32) throw Error("distributed: a truncated message");
    v.resize(size_t(n));
    for (Splat& sp : v) {
        sp.p.x = br.get<Float>();
        sp.p.y = br.get<Float>();
        br.get_array(sp.xyz.data(), 3);
    }
}

}  // namespace

RenderStats render_mlt(const Scene& scene, Film& film, const RenderOptions& opt) {
    using Clock = std::chrono::steady_clock;
    check_bidir_scene(scene, "mlt");
    if (opt.checkpoint || opt.resume)
        throw Error("Integrator \"mlt\": checkpoints are not supported yet");
    if (film.has_aux())
        throw Error("Integrator \"mlt\": only the \"rgb\" film is supported yet");
    WorkCoordinator* const coord =
        opt.distribute && opt.distribute->workers() > 0 ? opt.distribute : nullptr;
    const IntegratorSettings::Mlt& mp = scene.integrator.mlt;
    const int max_depth = scene.integrator.max_depth;
    const int mpp = opt.spp > 0 ? opt.spp : mp.mutations_per_pixel;
    const uint64_t seed = scene.sampler.seed + opt.seed;
    const FilmParams& fp = film.params();

    const MltSetup setup(scene, film, seed);
    const double area = setup.area;

    const int threads = opt.threads > 0 ? opt.threads : int(std::thread::hardware_concurrency());
    tbb::global_control gc(tbb::global_control::max_allowed_parallelism, size_t(threads));
    tbb::task_arena arena(threads);
    tbb::enumerable_thread_specific<MltThread> states;
    ItemCounts remote;  // the other processes' counts (distributed)

    const auto t0 = Clock::now();
    const double cpu0 = process_cpu_seconds();
    auto elapsed = [&] { return std::chrono::duration<double>(Clock::now() - t0).count(); };

    // Mutations: pbrt-v4's (integer) area of the sample bounds per mutation per pixel, in
    // rounds of one mutation per pixel; mutation j goes to chain j mod n (so that every chain
    // takes part when a round has fewer mutations than there are chains).
    const int64_t per_round = std::max<int64_t>(1, int64_t(area));
    const int64_t n_chains = mp.chains;
    const int64_t n_boot = int64_t(mp.bootstrap_samples) * (max_depth + 1);
    Progress progress(opt.progress, uint64_t(n_boot) + uint64_t(per_round) * uint64_t(mpp));
    RenderStats stats;

    // 1. Bootstrap: independent states, each the first state of the sampler of its index.
    // Distributed, blocks of kBootBlock samples are the items; each weight lands at its index.
    std::vector<Float> weights(size_t(n_boot), 0);
    if (!coord) {
        arena.execute([&] {
            tbb::parallel_for(tbb::blocked_range<int64_t>(0, n_boot, 256),
                              [&](const tbb::blocked_range<int64_t>& r) {
                                  MltThread& th = states.local();
                                  for (int64_t i = r.begin(); i < r.end(); ++i)
                                      weights[size_t(i)] = setup.bootstrap(i, th);
                                  progress.add(uint64_t(r.size()));
                              });
        });
    } else {
        auto block = [&](size_t k) {
            const int64_t i0 = int64_t(k) * kBootBlock;
            return std::pair<int64_t, int64_t>(i0, std::min(n_boot, i0 + kBootBlock));
        };
        WorkCoordinator::Phase ph;
        ph.kind = kMltItems;
        ByteWriter hw(ph.header);
        hw.put(uint8_t(kStageBootstrap));
        hw.put(seed);
        hw.put(n_boot);
        ph.items = size_t((n_boot + kBootBlock - 1) / kBootBlock);
        ph.input = [](size_t, ByteWriter&) {};
        ph.output = [&](size_t k, ByteReader& br) {
            const auto [i0, i1] = block(k);
            remote.paths += br.get<uint64_t>();
            remote.rays += br.get<uint64_t>();
            remote.nonfinite += br.get<uint64_t>();
            br.get_array(weights.data() + i0, size_t(i1 - i0));
            progress.add(uint64_t(i1 - i0));
        };
        ph.local = [&](const std::function<std::optional<size_t>()>& claim,
                       const std::function<void(size_t)>&) {
            run_local_share(arena, threads, claim, [] { return false; }, [&](size_t k) {
                const auto [i0, i1] = block(k);
                MltThread& th = states.local();
                for (int64_t i = i0; i < i1; ++i) weights[size_t(i)] = setup.bootstrap(i, th);
                progress.add(uint64_t(i1 - i0));
            });
        };
        coord->run(ph);
    }
    double sum = 0;
    for (Float w : weights) sum += double(w);
    if (!(sum > 0) || !std::isfinite(sum))
        throw Error(fmt::format("Integrator \"mlt\": none of the {} bootstrap paths carries "
                                "light (is the image black? if not, raise \"bootstrapsamples\")",
                                n_boot));
    // b: the integral of c over primary sample space, summed over the depths.
    const double b = sum / double(mp.bootstrap_samples);
    const AliasTable table(weights);

    // 2. The chains, each from a bootstrap state drawn in proportion to its c (on this
    // process: n_chains evaluations).
    std::vector<Chain> chains;
    chains.reserve(size_t(n_chains));
    for (int64_t i = 0; i < n_chains; ++i)
        chains.push_back(Chain{MltSampler(mp.sigma, mp.large_step_probability, kStreams, 0, 0),
                               Pcg32(uint64_t(i), mix_bits(seed ^ 0x636861696eULL)), 0, {}, {}});
    arena.execute([&] {
        tbb::parallel_for(tbb::blocked_range<int64_t>(0, n_chains, 16),
                          [&](const tbb::blocked_range<int64_t>& r) {
                              MltThread& th = states.local();
                              for (int64_t i = r.begin(); i < r.end(); ++i) {
                                  Chain& ch = chains[size_t(i)];
                                  const int index = table.sample(ch.rng.next_float());
                                  ch.depth = index % (max_depth + 1);
                                  ch.sampler = MltSampler(mp.sigma, mp.large_step_probability,
                                                          kStreams, uint64_t(index), seed);
                                  evaluate(scene, film, setup.ctx, ch.sampler, ch.depth, th,
                                           ch.current);
                                  ch.sampler.reseed(uint64_t(n_boot + i), seed);
                              }
                          });
    });

    // 3. Rounds of mutations; each round's splats added chain by chain.
    std::vector<double> sums = film.splat_buffer();
    const size_t chunk = size_t(std::max(64, 8 * threads));
    const int n_bands = std::min(fp.height(), 4 * threads);
    std::vector<std::vector<Splat>> splats(coord ? size_t(n_chains) : chunk);
    std::vector<uint64_t> splat_nonfinite(splats.size(), 0);
    const Filter& filter = *scene.filter;
    // Distributed: chains per item, so that a worker's job is tens of milliseconds of work
    // (a busy coordinator answers a request late; fewer, larger messages), while a round
    // keeps about 8 items per thread of all processes.
    const int64_t chain_block =
        coord ? std::clamp<int64_t>(
                    n_chains / (8 * int64_t(threads) * (coord->workers() + 1)), 1, 64)
              : 1;
    int done = 0;
    for (int64_t round = 0; round < mpp; ++round) {
        if (round > 0 && opt.stop && opt.stop->load()) {
            stats.interrupted = true;
            break;
        }
        if (round > 0 && opt.time_budget > 0 && elapsed() > opt.time_budget) {
            stats.time_limited = true;
            break;
        }
        auto share = [&](int64_t i) {
            return chain_share(i, n_chains, round * per_round, (round + 1) * per_round);
        };
        if (coord) {
            // Distributed: blocks of consecutive chains are the items, each chain handed out
            // with its state and returned with it and its splats; the splats are added chain
            // by chain in chain order (Phase::reduce), every pixel receiving the additions one
            // process makes, in the same order (which the block size does not change).
            WorkCoordinator::Phase ph;
            ph.kind = kMltItems;
            ByteWriter hw(ph.header);
            hw.put(uint8_t(kStageRound));
            hw.put(seed);
            hw.put(round);
            hw.put(per_round);
            hw.put(n_chains);
            hw.put(chain_block);
            auto chains_of = [&](size_t k) {
                const int64_t c0 = int64_t(k) * chain_block;
                return std::pair<int64_t, int64_t>(c0, std::min(n_chains, c0 + chain_block));
            };
            ph.items = size_t((n_chains + chain_block - 1) / chain_block);
            ph.window = size_t(std::max(32, 6 * threads * (coord->workers() + 1)));
            ph.input = [&](size_t k, ByteWriter& bw) {
                const auto [c0, c1] = chains_of(k);
                for (int64_t i = c0; i < c1; ++i) put_chain(bw, chains[size_t(i)]);
            };
            ph.output = [&](size_t k, ByteReader& br) {
                const auto [c0, c1] = chains_of(k);
                remote.paths += br.get<uint64_t>();
                remote.rays += br.get<uint64_t>();
                remote.nonfinite += br.get<uint64_t>();
                for (int64_t i = c0; i < c1; ++i) {
                    get_chain(br, chains[size_t(i)], max_depth);
                    const size_t at = br.left();
                    get_splats(br, splats[size_t(i)]);
                    stats.dist_splat_bytes += at - br.left();
                    progress.add(uint64_t(share(i)));
                }
            };
            ph.local = [&](const std::function<std::optional<size_t>()>& claim,
                           const std::function<void(size_t)>& block_done) {
                run_local_share(arena, threads, claim, [] { return false; }, [&](size_t k) {
                    const auto [c0, c1] = chains_of(k);
                    for (int64_t i = c0; i < c1; ++i) {
                        const size_t ci = size_t(i);
                        splats[ci].clear();
                        splat_nonfinite[ci] = 0;
                        setup.run_chain(chains[ci], share(i), states.local(), splats[ci],
                                        splat_nonfinite[ci]);
                        progress.add(uint64_t(share(i)));
                    }
                    block_done(k);
                });
            };
            // The reduction: reduce() queues the blocks in chain order; `n_red` threads, each
            // owning a band of rows, add every queued block's splats into their rows in that
            // order (a pixel's terms keep their order; one process adds its chunks in bands
            // too), and the last band to finish a block frees its splats. At most `window`
            // blocks wait for their bands.
            const int n_red = std::max(1, std::min(fp.height(), threads));
            std::mutex qm;
            std::condition_variable qcv;
            std::vector<size_t> ready;
            bool closing = false;
            std::unique_ptr<std::atomic<int>[]> bands_left(new std::atomic<int>[ph.items]);
            std::atomic<size_t> pending{0};
            std::vector<double> red_cpu(size_t(n_red), 0);
            std::vector<std::thread> reducers;
            for (int band = 0; band < n_red; ++band)
                reducers.emplace_back([&, band] {
                    const double t0c = thread_cpu_seconds();
                    const int r0 = fp.y0 + int(int64_t(band) * fp.height() / n_red);
                    const int r1 = fp.y0 + int(int64_t(band + 1) * fp.height() / n_red);
                    for (size_t next = 0;; ++next) {
                        size_t k = 0;
                        {
                            std::unique_lock<std::mutex> lock(qm);
                            qcv.wait(lock, [&] { return next < ready.size() || closing; });
                            if (next >= ready.size()) break;
                            k = ready[next];
                        }
                        const auto [c0, c1] = chains_of(k);
                        for (int64_t i = c0; i < c1; ++i)
                            for (const Splat& sp : splats[size_t(i)])
                                film.add_splat(sums, sp.p, sp.xyz, filter, r0, r1);
                        if (bands_left[k].fetch_sub(1, std::memory_order_acq_rel) == 1) {
                            for (int64_t i = c0; i < c1; ++i)
                                std::vector<Splat>().swap(splats[size_t(i)]);
                            pending.fetch_sub(1, std::memory_order_release);
                        }
                    }
                    red_cpu[size_t(band)] = thread_cpu_seconds() - t0c;
                });
            auto close_reducers = [&] {
                {
                    const std::lock_guard<std::mutex> lock(qm);
                    closing = true;
                }
                qcv.notify_all();
                for (std::thread& t : reducers) t.join();
                reducers.clear();
            };
            ph.reduce = [&](size_t k) {
                const auto [c0, c1] = chains_of(k);
                for (int64_t i = c0; i < c1; ++i) {
                    const size_t ci = size_t(i);
                    remote.nonfinite += splat_nonfinite[ci];
                    splat_nonfinite[ci] = 0;
                    stats.dist_splats += splats[ci].size();
                }
                while (pending.load(std::memory_order_acquire) >= ph.window)
                    std::this_thread::sleep_for(std::chrono::microseconds(200));
                bands_left[k].store(n_red, std::memory_order_relaxed);
                pending.fetch_add(1, std::memory_order_relaxed);
                {
                    const std::lock_guard<std::mutex> lock(qm);
                    ready.push_back(k);
                }
                qcv.notify_all();
            };
            try {
                coord->run(ph);
            } catch (...) {
                close_reducers();
                throw;
            }
            close_reducers();
            for (double c : red_cpu) stats.dist_splat_seconds += c;
            done = int(round) + 1;
            continue;
        }
        for (int64_t c0 = 0; c0 < n_chains; c0 += int64_t(chunk)) {
            const int64_t c1 = std::min(n_chains, c0 + int64_t(chunk));
            arena.execute([&] {
                tbb::parallel_for(
                    tbb::blocked_range<int64_t>(c0, c1, 1),
                    [&](const tbb::blocked_range<int64_t>& r) {
                        MltThread& th = states.local();
                        for (int64_t i = r.begin(); i < r.end(); ++i) {
                            std::vector<Splat>& out = splats[size_t(i - c0)];
                            uint64_t& bad = splat_nonfinite[size_t(i - c0)];
                            out.clear();
                            bad = 0;
                            const int64_t n = share(i);
                            setup.run_chain(chains[size_t(i)], n, th, out, bad);
                            progress.add(uint64_t(n));
                        }
                    },
                    tbb::simple_partitioner());
            });
            // The chunk's splats, chain by chain: each pixel receives its additions in chain
            // order, whichever thread adds into its band of rows.
            for (int64_t i = c0; i < c1; ++i)
                states.local().nonfinite += splat_nonfinite[size_t(i - c0)];
            arena.execute([&] {
                tbb::parallel_for(0, n_bands, [&](int band) {
                    const int r0 = fp.y0 + int(int64_t(band) * fp.height() / n_bands);
                    const int r1 = fp.y0 + int(int64_t(band + 1) * fp.height() / n_bands);
                    for (int64_t i = c0; i < c1; ++i)
                        for (const Splat& sp : splats[size_t(i - c0)])
                            film.add_splat(sums, sp.p, sp.xyz, filter, r0, r1);
                });
            });
        }
        done = int(round) + 1;
    }
    progress.finish();

    film.set_splat_sums(std::move(sums));
    // Each mutation carries b / (mutations) of the integral over the sample bounds' area.
    film.set_splat_scale(b * area / (double(per_round) * double(done)) / filter.integral());
    stats.wall_seconds = elapsed();
    stats.cpu_seconds = process_cpu_seconds() - cpu0;
    stats.spp = done;
    for (const MltThread& th : states) {
        stats.camera_paths += th.paths;
        stats.rays += th.counters.rays;
        stats.nonfinite += th.nonfinite;
    }
    stats.camera_paths += remote.paths;
    stats.rays += remote.rays;
    stats.nonfinite += remote.nonfinite;
    stats.peak_rss_bytes = peak_rss_bytes();
    return stats;
}

JobHandler mlt_job_handler(const Scene& scene, int threads) {
    // A worker's state: a film of the scene's parameters (for its wavelengths and sensor
    // values), the setup of the seed the jobs carry, and its threads.
    struct Worker {
        Film film;
        std::unique_ptr<MltSetup> setup;
        int threads;
        tbb::task_arena arena;
        tbb::enumerable_thread_specific<MltThread> states;
        Worker(const Scene& s, int n)
            : film(s.film), threads(n > 0 ? n : int(std::thread::hardware_concurrency())),
              arena(threads) {}
    };
    auto wk = std::make_shared<Worker>(scene, threads);
    return [&scene, wk](ByteReader& header, size_t count, ByteReader& inputs,
                        ByteWriter& outputs) {
        Worker& W = *wk;
        if (scene.integrator.type != "mlt")
            throw Error("distributed: Metropolis work for a scene of another integrator");
        const uint8_t stage = header.get<uint8_t>();
        const uint64_t seed = header.get<uint64_t>();
        if (!W.setup || W.setup->seed != seed) W.setup = std::make_unique<MltSetup>(scene, W.film, seed);
        const MltSetup& setup = *W.setup;
        std::vector<uint64_t> items(count);
        std::vector<ItemCounts> counts(count);  // each item's
        auto now = [](const MltThread& th) {
            return ItemCounts{th.paths, th.counters.rays, th.nonfinite};
        };
        auto delta = [](const ItemCounts& a, const ItemCounts& b) {
            return ItemCounts{b.paths - a.paths, b.rays - a.rays, b.nonfinite - a.nonfinite};
        };
        if (stage == kStageBootstrap) {
            const int64_t n_boot = header.get<int64_t>();
            if (n_boot != int64_t(setup.mp.bootstrap_samples) * (setup.max_depth + 1))
                throw Error("distributed: a bootstrap of another size than the scene's");
            std::vector<std::vector<Float>> w(count);
            for (size_t j = 0; j < count; ++j) {
                items[j] = inputs.get<uint64_t>();
                if (items[j] >= uint64_t((n_boot + kBootBlock - 1) / kBootBlock))
                    throw Error("distributed: a bootstrap block outside the bootstrap");
            }
            W.arena.execute([&] {
                tbb::parallel_for(size_t(0), count, [&](size_t j) {
                    MltThread& th = W.states.local();
                    const ItemCounts before = now(th);
                    const int64_t i0 = int64_t(items[j]) * kBootBlock;
                    const int64_t i1 = std::min(n_boot, i0 + kBootBlock);
                    for (int64_t i = i0; i < i1; ++i) w[j].push_back(setup.bootstrap(i, th));
                    counts[j] = delta(before, now(th));
                }, tbb::simple_partitioner());
            });
            for (size_t j = 0; j < count; ++j) {
                outputs.put(items[j]);
                outputs.put(counts[j].paths);
                outputs.put(counts[j].rays);
                outputs.put(counts[j].nonfinite);
                outputs.put_array(w[j].data(), w[j].size());
            }
            return;
        }
        if (stage != kStageRound) throw Error("distributed: an unknown Metropolis stage");
        const int64_t round = header.get<int64_t>();
        const int64_t per_round = header.get<int64_t>();
        const int64_t n_chains = header.get<int64_t>();
        const int64_t block = header.get<int64_t>();
        if (n_chains != setup.mp.chains || round < 0 || per_round < 1 || block < 1)
            throw Error("distributed: a round of other chains than the scene's");
        const uint64_t n_items = uint64_t((n_chains + block - 1) / block);
        std::vector<std::vector<Chain>> chains(count);
        std::vector<std::vector<std::vector<Splat>>> splats(count);
        std::vector<uint64_t> bad(count, 0);
        for (size_t j = 0; j < count; ++j) {
            items[j] = inputs.get<uint64_t>();
            if (items[j] >= n_items) throw Error("distributed: a block of no chains");
            const int64_t c0 = int64_t(items[j]) * block, c1 = std::min(n_chains, c0 + block);
            chains[j].resize(size_t(c1 - c0),
                             Chain{MltSampler(0, 0, kStreams, 0, 0), {}, 0, {}, {}});
            splats[j].resize(size_t(c1 - c0));
            for (Chain& ch : chains[j]) get_chain(inputs, ch, setup.max_depth);
        }
        W.arena.execute([&] {
            tbb::parallel_for(size_t(0), count, [&](size_t j) {
                MltThread& th = W.states.local();
                const ItemCounts before = now(th);
                const int64_t c0 = int64_t(items[j]) * block;
                for (size_t k = 0; k < chains[j].size(); ++k) {
                    const int64_t n = chain_share(c0 + int64_t(k), n_chains, round * per_round,
                                                  (round + 1) * per_round);
                    setup.run_chain(chains[j][k], n, th, splats[j][k], bad[j]);
                }
                counts[j] = delta(before, now(th));
            }, tbb::simple_partitioner());
        });
        for (size_t j = 0; j < count; ++j) {
            outputs.put(items[j]);
            outputs.put(counts[j].paths);
            outputs.put(counts[j].rays);
            outputs.put(counts[j].nonfinite + bad[j]);
            for (size_t k = 0; k < chains[j].size(); ++k) {
                put_chain(outputs, chains[j][k]);
                put_splats(outputs, splats[j][k]);
            }
        }
    };
}

}  // namespace sr
