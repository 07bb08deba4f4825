// Micro-benchmarks of the per-vertex operations: ray casts (closest hit and shadow) in the
// Cornell box, BSDF sample/eval, light sampling, spectrum evaluation and the film's sensor
// response. Run: build/release/steradian_bench --benchmark_filter=...
#include <benchmark/benchmark.h>

#include "steradian/bsdf/bsdf.h"
#include "steradian/film/film.h"
#include "steradian/sampling/rng.h"
#include "steradian/sampling/warp.h"
#include "steradian/scene/build.h"
#include "steradian/scene/pbrt/parser.h"

namespace sr {
namespace {

const Scene& cornell() {
    static Scene s = [] {
        set_warnings_quiet(true);
        return build_scene(parse_pbrt_file(std::string(STERADIAN_SOURCE_DIR) + "/scenes/cornell-box.pbrt"));
    }();
    return s;
}

/// Random rays from inside the box in uniformly distributed directions.
std::vector<Ray> box_rays(size_t n) {
    Pcg32 rng(1, 2);
    std::vector<Ray> rays(n);
    for (auto& r : rays) {
        Point3 o(50 + 450 * rng.next_float(), 50 + 450 * rng.next_float(), 50 + 450 * rng.next_float());
        r = Ray{o, sample_uniform_sphere(Point2(rng.next_float(), rng.next_float())), kInfinity};
    }
    return rays;
}

void BM_RayCastClosestHit(benchmark::State& state) {
    const Scene& s = cornell();
    auto rays = box_rays(4096);
    size_t i = 0;
    for (auto _ : state) {
        SurfaceHit h;
        benchmark::DoNotOptimize(s.intersect(rays[i++ & 4095], h));
    }
    state.SetItemsProcessed(state.iterations());
}
BENCHMARK(BM_RayCastClosestHit);

void BM_RayCastShadow(benchmark::State& state) {
    const Scene& s = cornell();
    auto rays = box_rays(4096);
    for (auto& r : rays) r.t_max = 300;
    size_t i = 0;
    for (auto _ : state) benchmark::DoNotOptimize(s.occluded(rays[i++ & 4095]));
    state.SetItemsProcessed(state.iterations());
}
BENCHMARK(BM_RayCastShadow);

constexpr int kPacket = Scene::kRayPacket;

/// The camera rays of kPacket samples of a random pixel, spread as the gaussian filter's
/// 1.5-pixel radius spreads them.
void pixel_camera_rays(const Scene& s, Pcg32& rng, Ray* rays) {
    Float x = 512 * rng.next_float(), y = 512 * rng.next_float();
    for (int k = 0; k < kPacket; ++k)
        rays[k] = s.camera->generate_ray(
            Point2(x + 3 * rng.next_float() - 1.5f, y + 3 * rng.next_float() - 1.5f),
            Point2(0.5f, 0.5f));
}

/// The first hits of a random pixel's kPacket camera rays, if they all hit.
bool pixel_first_hits(const Scene& s, Pcg32& rng, SurfaceHit* hits) {
    Ray rays[kPacket];
    pixel_camera_rays(s, rng, rays);
    return s.intersect_packet(rays, (1u << kPacket) - 1, hits) == (1u << kPacket) - 1;
}

/// A cosine-distributed diffuse bounce from h.
Ray diffuse_bounce(const SurfaceHit& h, Pcg32& rng) {
    Vec3 d = Frame::from_z(h.ns).to_world(
        sample_cosine_hemisphere(Point2(rng.next_float(), rng.next_float())));
    return spawn_ray(h, d);
}

/// Times packets of kPacket rays (512 of them, in turn): `packet` for one packet at a time
/// when `as_packet`, `single` for each ray of the packet otherwise.
template <typename Single, typename Packet>
void time_packets(benchmark::State& state, bool as_packet, const std::vector<Ray>& rays,
                  Single single, Packet packet) {
    size_t i = 0;
    for (auto _ : state) {
        const Ray* r = &rays[kPacket * (i++ & 511)];
        if (as_packet) {
            packet(r);
        } else {
            for (int k = 0; k < kPacket; ++k) single(r[k], k);
        }
    }
    state.SetItemsProcessed(kPacket * state.iterations());
}

/// time_packets of closest hits, as packets if the benchmark's first argument is not 0.
void time_closest_hits(benchmark::State& state, const Scene& s, const std::vector<Ray>& rays) {
    SurfaceHit h[kPacket];
    time_packets(
        state, state.range(0) != 0, rays,
        [&](const Ray& r, int k) { benchmark::DoNotOptimize(s.intersect(r, h[k])); },
        [&](const Ray* r) {
            benchmark::DoNotOptimize(s.intersect_packet(r, (1u << kPacket) - 1, h));
        });
}

// A pixel's camera rays traced one by one (arg 0) or as one packet (arg 1, what the
// renderer does).
void BM_CameraRayPacket(benchmark::State& state) {
    const Scene& s = cornell();
    Pcg32 rng(1, 2);
    std::vector<Ray> rays(kPacket * 512);
    for (int p = 0; p < 512; ++p) pixel_camera_rays(s, rng, &rays[kPacket * p]);
    time_closest_hits(state, s, rays);
}
BENCHMARK(BM_CameraRayPacket)->Arg(0)->Arg(1);

// The first bounce of a pixel's paths: rays from their (nearby) first hits in cosine-
// distributed directions, one by one (arg 0) or as one packet (arg 1).
void BM_FirstBouncePacket(benchmark::State& state) {
    const Scene& s = cornell();
    Pcg32 rng(1, 2);
    std::vector<Ray> rays;
    SurfaceHit h[kPacket];
    while (rays.size() < kPacket * 512) {
        if (!pixel_first_hits(s, rng, h)) continue;
        for (int k = 0; k < kPacket; ++k) rays.push_back(diffuse_bounce(h[k], rng));
    }
    time_closest_hits(state, s, rays);
}
BENCHMARK(BM_FirstBouncePacket)->Arg(0)->Arg(1);

// Shadow rays to the light: first arg 0 = from a pixel's first hits (the renderer's first
// vertices), 1 = from the hits of their diffuse bounces (spread over the box); second arg:
// one by one (0) or as one packet (1).
void BM_ShadowPacket(benchmark::State& state) {
    const Scene& s = cornell();
    Pcg32 rng(1, 2);
    auto lambda = SampledWavelengths::sample_visible(0.5f);
    std::vector<Ray> rays;
    SurfaceHit h[kPacket];
    while (rays.size() < kPacket * 512) {
        if (!pixel_first_hits(s, rng, h)) continue;
        bool all = true;
        for (int k = 0; k < kPacket && all && state.range(0) == 1; ++k)
            all = s.intersect(diffuse_bounce(h[k], rng), h[k]);
        if (!all) continue;
        for (int k = 0; k < kPacket; ++k) {
            Float pmf;
            int li = s.light_sampler.sample(rng.next_float(), pmf);
            LightSampleContext ctx{h[k].p, h[k].p_error, h[k].ng};
            auto ls = sample_li(s.lights[li], ctx, Point2(rng.next_float(), rng.next_float()), lambda);
            rays.push_back(ls ? spawn_ray_between(h[k], ls->p_light, ls->p_error, ls->n_light)
                              : spawn_ray(h[k], h[k].ng));
        }
    }
    time_packets(
        state, state.range(1) != 0, rays,
        [&](const Ray& r, int) { benchmark::DoNotOptimize(s.occluded(r)); },
        [&](const Ray* r) { benchmark::DoNotOptimize(s.occluded_packet(r, (1u << kPacket) - 1)); });
}
BENCHMARK(BM_ShadowPacket)->Args({0, 0})->Args({0, 1})->Args({1, 0})->Args({1, 1});

void BM_LambertSample(benchmark::State& state) {
    Pcg32 rng;
    LambertLobe l{SampledSpectrum(0.5f)};
    Bsdf b(Frame::from_z(normalize(Vec3(0.1f, 0.2f, 1))), Vec3(0, 0, 1), l);
    Vec3 wo = normalize(Vec3(0.3f, -0.2f, 0.9f));
    for (auto _ : state) {
        auto s = b.sample(wo, rng.next_float(), Point2(rng.next_float(), rng.next_float()));
        benchmark::DoNotOptimize(s);
    }
    state.SetItemsProcessed(state.iterations());
}
BENCHMARK(BM_LambertSample);

void BM_LambertEval(benchmark::State& state) {
    Pcg32 rng;
    LambertLobe l{SampledSpectrum(0.5f)};
    Bsdf b(Frame::from_z(Vec3(0, 0, 1)), Vec3(0, 0, 1), l);
    Vec3 wo = normalize(Vec3(0.3f, -0.2f, 0.9f));
    for (auto _ : state) {
        Vec3 wi = sample_cosine_hemisphere(Point2(rng.next_float(), rng.next_float()));
        benchmark::DoNotOptimize(b.f(wo, wi));
        benchmark::DoNotOptimize(b.pdf(wo, wi));
    }
    state.SetItemsProcessed(state.iterations());
}
BENCHMARK(BM_LambertEval);

void BM_AreaLightSample(benchmark::State& state) {
    const Scene& s = cornell();
    Pcg32 rng;
    LightSampleContext ctx{Point3(278, 100, 300), Vec3(0, 0, 0), Vec3(0, 1, 0)};
    auto lambda = SampledWavelengths::sample_visible(0.3f);
    for (auto _ : state) {
        Float pmf;
        int li = s.light_sampler.sample(rng.next_float(), pmf);
        auto ls = sample_li(s.lights[li], ctx, Point2(rng.next_float(), rng.next_float()), lambda);
        benchmark::DoNotOptimize(ls);
    }
    state.SetItemsProcessed(state.iterations());
}
BENCHMARK(BM_AreaLightSample);

void BM_SpectrumSampleDense(benchmark::State& state) {
    Spectrum sp = densely_sampled(BlackbodySpectrum(3000));
    Pcg32 rng;
    for (auto _ : state) {
        auto lambda = SampledWavelengths::sample_visible(rng.next_float());
        benchmark::DoNotOptimize(sp.sample(lambda));
    }
    state.SetItemsProcessed(state.iterations());
}
BENCHMARK(BM_SpectrumSampleDense);

void BM_SpectrumSampleRgbAlbedo(benchmark::State& state) {
    Spectrum sp = rgb_albedo_spectrum({0.7f, 0.3f, 0.2f});
    Pcg32 rng;
    for (auto _ : state) {
        auto lambda = SampledWavelengths::sample_visible(rng.next_float());
        benchmark::DoNotOptimize(sp.sample(lambda));
    }
    state.SetItemsProcessed(state.iterations());
}
BENCHMARK(BM_SpectrumSampleRgbAlbedo);

void BM_FilmToSensor(benchmark::State& state) {
    FilmParams fp;
    fp.rgb_from_sensor = srgb_from_xyz_matrix();
    Film film(fp);
    Pcg32 rng;
    for (auto _ : state) {
        auto lambda = SampledWavelengths::sample_visible(rng.next_float());
        benchmark::DoNotOptimize(film.to_sensor(SampledSpectrum(1), lambda));
    }
    state.SetItemsProcessed(state.iterations());
}
BENCHMARK(BM_FilmToSensor);

void BM_RgbUpliftSolve(benchmark::State& state) {
    // Distinct colours each iteration, so the solver (not the cache) is measured.
    Pcg32 rng(5);
    for (auto _ : state) {
        Rgb c{rng.next_float(), rng.next_float(), rng.next_float()};
        benchmark::DoNotOptimize(rgb_albedo_spectrum(c));
    }
    state.SetItemsProcessed(state.iterations());
}
BENCHMARK(BM_RgbUpliftSolve)->Unit(benchmark::kMicrosecond);

}  // namespace
}  // namespace sr
