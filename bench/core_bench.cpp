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

// A pixel's camera rays (8 samples within the gaussian filter's 1.5-pixel radius) traced one
// by one (arg 0) or as one packet (arg 1, what the renderer does).
void BM_CameraRayPacket(benchmark::State& state) {
    const Scene& s = cornell();
    constexpr int kN = Scene::kRayPacket;
    Pcg32 rng(1, 2);
    std::vector<Ray> rays(kN * 512);
    for (int p = 0; p < 512; ++p) {
        Float x = 512 * rng.next_float(), y = 512 * rng.next_float();
        for (int k = 0; k < kN; ++k)
            rays[kN * p + k] = s.camera->generate_ray(
                Point2(x + 3 * rng.next_float() - 1.5f, y + 3 * rng.next_float() - 1.5f),
                Point2(0.5f, 0.5f));
    }
    size_t p = 0;
    SurfaceHit h[kN];
    for (auto _ : state) {
        const Ray* r = &rays[kN * (p++ & 511)];
        if (state.range(0)) {
            benchmark::DoNotOptimize(s.intersect_packet(r, (1u << kN) - 1, h));
        } else {
            for (int k = 0; k < kN; ++k) benchmark::DoNotOptimize(s.intersect(r[k], h[k]));
        }
    }
    state.SetItemsProcessed(kN * state.iterations());
}
BENCHMARK(BM_CameraRayPacket)->Arg(0)->Arg(1);

// The first bounce of a pixel's 8 paths: rays from their (nearby) first hits in cosine-
// distributed directions, one by one (arg 0) or as one packet (arg 1).
void BM_FirstBouncePacket(benchmark::State& state) {
    const Scene& s = cornell();
    constexpr int kN = Scene::kRayPacket;
    Pcg32 rng(1, 2);
    std::vector<Ray> rays;
    while (rays.size() < kN * 512) {
        Float x = 512 * rng.next_float(), y = 512 * rng.next_float();
        Ray cam[kN];
        SurfaceHit h[kN];
        for (int k = 0; k < kN; ++k)
            cam[k] = s.camera->generate_ray(
                Point2(x + 3 * rng.next_float() - 1.5f, y + 3 * rng.next_float() - 1.5f),
                Point2(0.5f, 0.5f));
        if (s.intersect_packet(cam, (1u << kN) - 1, h) != (1u << kN) - 1) continue;
        for (int k = 0; k < kN; ++k) {
            Frame f = Frame::from_z(h[k].ns);
            Vec3 d = f.to_world(sample_cosine_hemisphere(Point2(rng.next_float(), rng.next_float())));
            rays.push_back(spawn_ray(h[k], d));
        }
    }
    size_t p = 0;
    SurfaceHit h[kN];
    for (auto _ : state) {
        const Ray* r = &rays[kN * (p++ & 511)];
        if (state.range(0)) {
            benchmark::DoNotOptimize(s.intersect_packet(r, (1u << kN) - 1, h));
        } else {
            for (int k = 0; k < kN; ++k) benchmark::DoNotOptimize(s.intersect(r[k], h[k]));
        }
    }
    state.SetItemsProcessed(kN * state.iterations());
}
BENCHMARK(BM_FirstBouncePacket)->Arg(0)->Arg(1);

// Shadow rays to the light: arg 0 = from a pixel's 8 first hits (as the renderer's first
// vertices), 1 = from 8 second hits (the first bounce's hits: spread over the box); arg 1 =
// one by one (0) or as one packet (1).
void BM_ShadowPacket(benchmark::State& state) {
    const Scene& s = cornell();
    constexpr int kN = Scene::kRayPacket;
    Pcg32 rng(1, 2);
    auto lambda = SampledWavelengths::sample_visible(0.5f);
    std::vector<Ray> rays;
    while (rays.size() < kN * 512) {
        Float x = 512 * rng.next_float(), y = 512 * rng.next_float();
        Ray cam[kN];
        SurfaceHit h[kN];
        for (int k = 0; k < kN; ++k)
            cam[k] = s.camera->generate_ray(
                Point2(x + 3 * rng.next_float() - 1.5f, y + 3 * rng.next_float() - 1.5f),
                Point2(0.5f, 0.5f));
        if (s.intersect_packet(cam, (1u << kN) - 1, h) != (1u << kN) - 1) continue;
        if (state.range(0) == 1) {
            bool all = true;
            for (int k = 0; k < kN && all; ++k) {
                Frame f = Frame::from_z(h[k].ns);
                Vec3 d = f.to_world(sample_cosine_hemisphere(Point2(rng.next_float(), rng.next_float())));
                all = s.intersect(spawn_ray(h[k], d), h[k]);
            }
            if (!all) continue;
        }
        for (int k = 0; k < kN; ++k) {
            Float pmf;
            int li = s.light_sampler.sample(rng.next_float(), pmf);
            LightSampleContext ctx{h[k].p, h[k].p_error, h[k].ng};
            auto ls = sample_li(s.lights[li], ctx, Point2(rng.next_float(), rng.next_float()), lambda);
            rays.push_back(ls ? spawn_ray_between(h[k], ls->p_light, ls->p_error, ls->n_light)
                              : spawn_ray(h[k], h[k].ng));
        }
    }
    size_t p = 0;
    for (auto _ : state) {
        const Ray* r = &rays[kN * (p++ & 511)];
        if (state.range(1)) {
            benchmark::DoNotOptimize(s.occluded_packet(r, (1u << kN) - 1));
        } else {
            for (int k = 0; k < kN; ++k) benchmark::DoNotOptimize(s.occluded(r[k]));
        }
    }
    state.SetItemsProcessed(kN * state.iterations());
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
