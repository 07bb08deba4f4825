#include <sys/resource.h>
#include <time.h>
#include <unistd.h>

#include <array>
#include <atomic>
#include <chrono>
#include <cmath>
#include <condition_variable>
#include <cstdio>
#include <mutex>
#include <optional>
#include <string>
#include <thread>

#include <tbb/blocked_range2d.h>
#include <tbb/enumerable_thread_specific.h>
#include <tbb/global_control.h>
#include <tbb/parallel_for.h>
#include <tbb/task_arena.h>

#include "steradian/core/error.h"
#include "steradian/integrators/bdpt/bdpt.h"
#include "steradian/integrators/distributed.h"
#include "steradian/integrators/integrator.h"
#include "steradian/integrators/mlt/mlt.h"
#include "steradian/integrators/path/path.h"
#include "steradian/integrators/progress.h"
#include "steradian/integrators/radiosity/radiosity.h"
#include "steradian/integrators/sppm/sppm.h"
#include "steradian/integrators/vcm/vcm.h"
#include "steradian/scene/scene.h"

namespace sr {

double process_cpu_seconds() {
    rusage ru{};
    getrusage(RUSAGE_SELF, &ru);
    return double(ru.ru_utime.tv_sec) + 1e-6 * double(ru.ru_utime.tv_usec) +
           double(ru.ru_stime.tv_sec) + 1e-6 * double(ru.ru_stime.tv_usec);
}

double thread_cpu_seconds() {
    timespec ts{};
    clock_gettime(CLOCK_THREAD_CPUTIME_ID, &ts);
    return double(ts.tv_sec) + 1e-9 * double(ts.tv_nsec);
}

size_t peak_rss_bytes() {
    rusage ru{};
    getrusage(RUSAGE_SELF, &ru);
    return size_t(ru.ru_maxrss) * 1024;
}

namespace {

using Clock = std::chrono::steady_clock;

/// Up to kSize camera samples of one pixel in flight together. A pixel's camera rays are
/// coherent, and traced as one packet they cost far less than one by one; each path then
/// continues from its first hit with the sampler's dimensions after the camera's, so each
/// sample's estimate is the one of tracing it alone (path_li), up to the order of a sum and
/// to which of two coincident surfaces a camera ray reports (Embree's traversal order, which
/// differs between packets and single rays, decides a tie in distance). The paths' first
/// vertices' shadow rays start close together and aim at the same lights: the paths leave
/// them untested, nothing in a path depends on them, and they are tested as one packet
/// afterwards.
struct SamplePacket {
    static constexpr int kSize = Scene::kRayPacket;
    Ray rays[kSize];
    SurfaceHit hits[kSize];
    FilterSample filter[kSize];
    SampledWavelengths lambda[kSize];
    SampledSpectrum L[kSize];
    DeferredShadowRay shadow[kSize];
    Ray shadow_rays[kSize];
    Point2 p_film[kSize], u_lens[kSize];
    VisibleSurface visible[kSize];  ///< for films that use it (gbuffer)
};

struct ThreadState {
    std::unique_ptr<Sampler> sampler;
    PathCounters counters;
    uint64_t paths = 0;
    uint64_t nonfinite = 0;
    /// Scale of the camera's ray differentials for texture footprints (0: none; pbrt-v4's
    /// max(1/8, 1/sqrt(spp))).
    Float footprint_scale = 0;
    /// Scale of the first hits' footprints when only the film needs them (gbuffer's
    /// dpdx, dpdy; the same scale).
    Float visible_footprint_scale = 0;
    /// Integrator "radiosity": the solution its camera samples gather from; null: path.
    const RadiositySolution* radiosity = nullptr;
    /// Scratch space of render_packet (kept per thread: its hit records are large).
    std::unique_ptr<SamplePacket> packet = std::make_unique<SamplePacket>();
    /// Scratch space of the bidirectional integrators' subpaths.
    BdptScratchPtr bdpt = make_bdpt_scratch();
};

/// A splat as a tile records it: sensor values at a film position, for buffer `buffer` (0:
/// the image; k + 1: strategy image k of visualizestrategies / visualizeweights).
struct SplatRecord {
    Point2 p;
    int buffer;
    std::array<double, 3> xyz;
};

/// The bidirectional integrators' splats of one tile, in the order its samples made them.
class TileSplats final : public SplatSink {
public:
    TileSplats(const Film& film, uint64_t& nonfinite, std::vector<SplatRecord>& out, int max_depth,
               bool weights)
        : m_film(film), m_nonfinite(nonfinite), m_out(out), m_max_depth(max_depth),
          m_weights(weights) {}
    const SampledWavelengths* lambda = nullptr;
    void splat(Point2 p, const SampledSpectrum& L) override { add(p, 0, L); }
    void strategy(int s, int t, Point2 p, const SampledSpectrum& L, Float w) override {
        const int depth = s + t - 2;
        if (depth > m_max_depth) return;
        // pbrt-v4's BufferIndex: strategies of one depth together, by s.
        const int index = s + depth * (5 + depth) / 2;
        // visualizeweights: the weighted contribution; visualizestrategies: the unweighted.
        add(p, 1 + index, m_weights ? L * w : L);
    }

private:
    void add(Point2 p, int buffer, const SampledSpectrum& L) {
        std::array<double, 3> xyz{0, 0, 0};
        bool finite = !L.has_nonfinite();
        if (finite) {
            xyz = m_film.to_sensor(L, *lambda);
            finite = std::isfinite(xyz[0]) && std::isfinite(xyz[1]) && std::isfinite(xyz[2]);
        }
        if (!finite) {
            ++m_nonfinite;
            return;
        }
        if (xyz[0] == 0 && xyz[1] == 0 && xyz[2] == 0) return;
        m_out.push_back({p, buffer, xyz});
    }
    const Film& m_film;
    uint64_t& m_nonfinite;
    std::vector<SplatRecord>& m_out;
    int m_max_depth;
    bool m_weights;
};

/// Samples [s0, s1) of `pixel` with a bidirectional integrator: the pixel's estimates
/// (bdpt's t >= 2 strategies) go to `pass`, the splats to `splats`.
void render_bidir_pixel(const Scene& scene, const BidirContext& ctx, bool lightpath,
                        const Film& film, ThreadState& ts, Vec2i pixel, int s0, int s1,
                        std::vector<PixelSum>& pass, TileSplats& splats) {
    Sampler& sampler = *ts.sampler;
    for (int i = s0; i < s1; ++i) {
        sampler.start_pixel_sample(pixel, i);
        const FilterSample fs = scene.filter->sample(sampler.get_pixel_2d());
        SampledWavelengths lambda = film.sample_wavelengths(sampler.get_pixel_1d());
        // The lens sample is drawn whether or not the camera has a lens (kCameraDimensions).
        const Point2 u_lens = sampler.get_2d();
        splats.lambda = &lambda;
        ++ts.paths;
        if (lightpath) {
            lightpath_sample(ctx, *ts.bdpt, lambda, sampler, ts.counters, splats);
            continue;
        }
        const Point2 p_film(Float(pixel.x) + 0.5f + fs.offset.x, Float(pixel.y) + 0.5f + fs.offset.y);
        const Ray ray = scene.camera->generate_ray(
            p_film, scene.camera->uses_lens_sample() ? u_lens : Point2(0.5f, 0.5f));
        const SampledSpectrum L =
            bdpt_li(ctx, *ts.bdpt, ray, p_film, lambda, sampler, ts.counters, splats);
        std::array<double, 3> xyz{0, 0, 0};
        bool finite = !L.has_nonfinite();
        if (finite) {
            xyz = film.to_sensor(L, lambda);
            finite = std::isfinite(xyz[0]) && std::isfinite(xyz[1]) && std::isfinite(xyz[2]);
        }
        if (!finite) {
            ++ts.nonfinite;
            xyz = {0, 0, 0};
        }
        film.add(pass, pixel.x, pixel.y, xyz, fs.weight);
    }
}

/// Samples [first, first + n) of `pixel` (n <= SamplePacket::kSize), added to `pass`.
void render_packet(const Scene& scene, const Film& film, ThreadState& ts, Vec2i pixel, int first,
                   int n, std::vector<PixelSum>& pass, std::vector<double>& aux) {
    Sampler& sampler = *ts.sampler;
    SamplePacket& p = *ts.packet;
    const bool thin_lens = scene.camera->uses_lens_sample();
    for (int k = 0; k < n; ++k) {
        sampler.start_pixel_sample(pixel, first + k);
        p.filter[k] = scene.filter->sample(sampler.get_pixel_2d());
        p.lambda[k] = film.sample_wavelengths(sampler.get_pixel_1d());
        p.u_lens[k] = thin_lens ? sampler.get_2d() : Point2(0.5f, 0.5f);
        p.p_film[k] = Point2(Float(pixel.x) + 0.5f + p.filter[k].offset.x,
                             Float(pixel.y) + 0.5f + p.filter[k].offset.y);
        p.rays[k] = scene.camera->generate_ray(p.p_film[k], p.u_lens[k]);
    }
    const bool visible = film.uses_visible_surface();
    const unsigned found = scene.intersect_packet(p.rays, (1u << n) - 1, p.hits);
    // The first hits' footprints: for textures, and for the film's visible surfaces
    // (gbuffer's dpdx, dpdy, copied from the hit the path first scatters at).
    const Float first_scale = ts.footprint_scale > 0 ? ts.footprint_scale
                              : visible              ? ts.visible_footprint_scale
                                                     : 0;
    if (first_scale > 0) {
        for (int k = 0; k < n; ++k) {
            if (!((found >> k) & 1)) continue;
            const Point2 pf = p.p_film[k];
            const Ray rx = scene.camera->generate_ray(Point2(pf.x + 1, pf.y), p.u_lens[k]);
            const Ray ry = scene.camera->generate_ray(Point2(pf.x, pf.y + 1), p.u_lens[k]);
            set_footprint_from_rays(p.hits[k], p.rays[k], rx, ry, first_scale);
        }
    }
    unsigned pending = 0;
    for (int k = 0; k < n; ++k) {
        sampler.start_pixel_sample(pixel, first + k, kCameraDimensions);
        if (ts.radiosity) {
            p.L[k] = radiosity_li_from(scene, *ts.radiosity, p.rays[k], (found >> k) & 1, p.hits[k],
                                       p.lambda[k], sampler, ts.counters);
            p.shadow[k].pending = false;
            if (visible) p.visible[k].set = false;
            continue;
        }
        p.L[k] = path_li_from(scene, p.rays[k], (found >> k) & 1, p.hits[k], p.lambda[k], sampler,
                              ts.counters, &p.shadow[k], visible ? &p.visible[k] : nullptr,
                              ts.footprint_scale);
        p.shadow_rays[k] = p.shadow[k].ray;
        pending |= unsigned(p.shadow[k].pending) << k;
    }
    const unsigned lit = pending & ~(pending ? scene.occluded_packet(p.shadow_rays, pending) : 0);
    for (int k = 0; k < n; ++k) {
        SampledSpectrum L = p.L[k];
        if ((lit >> k) & 1) L += p.shadow[k].contribution;
        // A finite radiance near the float range can still overflow in its division by the
        // wavelength pdfs: the sensor value is checked too, so that no NaN or Inf reaches
        // the image uncounted.
        std::array<double, 3> xyz{0, 0, 0};
        bool finite = !L.has_nonfinite();
        if (finite) {
            xyz = film.to_sensor(L, p.lambda[k]);
            finite = std::isfinite(xyz[0]) && std::isfinite(xyz[1]) && std::isfinite(xyz[2]);
        }
        if (!finite) {
            ++ts.nonfinite;
            xyz = {0, 0, 0};
        }
        ++ts.paths;
        film.add(pass, pixel.x, pixel.y, xyz, p.filter[k].weight);
        if (film.has_aux())
            film.add_aux(aux, pixel.x, pixel.y, finite ? L : SampledSpectrum(0), p.lambda[k], xyz,
                         p.filter[k].weight, visible ? &p.visible[k] : nullptr);
    }
}

/// What a tile's samples cost: camera paths, rays and NaN/Inf samples.
struct TileCounts {
    uint64_t paths = 0, rays = 0, nonfinite = 0;
};

/// Samples [s0, s1) of every pixel of the tile [x0, x1) x [y0, y1), added to `pass` and
/// `aux`, pixel by pixel in packets that start at multiples of the packet size.
TileCounts render_tile(const Scene& scene, const Film& film, ThreadState& ts, int x0, int y0,
                       int x1, int y1, int s0, int s1, std::vector<PixelSum>& pass,
                       std::vector<double>& aux) {
    const TileCounts before{ts.paths, ts.counters.rays, ts.nonfinite};
    Sampler& sampler = *ts.sampler;
    for (int y = y0; y < y1; ++y)
        for (int x = x0; x < x1; ++x) {
            const Vec2i pixel(x, y);
            sampler.start_pixel(pixel, s0, s1);
            for (int sb = s0; sb < s1;) {
                const int se = std::min(s1, (sb / SamplePacket::kSize + 1) * SamplePacket::kSize);
                render_packet(scene, film, ts, pixel, sb, se - sb, pass, aux);
                sb = se;
            }
        }
    return {ts.paths - before.paths, ts.counters.rays - before.rays,
            ts.nonfinite - before.nonfinite};
}

/// Samples [s0, s1) of every pixel of the tile [x0, x1) x [y0, y1) with a bidirectional
/// integrator: the pixels' estimates added to `pass`, the splats recorded by `sink` in the
/// order the samples make them (pixels in rows, samples in index order).
TileCounts render_bidir_tile(const Scene& scene, const BidirContext& ctx, bool lightpath,
                             const Film& film, ThreadState& ts, const std::array<int, 4>& t,
                             int s0, int s1, std::vector<PixelSum>& pass, TileSplats& sink) {
    const TileCounts before{ts.paths, ts.counters.rays, ts.nonfinite};
    for (int y = t[1]; y < t[3]; ++y)
        for (int x = t[0]; x < t[2]; ++x) {
            ts.sampler->start_pixel(Vec2i(x, y), s0, s1);
            render_bidir_pixel(scene, ctx, lightpath, film, ts, Vec2i(x, y), s0, s1, pass, sink);
        }
    return {ts.paths - before.paths, ts.counters.rays - before.rays,
            ts.nonfinite - before.nonfinite};
}

/// A tile's splat records in a message (36 bytes each: position, buffer, sensor values),
/// and read back, exactly.
void put_splats(ByteWriter& bw, const std::vector<SplatRecord>& recs) {
    bw.put(uint64_t(recs.size()));
    for (const SplatRecord& r : recs) {
        bw.put(r.p.x);
        bw.put(r.p.y);
        bw.put(int32_t(r.buffer));
        bw.put_array(r.xyz.data(), 3);
    }
}

void get_splats(ByteReader& br, std::vector<SplatRecord>& recs, int buffers) {
    const uint64_t n = br.get<uint64_t>();
    if (n > br.left() / 36) throw Error("distributed: a truncated message");
    recs.resize(size_t(n));
    for (SplatRecord& r : recs) {
        r.p.x = br.get<Float>();
        r.p.y = br.get<Float>();
        r.buffer = br.get<int32_t>();
        if (r.buffer < 0 || r.buffer > buffers)
            throw Error("distributed: a splat of no image");
        br.get_array(r.xyz.data(), 3);
    }
}

/// What a distributed pass's workers compute (the header's integrator byte).
enum : uint8_t { kPassPath = 0, kPassRadiosity = 1, kPassBdpt = 2, kPassLightpath = 3 };

constexpr int kTile = 16;

/// The film's crop window in tiles of kTile x kTile pixels, numbered in rows: the items of a
/// distributed pass.
struct TileGrid {
    explicit TileGrid(const FilmParams& fp)
        : x0(fp.x0), y0(fp.y0), x1(fp.x1), y1(fp.y1), nx((fp.width() + kTile - 1) / kTile),
          ny((fp.height() + kTile - 1) / kTile) {}
    size_t count() const { return size_t(nx) * size_t(ny); }
    /// Tile i as {x0, y0, x1, y1}.
    std::array<int, 4> rect(size_t i) const {
        const int tx = x0 + int(i % size_t(nx)) * kTile, ty = y0 + int(i / size_t(nx)) * kTile;
        return {tx, ty, std::min(tx + kTile, x1), std::min(ty + kTile, y1)};
    }
    int x0, y0, x1, y1, nx, ny;
};

/// A tile's pixels' sums (and auxiliary sums) of `pass`, `aux`, appended to a message; and
/// read back from one.
void put_tile(ByteWriter& bw, const Film& film, const std::array<int, 4>& t,
              const std::vector<PixelSum>& pass, const std::vector<double>& aux) {
    const FilmParams& fp = film.params();
    const size_t stride = film.aux_stride(), w = size_t(t[2] - t[0]);
    for (int y = t[1]; y < t[3]; ++y) {
        const size_t at = size_t(y - fp.y0) * size_t(fp.width()) + size_t(t[0] - fp.x0);
        bw.put_array(pass.data() + at, w);
        if (stride) bw.put_array(aux.data() + at * stride, w * stride);
    }
}

void get_tile(ByteReader& br, const Film& film, const std::array<int, 4>& t,
              std::vector<PixelSum>& pass, std::vector<double>& aux) {
    const FilmParams& fp = film.params();
    const size_t stride = film.aux_stride(), w = size_t(t[2] - t[0]);
    for (int y = t[1]; y < t[3]; ++y) {
        const size_t at = size_t(y - fp.y0) * size_t(fp.width()) + size_t(t[0] - fp.x0);
        br.get_array(pass.data() + at, w);
        if (stride) br.get_array(aux.data() + at * stride, w * stride);
    }
}

/// The render's sampler and its per-thread state: one clone of the sampler per thread.
struct RenderThreads {
    RenderThreads(const Scene& scene, const FilmParams& fp, int total_spp, uint64_t seed,
                  const RadiositySolution* radiosity = nullptr) {
        if (scene.sampler.type == "stratified")
            proto = make_stratified_sampler(scene.sampler.x_samples, scene.sampler.y_samples,
                                            scene.sampler.jitter, seed);
        else
            proto = make_sampler(scene.sampler.type, total_spp, fp.resolution, seed);
        // pbrt-v4 scales camera ray differentials by max(1/8, 1/sqrt(samples per pixel)).
        const Float scale = std::max(Float(0.125), 1 / std::sqrt(Float(total_spp)));
        const bool footprints = scene.texture_footprints;
        states = std::make_unique<tbb::enumerable_thread_specific<ThreadState>>([this, scale,
                                                                                  footprints,
                                                                                  radiosity] {
            ThreadState s;
            s.sampler = proto->clone();
            s.radiosity = radiosity;
            if (footprints) s.footprint_scale = scale;
            s.visible_footprint_scale = scale;
            return s;
        });
    }
    std::unique_ptr<Sampler> proto;
    std::unique_ptr<tbb::enumerable_thread_specific<ThreadState>> states;
};

}  // namespace

int render_samples_per_pixel(const Scene& scene, const RenderOptions& opt) {
    if (scene.integrator.type == "mlt")  // mutations per pixel
        return opt.spp > 0 ? opt.spp : scene.integrator.mlt.mutations_per_pixel;
    if (scene.sampler.type == "stratified")
        return scene.sampler.x_samples * scene.sampler.y_samples;
    return opt.spp > 0 ? opt.spp : scene.sampler.spp;
}

RenderStats render(const Scene& scene, Film& film, const RenderOptions& opt) {
    const std::string& itype = scene.integrator.type;
    if (itype == "mlt") return render_mlt(scene, film, opt);
    const bool bidir = itype == "bdpt" || itype == "lightpath";
    if (itype == "sppm") return render_sppm(scene, film, opt);
    if (itype == "vcm") return render_vcm(scene, film, opt);
    if (itype != "path" && itype != "radiosity" && !bidir)
        throw Error(fmt::format("integrator \"{}\" is not supported yet", itype));
    std::unique_ptr<RadiositySolution> own_radiosity;
    const RadiositySolution* radiosity = opt.radiosity;
    if (itype == "radiosity" && !radiosity) {
        own_radiosity = solve_radiosity(scene, scene.integrator.radiosity, opt.threads);
        radiosity = own_radiosity.get();
    }
    std::optional<BidirContext> bctx;
    if (bidir) {
        check_bidir_scene(scene, itype.c_str());
        if (opt.checkpoint || opt.resume)
            throw Error(fmt::format("Integrator \"{}\": checkpoints are not supported yet for the "
                                    "bidirectional integrators",
                                    itype));
        if (film.has_aux())
            throw Error(fmt::format("Integrator \"{}\": only the \"rgb\" film is supported yet",
                                    itype));
        bctx.emplace(scene);
        bctx->visualize =
            itype == "bdpt" && (scene.integrator.visualize_strategies || scene.integrator.visualize_weights);
        bctx->unweighted = opt.bidir_unweighted;
        bctx->only_depth = opt.bidir_only_depth;
        if (!film.has_splats()) film.set_splat_sums(film.splat_buffer());
    }
    const FilmParams& fp = film.params();
    const int total_spp = render_samples_per_pixel(scene, opt);
    const uint64_t seed = scene.sampler.seed + opt.seed;

    int threads = opt.threads > 0 ? opt.threads : int(std::thread::hardware_concurrency());
    tbb::global_control gc(tbb::global_control::max_allowed_parallelism, size_t(threads));
    tbb::task_arena arena(threads);

    RenderThreads rt(scene, fp, total_spp, seed, radiosity);
    tbb::enumerable_thread_specific<ThreadState>& states = *rt.states;
    WorkCoordinator* const coord =
        opt.distribute && opt.distribute->workers() > 0 ? opt.distribute : nullptr;
    TileCounts remote;  // the workers' share (distributed)

    RenderStats stats;
    const auto t0 = Clock::now();
    const double cpu0 = process_cpu_seconds();
    const int w = fp.width(), h = fp.height();
    int done = 0;  // samples per pixel in the film
    if (opt.resume) {
        if (opt.resume->spp < 0 || opt.resume->spp > total_spp)
            throw Error(fmt::format("resume: {} samples per pixel done of {}", opt.resume->spp,
                                    total_spp));
        done = opt.resume->spp;
    }
    const int first_spp = done;  // this run's first pass always completes
    Progress progress(opt.progress, uint64_t(w) * h * uint64_t(total_spp - done));
    std::atomic<bool> out_of_time{false};
    auto elapsed = [&] { return std::chrono::duration<double>(Clock::now() - t0).count(); };

    static_assert(kPassAlign % SamplePacket::kSize == 0);
    const TileGrid grid(fp);

    // The bidirectional integrators' fixed tiles (their splats are reduced in tile order,
    // so that the image does not depend on the number of threads) and strategy images.
    std::vector<std::array<int, 4>> tiles;
    for (int ty = fp.y0; ty < fp.y1; ty += kTile)
        for (int tx = fp.x0; tx < fp.x1; tx += kTile)
            tiles.push_back({tx, ty, std::min(tx + kTile, fp.x1), std::min(ty + kTile, fp.y1)});
    const int n_strategy = bctx && bctx->visualize
                               ? (1 + scene.integrator.max_depth) * (6 + scene.integrator.max_depth) / 2
                               : 0;
    std::vector<std::vector<double>> strategy_sums(size_t(n_strategy), film.splat_buffer());
    const Filter box(FilterType::Box, Vec2(0.5f, 0.5f));

    // Each pass continues the film's sums (each pixel adds its samples in index order,
    // whatever the passes), and a pixel's samples are traced in packets that start at
    // multiples of the packet size; so the image does not depend on the passes, as long as
    // their boundaries are multiples of kPassAlign. Without a budget or checkpoints, passes
    // are of kMaxPassSpp (the samplers compute the per-pixel parts of each dimension once per
    // pass). With a time budget or checkpoints they start at kPassAlign and double, each
    // sized from the time the previous ones took to end within the budget and about at the
    // next checkpoint; a time-budgeted render without checkpoints starts with a pass of 1 spp
    // (it always completes: an image of no samples is no answer), so the image differs from
    // the others only where its first packets' rays meet two surfaces at the same distance.
    // Distributed (opt.distribute), a pass's tiles are shared with the other processes, each
    // given the tile's sums so far and returning them continued: the same sums.
    const bool paced = opt.time_budget > 0 || opt.checkpoint;
    int pass_size = paced ? kPassAlign : kMaxPassSpp;
    double seconds_per_spp = 0;  // of the passes so far (wall)
    double last_checkpoint = 0;
    auto stats_so_far = [&] {
        RenderStats s = opt.resume ? *opt.resume : RenderStats{};
        s.spp = done;
        s.wall_seconds += elapsed();
        s.cpu_seconds += process_cpu_seconds() - cpu0;
        for (const ThreadState& t : states) {  // between passes: no thread writes them
            s.camera_paths += t.paths;
            s.rays += t.counters.rays;
            s.nonfinite += t.nonfinite;
        }
        s.camera_paths += remote.paths;
        s.rays += remote.rays;
        s.nonfinite += remote.nonfinite;
        return s;
    };
    // The end of a pass that would end at `end`: a multiple of kPassAlign after `done`.
    auto align_end = [&](int end) {
        if (end >= total_spp) return total_spp;
        const int a = end / kPassAlign * kPassAlign;
        return a > done ? a : std::min(total_spp, (done / kPassAlign + 1) * kPassAlign);
    };
    while (done < total_spp) {
        int s1 = done == 0 && opt.time_budget > 0 && !opt.checkpoint
                     ? 1
                     : align_end(std::min(total_spp, done + pass_size));
        if (paced && seconds_per_spp > 0) {
            // The pass may take at most the time left of the budget and about the checkpoint
            // interval; none fits the budget: stop here rather than start a pass to drop.
            double fit = kInfinity;
            if (opt.time_budget > 0) fit = (opt.time_budget - elapsed()) / seconds_per_spp;
            if (opt.checkpoint && opt.checkpoint_every > 0)
                fit = std::min(fit, std::max(1.0, opt.checkpoint_every / seconds_per_spp));
            const int shortest = align_end(done + 1);
            if (opt.time_budget > 0 && fit < double(shortest - done)) {
                stats.time_limited = true;
                break;
            }
            if (fit < double(s1 - done)) s1 = align_end(done + std::max(1, int(fit)));
        }
        const int s0 = done;
        const double pass_t0 = elapsed();
        std::vector<PixelSum> pass = film.sums();
        std::vector<double> aux = film.aux_sums();
        // Camera samples of tile t in this pass, for the progress bar.
        auto tile_samples = [&](const std::array<int, 4>& t) {
            return uint64_t(t[2] - t[0]) * uint64_t(t[3] - t[1]) * uint64_t(s1 - s0);
        };
        // A tile is abandoned once the budget is spent (after this run's first pass).
        auto budget_spent = [&] {
            if (out_of_time.load(std::memory_order_relaxed)) return true;
            if (opt.time_budget > 0 && s0 > first_spp && elapsed() > opt.time_budget) {
                out_of_time = true;
                return true;
            }
            return false;
        };
        // The pass's header for the workers: the sampler's key, the samples, the integrator.
        std::vector<char> header;
        if (coord) {
            ByteWriter hw(header);
            hw.put(int32_t(total_spp));
            hw.put(uint64_t(seed));
            hw.put(int32_t(s0));
            hw.put(int32_t(s1));
            hw.put(uint8_t(bidir ? (itype == "lightpath" ? kPassLightpath : kPassBdpt)
                           : radiosity ? kPassRadiosity
                                       : kPassPath));
            hw.put(uint8_t(opt.bidir_unweighted));
            hw.put(int32_t(opt.bidir_only_depth));
        }
        if (bidir) {
            std::vector<double> splat_pass = film.splat_sums();
            std::vector<std::vector<double>> strategy_pass = strategy_sums;
            // The splat reduction: each tile's splats are kept in its own list while it
            // renders, then added in tile order, so that the image depends neither on the
            // threads nor on the processes that rendered the tiles.
            auto add_splats = [&](const std::vector<SplatRecord>& tile_recs) {
                for (const SplatRecord& rec : tile_recs) {
                    if (rec.buffer == 0)
                        film.add_splat(splat_pass, rec.p, rec.xyz, *scene.filter);
                    else
                        film.add_splat(strategy_pass[size_t(rec.buffer - 1)], rec.p, rec.xyz, box);
                }
            };
            const bool lightpath = itype == "lightpath";
            if (!coord) {
                // Tiles in chunks (bounding the splat lists' memory), added in tile order.
                const size_t chunk = size_t(std::max(4, 4 * threads));
                std::vector<std::vector<SplatRecord>> recs(chunk);
                std::vector<uint64_t> rec_nonfinite(chunk);
                for (size_t c0 = 0; c0 < tiles.size() && !out_of_time; c0 += chunk) {
                    const size_t c1 = std::min(tiles.size(), c0 + chunk);
                    arena.execute([&] {
                        tbb::parallel_for(
                            tbb::blocked_range<size_t>(c0, c1, 1),
                            [&](const tbb::blocked_range<size_t>& r) {
                                for (size_t ti = r.begin(); ti < r.end(); ++ti) {
                                    auto& out = recs[ti - c0];
                                    out.clear();
                                    rec_nonfinite[ti - c0] = 0;
                                    if (out_of_time.load(std::memory_order_relaxed)) return;
                                    if (opt.time_budget > 0 && s0 > first_spp &&
                                        elapsed() > opt.time_budget) {
                                        out_of_time = true;
                                        return;
                                    }
                                    ThreadState& ts = states.local();
                                    TileSplats sink(film, rec_nonfinite[ti - c0], out,
                                                    scene.integrator.max_depth,
                                                    scene.integrator.visualize_weights);
                                    const auto& tb = tiles[ti];
                                    render_bidir_tile(scene, *bctx, lightpath, film, ts, tb, s0, s1,
                                                      pass, sink);
                                    progress.add(tile_samples(tb));
                                }
                            },
                            tbb::simple_partitioner());
                    });
                    if (out_of_time) break;
                    for (size_t ti = c0; ti < c1; ++ti) {
                        states.local().nonfinite += rec_nonfinite[ti - c0];
                        add_splats(recs[ti - c0]);
                    }
                }
            } else {
                // Distributed: a tile's splats come back with its sums (or stay here when this
                // process's threads rendered it), kept per tile until every tile before it is
                // in, then added in tile order: the same additions, in the same order, as
                // above. The window bounds the tiles whose splats are kept at once.
                const size_t nt = grid.count();
                std::vector<std::vector<SplatRecord>> recs(nt);
                std::vector<uint64_t> rec_nonfinite(nt, 0);
                uint64_t pass_splats = 0;  // counted once the pass completes
                WorkCoordinator::Phase ph;
                ph.kind = kRenderTiles;
                ph.header = header;
                ph.items = nt;
                ph.window = size_t(std::max(32, 6 * threads * (coord->workers() + 1)));
                ph.input = [&](size_t i, ByteWriter& bw) {
                    put_tile(bw, film, grid.rect(i), pass, aux);
                };
                ph.output = [&](size_t i, ByteReader& br) {
                    const std::array<int, 4> t = grid.rect(i);
                    get_tile(br, film, t, pass, aux);
                    remote.paths += br.get<uint64_t>();
                    remote.rays += br.get<uint64_t>();
                    remote.nonfinite += br.get<uint64_t>();
                    const size_t at = br.left();
                    get_splats(br, recs[i], n_strategy);
                    stats.dist_splat_bytes += at - br.left();
                    progress.add(tile_samples(t));
                };
                ph.local = [&](const std::function<std::optional<size_t>()>& claim,
                               const std::function<void(size_t)>& tile_done) {
                    run_local_share(arena, threads, claim, budget_spent, [&](size_t i) {
                        const std::array<int, 4> t = grid.rect(i);
                        TileSplats sink(film, rec_nonfinite[i], recs[i],
                                        scene.integrator.max_depth,
                                        scene.integrator.visualize_weights);
                        render_bidir_tile(scene, *bctx, lightpath, film, states.local(), t, s0,
                                          s1, pass, sink);
                        tile_done(i);
                        progress.add(tile_samples(t));
                    });
                };
                ph.reduce = [&](size_t i) {
                    const double r0 = thread_cpu_seconds();
                    remote.nonfinite += rec_nonfinite[i];
                    add_splats(recs[i]);
                    pass_splats += recs[i].size();
                    std::vector<SplatRecord>().swap(recs[i]);
                    stats.dist_splat_seconds += thread_cpu_seconds() - r0;
                };
                ph.abandon = budget_spent;
                if (!coord->run(ph)) out_of_time = true;
                if (!out_of_time) stats.dist_splats += pass_splats;
            }
            if (!out_of_time) {
                film.set_splat_sums(std::move(splat_pass));
                strategy_sums = std::move(strategy_pass);
            }
        } else {
        if (!coord) {
            arena.execute([&] {
                tbb::parallel_for(
                    tbb::blocked_range2d<int>(fp.y0, fp.y1, kTile, fp.x0, fp.x1, kTile),
                    [&](const tbb::blocked_range2d<int>& r) {
                        if (budget_spent()) return;
                        render_tile(scene, film, states.local(), r.cols().begin(),
                                    r.rows().begin(), r.cols().end(), r.rows().end(), s0, s1,
                                    pass, aux);
                        progress.add(uint64_t(r.rows().size()) * r.cols().size() * (s1 - s0));
                    });
            });
        } else {
            WorkCoordinator::Phase ph;
            ph.kind = kRenderTiles;
            ph.header = header;
            ph.items = grid.count();
            ph.input = [&](size_t i, ByteWriter& bw) { put_tile(bw, film, grid.rect(i), pass, aux); };
            ph.output = [&](size_t i, ByteReader& br) {
                const std::array<int, 4> t = grid.rect(i);
                get_tile(br, film, t, pass, aux);
                remote.paths += br.get<uint64_t>();
                remote.rays += br.get<uint64_t>();
                remote.nonfinite += br.get<uint64_t>();
                progress.add(tile_samples(t));
            };
            ph.local = [&](const std::function<std::optional<size_t>()>& claim,
                           const std::function<void(size_t)>&) {
                run_local_share(arena, threads, claim, budget_spent, [&](size_t i) {
                    const std::array<int, 4> t = grid.rect(i);
                    render_tile(scene, film, states.local(), t[0], t[1], t[2], t[3], s0, s1,
                                pass, aux);
                    progress.add(tile_samples(t));
                });
            };
            ph.abandon = budget_spent;
            if (!coord->run(ph)) out_of_time = true;
        }
        }
        if (out_of_time) {
            stats.time_limited = true;
            break;
        }
        film.set_sums(std::move(pass));
        film.set_aux_sums(std::move(aux));
        done = s1;
        if (bidir) film.set_splat_scale(1 / (double(done) * scene.filter->integral()));
        seconds_per_spp = (elapsed() - pass_t0) / double(s1 - s0);
        pass_size = std::min(pass_size * 2, kMaxPassSpp);
        const bool stopping = (opt.stop && opt.stop->load() && done < total_spp) ||
                              (opt.time_budget > 0 && elapsed() > opt.time_budget &&
                               done < total_spp);
        if (opt.checkpoint &&
            (stopping || done == total_spp || elapsed() - last_checkpoint >= opt.checkpoint_every)) {
            opt.checkpoint(stats_so_far());
            last_checkpoint = elapsed();
        }
        if (opt.stop && opt.stop->load() && done < total_spp) {
            stats.interrupted = true;
            break;
        }
        if (opt.time_budget > 0 && elapsed() > opt.time_budget && done < total_spp) {
            stats.time_limited = true;
            break;
        }
    }
    progress.finish();

    const RenderStats so_far = stats_so_far();
    stats.wall_seconds = so_far.wall_seconds;
    stats.cpu_seconds = so_far.cpu_seconds;
    stats.spp = done;
    stats.camera_paths = so_far.camera_paths;
    stats.rays = so_far.rays;
    stats.nonfinite = so_far.nonfinite;
    stats.peak_rss_bytes = peak_rss_bytes();
    // visualizestrategies / visualizeweights: one image per (s, t), named as pbrt-v4's.
    for (int depth = 0; n_strategy > 0 && done > 0 && depth <= scene.integrator.max_depth; ++depth)
        for (int s = 0; s <= depth + 2; ++s) {
            const int t = depth + 2 - s;
            if (t == 0 || (s == 1 && t == 1)) continue;
            Film f(fp);
            f.set_splat_sums(strategy_sums[size_t(s + depth * (5 + depth) / 2)]);
            f.set_splat_scale(1 / double(done));
            stats.strategy_images.push_back(
                {fmt::format("bdpt_d{:02}_s{:02}_t{:02}.exr", depth, s, t), f.rgb_image()});
        }
    return stats;
}

JobHandler render_job_handler(const Scene& scene, int threads,
                              const RadiositySolution* radiosity) {
    // A worker's state, made on its first job and kept while the sample count, seed and
    // integrator stay: a film of the scene's size whose tiles are set from each job's inputs,
    // and the samplers.
    struct Worker {
        Film film;
        std::vector<PixelSum> pass;
        std::vector<double> aux;
        std::unique_ptr<RenderThreads> rt;
        int spp = -1;
        uint64_t seed = 0;
        uint8_t method = 0;
        std::optional<BidirContext> bctx;
        int threads;
        tbb::task_arena arena;
        Worker(const Scene& s, int n)
            : film(s.film), pass(film.make_buffer()), aux(film.aux_sums()),
              threads(n > 0 ? n : int(std::thread::hardware_concurrency())), arena(threads) {}
    };
    auto wk = std::make_shared<Worker>(scene, threads);
    return [&scene, wk, radiosity](ByteReader& header, size_t count, ByteReader& inputs,
                                   ByteWriter& outputs) {
        Worker& W = *wk;
        const int total_spp = header.get<int32_t>();
        const uint64_t seed = header.get<uint64_t>();
        const int s0 = header.get<int32_t>(), s1 = header.get<int32_t>();
        const uint8_t method = header.get<uint8_t>();
        const bool unweighted = header.get<uint8_t>() != 0;
        const int only_depth = header.get<int32_t>();
        if (total_spp <= 0 || s0 < 0 || s1 <= s0 || s1 > total_spp)
            throw Error(fmt::format("distributed: a pass [{}, {}) of {} samples", s0, s1, total_spp));
        const std::string& itype = scene.integrator.type;
        const bool bidir = method == kPassBdpt || method == kPassLightpath;
        const uint8_t mine = itype == "bdpt"        ? kPassBdpt
                             : itype == "lightpath" ? kPassLightpath
                             : itype == "radiosity" ? kPassRadiosity
                                                    : kPassPath;
        if (method > kPassLightpath || (method != kPassPath && method != mine))
            throw Error(fmt::format("distributed: a pass of another integrator than \"{}\"", itype));
        if (method == kPassRadiosity && !radiosity)
            throw Error("distributed: a radiosity pass, and no radiosity solution here");
        if (!W.rt || W.spp != total_spp || W.seed != seed || W.method != method) {
            W.rt = std::make_unique<RenderThreads>(scene, W.film.params(), total_spp, seed,
                                                   method == kPassRadiosity ? radiosity : nullptr);
            W.spp = total_spp;
            W.seed = seed;
            W.method = method;
        }
        if (bidir && !W.bctx) {
            W.bctx.emplace(scene);
            W.bctx->visualize = method == kPassBdpt && (scene.integrator.visualize_strategies ||
                                                        scene.integrator.visualize_weights);
        }
        if (bidir) {
            W.bctx->unweighted = unweighted;
            W.bctx->only_depth = only_depth;
        }
        const TileGrid grid(W.film.params());
        std::vector<size_t> items(count);
        std::vector<TileCounts> counts(count);
        std::vector<std::vector<SplatRecord>> recs(bidir ? count : 0);
        std::vector<uint64_t> rec_nonfinite(bidir ? count : 0, 0);
        for (size_t j = 0; j < count; ++j) {
            const uint64_t item = inputs.get<uint64_t>();
            if (item >= grid.count()) throw Error("distributed: a tile outside the film");
            items[j] = size_t(item);
            get_tile(inputs, W.film, grid.rect(items[j]), W.pass, W.aux);
        }
        W.arena.execute([&] {
            tbb::parallel_for(
                size_t(0), count,
                [&](size_t j) {
                    const std::array<int, 4> t = grid.rect(items[j]);
                    ThreadState& ts = W.rt->states->local();
                    if (bidir) {
                        TileSplats sink(W.film, rec_nonfinite[j], recs[j],
                                        scene.integrator.max_depth,
                                        scene.integrator.visualize_weights);
                        counts[j] = render_bidir_tile(scene, *W.bctx, method == kPassLightpath,
                                                      W.film, ts, t, s0, s1, W.pass, sink);
                    } else {
                        counts[j] = render_tile(scene, W.film, ts, t[0], t[1], t[2], t[3], s0,
                                                s1, W.pass, W.aux);
                    }
                },
                tbb::simple_partitioner());
        });
        for (size_t j = 0; j < count; ++j) {
            outputs.put(uint64_t(items[j]));
            put_tile(outputs, W.film, grid.rect(items[j]), W.pass, W.aux);
            outputs.put(counts[j].paths);
            outputs.put(counts[j].rays);
            outputs.put(counts[j].nonfinite + (bidir ? rec_nonfinite[j] : 0));
            if (bidir) put_splats(outputs, recs[j]);
        }
    };
}

}  // namespace sr
