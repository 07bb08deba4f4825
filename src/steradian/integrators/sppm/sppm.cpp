#include "steradian/integrators/sppm/sppm.h"

#include <algorithm>
#include <atomic>
#include <chrono>
#include <cmath>
#include <mutex>
#include <optional>
#include <thread>
#include <vector>

#include <tbb/blocked_range.h>
#include <tbb/enumerable_thread_specific.h>
#include <tbb/global_control.h>
#include <tbb/parallel_for.h>
#include <tbb/task_arena.h>

#include "steradian/core/error.h"
#include "steradian/integrators/distributed.h"
#include "steradian/integrators/integrator.h"
#include "steradian/integrators/iterations.h"
#include "steradian/integrators/path/visible_point.h"
#include "steradian/integrators/progress.h"
#include "steradian/sampling/hash.h"
#include "steradian/sampling/padded_sobol_sampler.h"
#include "steradian/scene/scene.h"

namespace sr {

namespace {

using Clock = std::chrono::steady_clock;

/// Photons a chunk traces at most: the unit of the photon pass's parallel work and of its
/// ordered reduction. (Where the photons meet many visible points each, a chunk takes fewer,
/// so that its deposits stay within kChunkDeposits; the image does not depend on it.)
constexpr int kPhotonChunk = 1024;
/// The most deposits a chunk can make (16 bytes each).
constexpr uint64_t kChunkDeposits = uint64_t(1) << 20;

/// One pixel's state (pbrt-v4's SPPMPixel), its sums in sensor values.
struct Pixel {
    double ld[3] = {0, 0, 0};   ///< camera paths' direct light, summed over iterations
    double tau[3] = {0, 0, 0};  ///< the flux within the current radius (pbrt's tau)
    double phi[3] = {0, 0, 0};  ///< this iteration's photons' flux
    double n = 0;               ///< the photon count N of the paper
    uint32_t m = 0;             ///< this iteration's photons M
    Float radius = 0;
    VisiblePoint vp;
};

/// A photon's contribution to a pixel's flux, in sensor values.
struct Deposit {
    uint32_t pixel;
    float xyz[3];
};

/// The hash grid of the visible points (pbrt-v4's): cells about the largest radius wide over
/// the visible points' bounds, each cell's list of the pixels whose visible point's sphere
/// may reach it, in one array (counting sort, pixels in index order within a cell's bucket).
class VisibleGrid {
public:
    void build(const std::vector<Pixel>& pixels) {
        m_bounds = Bounds3{};
        Float max_r = 0;
        size_t n_vp = 0;
        for (const Pixel& px : pixels) {
            if (!px.vp.set) continue;
            const Vec3 r(px.radius, px.radius, px.radius);
            m_bounds.expand(px.vp.p - r);
            m_bounds.expand(px.vp.p + r);
            max_r = std::max(max_r, px.radius);
            ++n_vp;
        }
        m_start.assign(1, 0);
        m_items.clear();
        m_size = 0;
        if (n_vp == 0) return;
        const Vec3 diag = m_bounds.diagonal();
        const Float max_diag = std::max({diag.x, diag.y, diag.z});
        // Cells at least the largest radius wide, so a sphere spans at most 3 per axis (the
        // count capped at 2^20 per axis, which only widens the cells).
        const double base = std::min(double(max_diag) / double(max_r), double(1 << 20));
        for (int i = 0; i < 3; ++i)
            m_res[i] = std::max(1, int(base * double(diag[i]) / double(max_diag)));
        m_size = 1;
        while (m_size < n_vp) m_size <<= 1;
        std::vector<uint32_t> count(m_size + 1, 0);
        std::vector<uint32_t> buckets;
        auto each_bucket = [&](const Pixel& px, auto&& fn) {
            int lo[3], hi[3];
            const Vec3 r(px.radius, px.radius, px.radius);
            to_grid(px.vp.p - r, lo);
            to_grid(px.vp.p + r, hi);
            buckets.clear();
            for (int z = lo[2]; z <= hi[2]; ++z)
                for (int y = lo[1]; y <= hi[1]; ++y)
                    for (int x = lo[0]; x <= hi[0]; ++x) buckets.push_back(bucket(x, y, z));
            // Two cells of one sphere in the same bucket: listed once (a photon there would
            // otherwise count twice).
            std::sort(buckets.begin(), buckets.end());
            buckets.erase(std::unique(buckets.begin(), buckets.end()), buckets.end());
            for (uint32_t b : buckets) fn(b);
        };
        for (const Pixel& px : pixels)
            if (px.vp.set) each_bucket(px, [&](uint32_t b) { ++count[b + 1]; });
        for (size_t b = 0; b < m_size; ++b) count[b + 1] += count[b];
        m_start = count;
        m_items.resize(count[m_size]);
        for (size_t i = 0; i < pixels.size(); ++i)
            if (pixels[i].vp.set)
                each_bucket(pixels[i], [&](uint32_t b) { m_items[count[b]++] = uint32_t(i); });
    }

    /// The longest list of one bucket: the most visible points a photon can meet at once.
    size_t max_list() const {
        size_t m = 0;
        for (size_t b = 0; b < m_size; ++b) m = std::max<size_t>(m, m_start[b + 1] - m_start[b]);
        return m;
    }

    /// The pixels listed in the cell of p (empty outside the grid).
    std::pair<const uint32_t*, const uint32_t*> near(Point3 p) const {
        int c[3];
        if (m_size == 0 || !to_grid(p, c)) return {nullptr, nullptr};
        const uint32_t b = bucket(c[0], c[1], c[2]);
        return {m_items.data() + m_start[b], m_items.data() + m_start[b + 1]};
    }

private:
    /// The cell of p, clamped to the grid; whether p was inside.
    bool to_grid(Point3 p, int c[3]) const {
        bool inside = true;
        const Vec3 d = m_bounds.diagonal();
        const Float o[3] = {p.x - m_bounds.lo.x, p.y - m_bounds.lo.y, p.z - m_bounds.lo.z};
        const Float e[3] = {d.x, d.y, d.z};
        for (int i = 0; i < 3; ++i) {
            const double t = e[i] > 0 ? double(o[i]) / double(e[i]) : 0;
            const double v = std::floor(double(m_res[i]) * t);
            inside &= v >= 0 && v < m_res[i];
            c[i] = int(std::clamp(v, 0.0, double(m_res[i] - 1)));
        }
        return inside;
    }
    uint32_t bucket(int x, int y, int z) const {
        const uint64_t h = hash_combine(hash_combine(mix_bits(uint64_t(uint32_t(x))), uint32_t(y)),
                                        uint32_t(z));
        return uint32_t(h & (m_size - 1));
    }

    Bounds3 m_bounds;
    int m_res[3] = {1, 1, 1};
    size_t m_size = 0;  ///< buckets (a power of two)
    std::vector<uint32_t> m_start, m_items;
};

struct CameraThread {
    std::unique_ptr<Sampler> sampler;
    PathCounters counters;
    uint64_t nonfinite = 0;
};

struct PhotonThread {
    std::unique_ptr<Sampler> sampler;
    PathCounters counters;
};

/// Rotates the iterations' wavelengths (pass_wavelength_sample) apart from the other
/// iterative integrators'.
constexpr uint64_t kWavelengthSalt = 0x5350504d5f4c414dULL;

/// Where a photon may deposit: a surface it reaches after at least one bounce, the direction
/// it comes from, its throughput, and whether its secondary wavelengths were terminated
/// (its wavelengths are otherwise the iteration's). The visible points' grid turns it into
/// deposits (gather_photon): distributed, workers trace photons to these records and the
/// coordinator, which holds the visible points, gathers them.
struct PhotonHit {
    Point3 p;
    Vec3 wi;
    SampledSpectrum beta;
    bool terminated = false;
};
/// Bytes of a PhotonHit in a message.
constexpr size_t kPhotonHitBytes = 12 + 12 + 4 * kSpectrumSamples + 1;

/// Photon tracing, the same on every process: the lights chosen by power (pbrt-v4's
/// shootLightSampler), the materials, the depth.
struct PhotonTracer {
    explicit PhotonTracer(const Scene& s)
        : scene(s), mctx(s.material_context()), max_depth(s.integrator.max_depth) {
        shoot.build(s.lights, LightSamplerKind::Power);
    }
    const Scene& scene;
    LightSampler shoot;
    MaterialContext mctx;
    int max_depth;

    /// Photons [i0, i1) of iteration `iter` (wavelengths `pass_lambda`): `hit(p, wi, beta,
    /// lambda)` for every surface a photon reaches after at least one bounce, in photon order.
    template <class OnHit>
    void trace(int iter, int64_t i0, int64_t i1, const SampledWavelengths& pass_lambda,
               Sampler& sampler, PathCounters& counters, OnHit&& on_hit) const {
        for (int64_t i = i0; i < i1; ++i) {
            sampler.start_pixel_sample(Vec2i(iter, -1), int(i));
            const Float ul = sampler.get_pixel_1d();
            const Point2 u_pos = sampler.get_pixel_2d();
            const Point2 u_dir = sampler.get_2d();
            Float pmf = 0;
            const int li = shoot.sample(ul, pmf);
            if (li < 0 || !(pmf > 0)) continue;
            SampledWavelengths lambda = pass_lambda;
            auto les = sample_le(scene.lights[size_t(li)], u_pos, u_dir, lambda);
            if (!les || !(les->pdf_pos > 0) || !(les->pdf_dir > 0) || les->L.is_zero()) continue;
            const bool on_surface = les->n.x != 0 || les->n.y != 0 || les->n.z != 0;
            const Float cos = on_surface ? absdot(les->n, les->ray.d) : 1;
            SampledSpectrum beta = les->L * (cos / (pmf * les->pdf_pos * les->pdf_dir));
            if (beta.is_zero()) continue;
            Ray ray = les->ray;
            SurfaceHit hit;
            int crossings = 0;
            for (int depth = 0; depth < max_depth;) {
                ++counters.rays;
                if (!scene.intersect(ray, hit)) break;
                std::optional<Bsdf> bsdf =
                    hit.material >= 0
                        ? make_bsdf(scene.materials[size_t(hit.material)], mctx, hit, lambda)
                        : std::nullopt;
                if (!bsdf) {
                    // An interface: straight through, not a bounce.
                    if (++crossings > 256) break;
                    ray = spawn_ray(hit, ray.d);
                    continue;
                }
                // The photon's flux at the visible points whose sphere holds it (the first
                // hit is direct light, which the camera paths sample).
                if (depth > 0) on_hit(hit.p, -ray.d, beta, lambda);
                ++depth;
                Float uc = 0;
                if (bsdf->uses_uc())
                    uc = sampler.get_1d();
                else
                    sampler.skip_1d();
                const Point2 u = sampler.get_2d();
                const Float u_rr = sampler.get_1d();
                if (depth >= max_depth) break;
                auto bs = bsdf->sample(hit.wo, uc, u, TransportMode::Importance);
                if (!bs) break;
                const SampledSpectrum bnew =
                    beta * bs->f * (absdot(bs->wi, bsdf->frame().n) / bs->pdf_sa);
                // Russian roulette by the throughput's change (pbrt-v4's photons).
                const Float q = std::max(Float(0), 1 - bnew.max_value() / beta.max_value());
                if (u_rr < q) break;
                beta = bnew / (1 - q);
                if (beta.is_zero() || beta.has_nonfinite()) break;
                ray = spawn_ray(hit, bs->wi);
            }
        }
    }
};

/// The header of a distributed photon phase: the iteration, its wavelengths, the photons.
struct PhotonJob {
    int32_t iter = 0;
    int64_t photons = 0, chunk_photons = 0;
    uint64_t seed = 0;
    SampledWavelengths lambda;
};

}  // namespace

RenderStats render_sppm(const Scene& scene, Film& film, const RenderOptions& opt) {
    const char* kName = "Integrator \"sppm\"";
    if (!scene.media.empty() || scene.integrator.volumetric)
        throw Error(fmt::format("{}: participating media are not supported (pbrt-v4's sppm ignores "
                                "them; use \"volpath\")",
                                kName));
    if (film.has_aux())
        throw Error(fmt::format("{}: only the \"rgb\" film is supported", kName));
    if (opt.checkpoint || opt.resume)
        throw Error(fmt::format("{}: checkpoints are not supported", kName));
    if (!scene.camera) throw Error(fmt::format("{}: the scene has no camera", kName));
    for (const Light& l : scene.lights)
        if (!light_can_emit(l))
            throw Error(fmt::format("{}: an \"infinite\" light with a \"portal\" cannot emit "
                                    "photons yet",
                                    kName));

    const SppmParams& sp = scene.integrator.sppm;
    const FilmParams& fp = film.params();
    const int w = fp.width(), h = fp.height();
    const size_t n_pixels = size_t(w) * size_t(h);
    if (n_pixels > size_t(UINT32_MAX)) throw Error(fmt::format("{}: too many pixels", kName));
    const int iterations = render_samples_per_pixel(scene, opt);
    const int64_t photons = sp.photons_per_iteration > 0 ? sp.photons_per_iteration
                                                         : int64_t(n_pixels);
    if (photons > INT32_MAX)
        throw Error(fmt::format("{}: photonsperiteration is at most {}", kName, INT32_MAX));
    const int max_depth = scene.integrator.max_depth;
    const uint64_t cam_seed = scene.sampler.seed + opt.seed;
    const uint64_t photon_seed = uint64_t(int64_t(sp.seed)) + opt.seed;

    int threads = opt.threads > 0 ? opt.threads : int(std::thread::hardware_concurrency());
    tbb::global_control gc(tbb::global_control::max_allowed_parallelism, size_t(threads));
    tbb::task_arena arena(threads);

    // Sensor values without the film's per-sample clamp (pbrt-v4's sppm converts with
    // ToOutputRGB, which does not clamp to maxcomponentvalue).
    FilmParams conv_params = fp;
    conv_params.max_component = kInfinity;
    const Film conv(conv_params);

    std::unique_ptr<Sampler> cam_proto =
        scene.sampler.type == "stratified"
            ? make_stratified_sampler(scene.sampler.x_samples, scene.sampler.y_samples,
                                      scene.sampler.jitter, cam_seed)
            : make_sampler(scene.sampler.type, iterations, fp.resolution, cam_seed);
    // Photon i of iteration k: sample i of the pseudo-pixel (k, -1) (camera pixels have
    // y >= 0) of an Owen-scrambled Sobol sampler with photons samples per pixel.
    const PaddedSobolSampler photon_proto(int(photons), photon_seed);
    tbb::enumerable_thread_specific<CameraThread> cam_threads([&] {
        CameraThread t;
        t.sampler = cam_proto->clone();
        return t;
    });
    tbb::enumerable_thread_specific<PhotonThread> photon_threads([&] {
        PhotonThread t;
        t.sampler = photon_proto.clone();
        return t;
    });

    const PhotonTracer tracer(scene);
    WorkCoordinator* const coord =
        opt.distribute && opt.distribute->workers() > 0 ? opt.distribute : nullptr;
    uint64_t remote_rays = 0;  // the other processes' (distributed)

    std::vector<Pixel> pixels(n_pixels);
    for (Pixel& px : pixels) px.radius = sp.radius;
    VisibleGrid grid;

    RenderStats stats;
    const auto t0 = Clock::now();
    const double cpu0 = process_cpu_seconds();
    auto elapsed = [&] { return std::chrono::duration<double>(Clock::now() - t0).count(); };
    Progress progress(opt.progress, uint64_t(iterations) * (uint64_t(n_pixels) + uint64_t(photons)));
    uint64_t nonfinite_photons = 0;
    const size_t slab = size_t(std::max(4, 4 * threads));
    std::vector<std::vector<Deposit>> deposits(slab);
    std::vector<uint64_t> chunk_nonfinite(slab);

    int done = 0;
    while (done < iterations) {
        const double iter_t0 = elapsed();
        const int iter = done;
        const SampledWavelengths pass_lambda =
            film.sample_wavelengths(pass_wavelength_sample(uint64_t(iter), cam_seed, kWavelengthSalt));

        // ---- camera pass: each pixel's path to its visible point --------------------------
        auto camera_pass = [&] {
            arena.execute([&] {
            tbb::parallel_for(tbb::blocked_range<int>(0, h, 1), [&](const tbb::blocked_range<int>& r) {
                CameraThread& ct = cam_threads.local();
                Sampler& sampler = *ct.sampler;
                for (int yy = r.begin(); yy < r.end(); ++yy) {
                    for (int xx = 0; xx < w; ++xx) {
                        const Vec2i pixel(fp.x0 + xx, fp.y0 + yy);
                        Pixel& px = pixels[size_t(yy) * size_t(w) + size_t(xx)];
                        sampler.start_pixel_sample(pixel, iter);
                        // The filter's offset by importance sampling; its weight is not
                        // applied (pbrt-v4's sppm averages the samples of a pixel).
                        const FilterSample fs = scene.filter->sample(sampler.get_pixel_2d());
                        const Point2 u_lens = sampler.get_2d();
                        const Point2 p_film(Float(pixel.x) + 0.5f + fs.offset.x,
                                            Float(pixel.y) + 0.5f + fs.offset.y);
                        const Ray ray = scene.camera->generate_ray(
                            p_film,
                            scene.camera->uses_lens_sample() ? u_lens : Point2(0.5f, 0.5f));
                        SampledWavelengths lambda = pass_lambda;
                        const SampledSpectrum L = path_li_visible_point(
                            scene, ray, lambda, sampler, ct.counters, px.vp);
                        std::array<double, 3> xyz{0, 0, 0};
                        bool finite = !L.has_nonfinite();
                        if (finite) {
                            xyz = conv.to_sensor(L, lambda);
                            finite = finite3(xyz);
                        }
                        if (!finite) {
                            ++ct.nonfinite;
                            xyz = {0, 0, 0};
                        }
                        for (int c = 0; c < 3; ++c) px.ld[c] += xyz[c];
                        if (px.vp.set && px.vp.beta.is_zero()) px.vp.set = false;
                    }
                }
                progress.add(uint64_t(r.size()) * uint64_t(w));
            });
            });
        };
        // Distributed, the photons are traced before the grid exists: chunks of 1,024 to
        // 8,192 photons, about 16 per thread of all processes (a worker's job is then
        // milliseconds of work at least: a busy coordinator answers a request late).
        int64_t chunk_photons =
            coord ? std::clamp<int64_t>(
                        photons / (16 * int64_t(threads) * (coord->workers() + 1)),
                        kPhotonChunk, 8 * kPhotonChunk)
                  : kPhotonChunk;
        if (!coord) {
            // ---- the visible points' grid ----------------------------------------------------
            camera_pass();
            grid.build(pixels);
            // A photon deposits at most max_list() times at each of at most max_depth
            // surfaces: chunks of that many photons keep their deposit lists within
            // kChunkDeposits.
            const uint64_t per_photon = uint64_t(std::max(1, max_depth)) *
                                        uint64_t(std::max<size_t>(1, grid.max_list()));
            chunk_photons = int64_t(
                std::clamp<uint64_t>(kChunkDeposits / per_photon, 1, uint64_t(kPhotonChunk)));
        }
        const size_t n_chunks = size_t((photons + chunk_photons - 1) / chunk_photons);

        // ---- photon pass ---------------------------------------------------------------------
        // A photon's deposits: the visible points whose sphere holds the surface it reached.
        auto gather = [&](Point3 p, Vec3 wi, const SampledSpectrum& beta,
                          const SampledWavelengths& lambda, std::vector<Deposit>& out,
                          uint64_t& nonfinite) {
            auto [b, e] = grid.near(p);
            for (; b != e; ++b) {
                const Pixel& px = pixels[*b];
                if (length_squared(px.vp.p - p) > sqr(px.radius)) continue;
                const SampledSpectrum phi = px.vp.beta * beta * px.vp.bsdf->f(px.vp.wo, wi);
                if (phi.is_zero()) continue;
                SampledWavelengths pl = lambda;
                if (px.vp.secondary_terminated) pl.terminate_secondary();
                std::array<double, 3> xyz{0, 0, 0};
                bool finite = !phi.has_nonfinite();
                if (finite) {
                    xyz = conv.to_sensor(phi, pl);
                    finite = finite3(xyz);
                }
                if (!finite) {
                    ++nonfinite;
                    continue;
                }
                out.push_back({*b, {float(xyz[0]), float(xyz[1]), float(xyz[2])}});
            }
        };
        auto trace_chunk = [&](size_t chunk, std::vector<Deposit>& out, uint64_t& nonfinite) {
            PhotonThread& pt = photon_threads.local();
            const int64_t i0 = int64_t(chunk) * chunk_photons;
            const int64_t i1 = std::min<int64_t>(photons, i0 + chunk_photons);
            tracer.trace(iter, i0, i1, pass_lambda, *pt.sampler, pt.counters,
                         [&](Point3 p, Vec3 wi, const SampledSpectrum& beta,
                             const SampledWavelengths& lambda) {
                             gather(p, wi, beta, lambda, out, nonfinite);
                         });
        };
        // Distributed: the photon chunks are the items. A worker traces a chunk's photons to
        // their PhotonHit records, which come back to be gathered here; this process's
        // threads do the camera pass and build the grid first (while the workers trace), then
        // trace and gather chunks themselves. The chunks' deposits are then added in chunk
        // order below, exactly as one process adds them.
        std::vector<std::vector<PhotonHit>> chunk_hits;
        std::vector<std::vector<Deposit>> chunk_deposits;
        std::vector<uint8_t> remote_chunk;
        std::vector<uint64_t> chunk_bad;
        std::vector<size_t> arrived;  // workers' chunks not yet gathered
        std::mutex arrived_mutex;
        // A worker's chunk: its photons' hits gathered here, in photon order (once).
        auto gather_remote = [&](size_t c) {
            if (!remote_chunk[c]) return;
            SampledWavelengths terminated = pass_lambda;
            terminated.terminate_secondary();
            for (const PhotonHit& hh : chunk_hits[c])
                gather(hh.p, hh.wi, hh.beta, hh.terminated ? terminated : pass_lambda,
                       chunk_deposits[c], chunk_bad[c]);
            std::vector<PhotonHit>().swap(chunk_hits[c]);
            remote_chunk[c] = 2;  // gathered
        };
        if (coord) {
            chunk_hits.resize(n_chunks);
            chunk_deposits.resize(n_chunks);
            remote_chunk.assign(n_chunks, 0);
            chunk_bad.assign(n_chunks, 0);
            WorkCoordinator::Phase ph;
            ph.kind = kSppmItems;
            PhotonJob job;
            job.iter = iter;
            job.photons = photons;
            job.chunk_photons = chunk_photons;
            job.seed = photon_seed;
            job.lambda = pass_lambda;
            ByteWriter(ph.header).put(job);
            ph.items = n_chunks;
            ph.input = [](size_t, ByteWriter&) {};
            ph.output = [&](size_t c, ByteReader& br) {
                remote_rays += br.get<uint64_t>();
                const size_t at = br.left();
                const uint64_t n = br.get<uint64_t>();
                if (n > br.left() / kPhotonHitBytes) throw Error("distributed: a truncated message");
                std::vector<PhotonHit>& hits = chunk_hits[c];
                hits.resize(size_t(n));
                for (PhotonHit& hh : hits) {
                    for (int k = 0; k < 3; ++k) hh.p[k] = br.get<Float>();
                    for (int k = 0; k < 3; ++k) hh.wi[k] = br.get<Float>();
                    for (int k = 0; k < kSpectrumSamples; ++k) hh.beta[k] = br.get<Float>();
                    hh.terminated = br.get<uint8_t>() != 0;
                }
                stats.dist_splat_bytes += at - br.left();
                remote_chunk[c] = 1;
                {
                    const std::lock_guard<std::mutex> lock(arrived_mutex);
                    arrived.push_back(c);
                }
                const int64_t i0 = int64_t(c) * chunk_photons;
                progress.add(uint64_t(std::min<int64_t>(photons, i0 + chunk_photons) - i0));
            };
            ph.local = [&](const std::function<std::optional<size_t>()>& claim,
                           const std::function<void(size_t)>&) {
                camera_pass();
                grid.build(pixels);
                // The threads gather the workers' chunks that have come in before they trace
                // a chunk of their own, so that few are left to gather when the phase ends
                // (the workers idle then).
                auto next_arrived = [&]() -> std::optional<size_t> {
                    const std::lock_guard<std::mutex> lock(arrived_mutex);
                    if (arrived.empty()) return std::nullopt;
                    const size_t c = arrived.back();
                    arrived.pop_back();
                    return c;
                };
                arena.execute([&] {
                    tbb::parallel_for(
                        0, threads,
                        [&](int) {
                            for (;;) {
                                if (const std::optional<size_t> c = next_arrived()) {
                                    gather_remote(*c);
                                    continue;
                                }
                                const std::optional<size_t> c = claim();
                                if (!c) return;
                                trace_chunk(*c, chunk_deposits[*c], chunk_bad[*c]);
                                const int64_t i0 = int64_t(*c) * chunk_photons;
                                progress.add(uint64_t(
                                    std::min<int64_t>(photons, i0 + chunk_photons) - i0));
                            }
                        },
                        tbb::simple_partitioner());
                });
            };
            coord->run(ph);
        }
        const double reduce_cpu0 = coord ? process_cpu_seconds() : 0;
        for (size_t c0 = 0; c0 < n_chunks; c0 += slab) {
            const size_t c1 = std::min(n_chunks, c0 + slab);
            arena.execute([&] {
                tbb::parallel_for(
                    tbb::blocked_range<size_t>(c0, c1, 1),
                    [&](const tbb::blocked_range<size_t>& r) {
                        for (size_t c = r.begin(); c < r.end(); ++c) {
                            if (coord) {
                                // Distributed: the workers' chunks not gathered yet are now
                                // (this process's chunks are gathered already).
                                if (remote_chunk[c] == 1) gather_remote(c);
                                std::vector<Deposit>& out = chunk_deposits[c];
                                deposits[c - c0].swap(out);
                                chunk_nonfinite[c - c0] = chunk_bad[c];
                                std::vector<Deposit>().swap(out);
                                continue;
                            }
                            deposits[c - c0].clear();
                            chunk_nonfinite[c - c0] = 0;
                            trace_chunk(c, deposits[c - c0], chunk_nonfinite[c - c0]);
                            const int64_t i0 = int64_t(c) * chunk_photons;
                            progress.add(
                                uint64_t(std::min<int64_t>(photons, i0 + chunk_photons) - i0));
                        }
                    },
                    tbb::simple_partitioner());
            });
            // The ordered reduction: chunk by chunk, each chunk's deposits in photon order.
            for (size_t c = c0; c < c1; ++c) {
                nonfinite_photons += chunk_nonfinite[c - c0];
                if (coord && remote_chunk[c] != 0) stats.dist_splats += deposits[c - c0].size();
                for (const Deposit& d : deposits[c - c0]) {
                    Pixel& px = pixels[d.pixel];
                    for (int k = 0; k < 3; ++k) px.phi[k] += double(d.xyz[k]);
                    ++px.m;
                }
            }
        }

        if (coord) stats.dist_splat_seconds += process_cpu_seconds() - reduce_cpu0;

        // ---- radius and flux update (Hachisuka and Jensen 2009, eqs. 6-7; alpha = 2/3) ----
        arena.execute([&] {
            tbb::parallel_for(size_t(0), n_pixels, [&](size_t i) {
                Pixel& px = pixels[i];
                if (px.m > 0) {
                    constexpr double kAlpha = 2.0 / 3.0;
                    const double n_new = px.n + kAlpha * double(px.m);
                    const double r = double(px.radius);
                    const double r_new = r * std::sqrt(n_new / (px.n + double(px.m)));
                    const double shrink = (r_new * r_new) / (r * r);
                    for (int k = 0; k < 3; ++k) {
                        px.tau[k] = (px.tau[k] + px.phi[k]) * shrink;
                        px.phi[k] = 0;
                    }
                    px.n = n_new;
                    px.radius = Float(r_new);
                    px.m = 0;
                }
                px.vp.set = false;
                px.vp.bsdf.reset();
            });
        });
        ++done;

        if (stop_before_next_iteration(opt, done, iterations, elapsed(), elapsed() - iter_t0,
                                       stats))
            break;
    }
    progress.finish();

    // The image: Ld / iterations + tau / (photons traced * pi r^2), per pixel.
    const double np = double(done) * double(photons);
    std::vector<PixelSum> sums(n_pixels);
    uint64_t nonfinite_pixels = 0;
    for (size_t i = 0; i < n_pixels; ++i) {
        const Pixel& px = pixels[i];
        const double area = kPi * double(px.radius) * double(px.radius);
        double v[3];
        for (int k = 0; k < 3; ++k) v[k] = px.ld[k] / double(done) + px.tau[k] / (np * area);
        if (!std::isfinite(v[0]) || !std::isfinite(v[1]) || !std::isfinite(v[2])) {
            ++nonfinite_pixels;
            v[0] = v[1] = v[2] = 0;
        }
        for (int k = 0; k < 3; ++k) sums[i].xyz[k] = v[k];
        sums[i].weight = 1;
    }
    film.set_sums(std::move(sums));

    stats.spp = done;
    stats.wall_seconds = elapsed();
    stats.cpu_seconds = process_cpu_seconds() - cpu0;
    stats.camera_paths = uint64_t(done) * uint64_t(n_pixels);
    stats.nonfinite = nonfinite_photons + nonfinite_pixels;
    for (const CameraThread& t : cam_threads) {
        stats.rays += t.counters.rays;
        stats.nonfinite += t.nonfinite;
    }
    for (const PhotonThread& t : photon_threads) stats.rays += t.counters.rays;
    stats.rays += remote_rays;
    stats.peak_rss_bytes = peak_rss_bytes();
    return stats;
}

}  // namespace sr

namespace sr {

JobHandler sppm_job_handler(const Scene& scene, int threads) {
    // A worker's state: the photon tracer, and per thread a photon sampler of the photon count
    // and seed the jobs carry.
    struct Worker {
        PhotonTracer tracer;
        int threads;
        tbb::task_arena arena;
        int64_t photons = -1;
        uint64_t seed = 0;
        std::unique_ptr<PaddedSobolSampler> proto;
        std::unique_ptr<tbb::enumerable_thread_specific<PhotonThread>> states;
        Worker(const Scene& s, int n)
            : tracer(s), threads(n > 0 ? n : int(std::thread::hardware_concurrency())),
              arena(threads) {}
    };
    auto wk = std::make_shared<Worker>(scene, threads);
    return [&scene, wk](ByteReader& header, size_t count, ByteReader& inputs,
                        ByteWriter& outputs) {
        Worker& W = *wk;
        if (scene.integrator.type != "sppm")
            throw Error("distributed: photon work for a scene of another integrator");
        const PhotonJob job = header.get<PhotonJob>();
        if (job.photons < 1 || job.photons > INT32_MAX || job.chunk_photons < 1 || job.iter < 0)
            throw Error("distributed: a malformed photon job");
        if (!W.proto || W.photons != job.photons || W.seed != job.seed) {
            W.proto = std::make_unique<PaddedSobolSampler>(int(job.photons), job.seed);
            W.photons = job.photons;
            W.seed = job.seed;
            W.states = std::make_unique<tbb::enumerable_thread_specific<PhotonThread>>([&W] {
                PhotonThread t;
                t.sampler = W.proto->clone();
                return t;
            });
        }
        const size_t n_chunks = size_t((job.photons + job.chunk_photons - 1) / job.chunk_photons);
        std::vector<uint64_t> items(count), rays(count, 0);
        for (size_t j = 0; j < count; ++j) {
            items[j] = inputs.get<uint64_t>();
            if (items[j] >= n_chunks) throw Error("distributed: a photon chunk of none");
        }
        std::vector<std::vector<PhotonHit>> hits(count);
        W.arena.execute([&] {
            tbb::parallel_for(
                size_t(0), count,
                [&](size_t j) {
                    PhotonThread& pt = W.states->local();
                    const uint64_t before = pt.counters.rays;
                    const int64_t i0 = int64_t(items[j]) * job.chunk_photons;
                    const int64_t i1 = std::min<int64_t>(job.photons, i0 + job.chunk_photons);
                    W.tracer.trace(job.iter, i0, i1, job.lambda, *pt.sampler, pt.counters,
                                   [&](Point3 p, Vec3 wi, const SampledSpectrum& beta,
                                       const SampledWavelengths& lambda) {
                                       hits[j].push_back(
                                           {p, wi, beta, lambda.secondary_terminated()});
                                   });
                    rays[j] = pt.counters.rays - before;
                },
                tbb::simple_partitioner());
        });
        for (size_t j = 0; j < count; ++j) {
            outputs.put(items[j]);
            outputs.put(rays[j]);
            outputs.put(uint64_t(hits[j].size()));
            for (const PhotonHit& hh : hits[j]) {
                for (int k = 0; k < 3; ++k) outputs.put(hh.p[k]);
                for (int k = 0; k < 3; ++k) outputs.put(hh.wi[k]);
                for (int k = 0; k < kSpectrumSamples; ++k) outputs.put(hh.beta[k]);
                outputs.put(uint8_t(hh.terminated));
            }
        }
    };
}

}  // namespace sr
