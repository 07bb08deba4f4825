#include <sys/resource.h>
#include <unistd.h>

#include <atomic>
#include <chrono>
#include <condition_variable>
#include <cstdio>
#include <mutex>
#include <thread>

#include <tbb/blocked_range2d.h>
#include <tbb/enumerable_thread_specific.h>
#include <tbb/global_control.h>
#include <tbb/parallel_for.h>
#include <tbb/task_arena.h>

#include "steradian/core/error.h"
#include "steradian/integrators/integrator.h"
#include "steradian/integrators/path/path.h"
#include "steradian/scene/scene.h"

namespace sr {

double process_cpu_seconds() {
    rusage ru{};
    getrusage(RUSAGE_SELF, &ru);
    return double(ru.ru_utime.tv_sec) + 1e-6 * double(ru.ru_utime.tv_usec) +
           double(ru.ru_stime.tv_sec) + 1e-6 * double(ru.ru_stime.tv_usec);
}

size_t peak_rss_bytes() {
    rusage ru{};
    getrusage(RUSAGE_SELF, &ru);
    return size_t(ru.ru_maxrss) * 1024;
}

namespace {

using Clock = std::chrono::steady_clock;

struct ThreadState {
    std::unique_ptr<Sampler> sampler;
    PathCounters counters;
    uint64_t paths = 0;
    uint64_t nonfinite = 0;
};

/// Progress bar on stderr: percent, elapsed, ETA. Redrawn by its own thread.
class Progress {
public:
    Progress(bool enabled, uint64_t total) : m_enabled(enabled), m_total(total) {
        if (!m_enabled) return;
        m_start = Clock::now();
        m_thread = std::thread([this] { loop(); });
    }
    ~Progress() { finish(); }
    void add(uint64_t n) { m_done += n; }
    void finish() {
        if (!m_enabled || !m_thread.joinable()) return;
        {
            std::lock_guard lock(m_mutex);
            m_stop = true;
        }
        m_cv.notify_all();
        m_thread.join();
        draw();
        std::fprintf(stderr, "\n");
    }

private:
    void loop() {
        std::unique_lock lock(m_mutex);
        while (!m_stop) {
            m_cv.wait_for(lock, std::chrono::milliseconds(200));
            if (!m_stop) draw();
        }
    }
    void draw() {
        double frac = m_total ? double(m_done.load()) / double(m_total) : 1;
        frac = std::min(frac, 1.0);
        double el = std::chrono::duration<double>(Clock::now() - m_start).count();
        double eta = frac > 0 ? el * (1 - frac) / frac : 0;
        const int width = 40;
        int filled = int(frac * width);
        char bar[width + 1];
        for (int i = 0; i < width; ++i) bar[i] = i < filled ? '#' : '.';
        bar[width] = 0;
        std::fprintf(stderr, "\r[%s] %5.1f%%  elapsed %6.1fs  ETA %6.1fs ", bar, 100 * frac, el,
                     eta);
        std::fflush(stderr);
    }
    bool m_enabled;
    uint64_t m_total;
    std::atomic<uint64_t> m_done{0};
    Clock::time_point m_start;
    std::thread m_thread;
    std::mutex m_mutex;
    std::condition_variable m_cv;
    bool m_stop = false;
};

}  // namespace

RenderStats render(const Scene& scene, Film& film, const RenderOptions& opt) {
    if (scene.integrator.type != "path")
        throw Error(fmt::format("integrator \"{}\" is not supported yet", scene.integrator.type));
    const FilmParams& fp = film.params();
    const int spp = opt.spp > 0 ? opt.spp : scene.sampler.spp;
    const uint64_t seed = scene.sampler.seed + opt.seed;
    std::unique_ptr<Sampler> proto;
    if (scene.sampler.type == "stratified")
        proto = make_stratified_sampler(scene.sampler.x_samples, scene.sampler.y_samples,
                                        scene.sampler.jitter, seed);
    else
        proto = make_sampler(scene.sampler.type, spp, fp.resolution, seed);
    const int total_spp = scene.sampler.type == "stratified" ? proto->samples_per_pixel() : spp;

    int threads = opt.threads > 0 ? opt.threads : int(std::thread::hardware_concurrency());
    tbb::global_control gc(tbb::global_control::max_allowed_parallelism, size_t(threads));
    tbb::task_arena arena(threads);

    tbb::enumerable_thread_specific<ThreadState> states([&] {
        ThreadState s;
        s.sampler = proto->clone();
        return s;
    });

    RenderStats stats;
    const auto t0 = Clock::now();
    const double cpu0 = process_cpu_seconds();
    const int w = fp.width(), h = fp.height();
    Progress progress(opt.progress, uint64_t(w) * h * uint64_t(total_spp));
    std::atomic<bool> out_of_time{false};
    auto elapsed = [&] { return std::chrono::duration<double>(Clock::now() - t0).count(); };

    const Camera& camera = *scene.camera;
    const Filter& filter = *scene.filter;
    const bool thin_lens = camera.uses_lens_sample();
    constexpr int kTile = 16;
    // The camera's dimensions after the pixel dimensions: the lens sample.
    constexpr int kCameraDimensions = 2;

    // Passes exist for the time budget: whole passes of 1, 2, 4, ... up to 64 samples per
    // pixel, so that stopping early still leaves an image of evenly many samples. Without a
    // budget one pass does everything, so that the samplers compute the per-pixel parts of
    // each dimension once per pixel rather than once per pass.
    int done = 0;
    int pass_size = opt.time_budget > 0 ? 1 : total_spp;
    while (done < total_spp) {
        int s0 = done, s1 = std::min(total_spp, done + pass_size);
        std::vector<PixelSum> pass = film.make_buffer();
        arena.execute([&] {
            tbb::parallel_for(
                tbb::blocked_range2d<int>(fp.y0, fp.y1, kTile, fp.x0, fp.x1, kTile),
                [&](const tbb::blocked_range2d<int>& r) {
                    if (out_of_time.load(std::memory_order_relaxed)) return;
                    if (opt.time_budget > 0 && elapsed() > opt.time_budget) {
                        out_of_time = true;
                        return;
                    }
                    ThreadState& ts = states.local();
                    Sampler& sampler = *ts.sampler;
                    // A pixel's camera rays are traced as packets of kRayPacket (they are
                    // coherent, and a packet costs far less than its rays one by one); each
                    // path then continues from its first hit, taking the sampler's
                    // dimensions after the camera's, so the image is the same as with
                    // one ray at a time.
                    constexpr int kPacket = Scene::kRayPacket;
                    Ray rays[kPacket];
                    SurfaceHit hits[kPacket];
                    FilterSample fss[kPacket];
                    SampledWavelengths lambdas[kPacket];
                    SampledSpectrum Ls[kPacket];
                    DeferredShadowRay shadows[kPacket];
                    Ray shadow_rays[kPacket];
                    for (int y = r.rows().begin(); y < r.rows().end(); ++y)
                        for (int x = r.cols().begin(); x < r.cols().end(); ++x) {
                            const Vec2i pixel(x, y);
                            sampler.start_pixel(pixel, s0, s1);
                            for (int sb = s0; sb < s1; sb += kPacket) {
                                const int n = std::min(kPacket, s1 - sb);
                                for (int k = 0; k < n; ++k) {
                                    sampler.start_pixel_sample(pixel, sb + k);
                                    Point2 up = sampler.get_pixel_2d();
                                    fss[k] = filter.sample(up);
                                    lambdas[k] = SampledWavelengths::sample_visible(
                                        sampler.get_pixel_1d());
                                    // The lens dimensions are consumed either way, so that
                                    // the path's dimensions do not depend on the camera.
                                    Point2 u_lens(0.5f, 0.5f);
                                    if (thin_lens) u_lens = sampler.get_2d();
                                    Point2 p_film(Float(x) + 0.5f + fss[k].offset.x,
                                                  Float(y) + 0.5f + fss[k].offset.y);
                                    rays[k] = camera.generate_ray(p_film, u_lens);
                                }
                                const unsigned found =
                                    scene.intersect_packet(rays, (1u << n) - 1, hits);
                                // The first vertices' shadow rays start close together
                                // and aim at the same lights: tested as one packet after
                                // the paths, which do not depend on them.
                                for (int k = 0; k < n; ++k) {
                                    sampler.start_pixel_sample(pixel, sb + k, kCameraDimensions);
                                    Ls[k] = path_li_from(scene, rays[k], (found >> k) & 1,
                                                         hits[k], lambdas[k], sampler,
                                                         ts.counters, &shadows[k]);
                                    shadow_rays[k] = shadows[k].ray;
                                }
                                unsigned pending = 0;
                                for (int k = 0; k < n; ++k)
                                    pending |= unsigned(shadows[k].pending) << k;
                                const unsigned blocked =
                                    pending ? scene.occluded_packet(shadow_rays, pending) : 0;
                                for (int k = 0; k < n; ++k) {
                                    SampledSpectrum L = Ls[k];
                                    if (((pending & ~blocked) >> k) & 1)
                                        L += shadows[k].contribution;
                                    if (L.has_nonfinite()) {
                                        ++ts.nonfinite;
                                        L = SampledSpectrum(0);
                                    }
                                    ++ts.paths;
                                    film.add(pass, x, y, film.to_sensor(L, lambdas[k]),
                                             fss[k].weight);
                                }
                            }
                        }
                    progress.add(uint64_t(r.rows().size()) * r.cols().size() * (s1 - s0));
                });
        });
        if (out_of_time) {
            stats.time_limited = true;
            break;
        }
        film.merge(pass);
        done = s1;
        pass_size = std::min(pass_size * 2, 64);
        if (opt.time_budget > 0 && elapsed() > opt.time_budget && done < total_spp) {
            stats.time_limited = true;
            break;
        }
    }
    progress.finish();

    stats.wall_seconds = elapsed();
    stats.cpu_seconds = process_cpu_seconds() - cpu0;
    stats.spp = done;
    for (const ThreadState& s : states) {
        stats.camera_paths += s.paths;
        stats.rays += s.counters.rays;
        stats.nonfinite += s.nonfinite;
    }
    stats.peak_rss_bytes = peak_rss_bytes();
    return stats;
}

}  // namespace sr
