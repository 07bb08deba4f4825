// Micro-benchmarks of the pixel samplers in the access pattern of the path integrator: pixels of
// a 512x512 image in raster order, 64 samples per pixel, start_pixel_sample() then ~30
// dimensions per path. Reports ns per get (start_pixel_sample() amortized over the gets of its
// path), through the virtual Sampler interface as the renderer calls it.
//
// Standalone build, from the repository root (as the project compiles: -O3 -march=x86-64-v2;
// the grep leaves out the unit tests that sit beside the sources), one command:
//   g++ -std=c++20 -O3 -march=x86-64-v2 -I src bench/sampler_bench.cpp
//       $(ls src/steradian/sampling/*.cpp | grep -v _test) src/steradian/core/error.cpp
//       -lbenchmark -lbenchmark_main -lfmt -pthread -o sampler_bench
// and run, e.g.: ./sampler_bench --benchmark_repetitions=5 --benchmark_min_time=0.2
// The per_get counter is CPU time per get_1d()/get_2d()/get_pixel_2d() call. On a shared
// machine compare the minimum over repetitions.
#include <benchmark/benchmark.h>

#include <algorithm>
#include <memory>
#include <string>

#include "steradian/sampling/sampler.h"

namespace sr {
namespace {

constexpr int kRes = 512;
constexpr int kSpp = 64;

/// Visits (pixel, sample) in raster order, all samples of a pixel consecutively; wraps around.
struct Cursor {
    int x = 0, y = 0, s = 0;
    void next() {
        if (++s < kSpp) return;
        s = 0;
        if (++x < kRes) return;
        x = 0;
        if (++y == kRes) y = 0;
    }
};

/// Visits (pixel, sample) in the renderer's progressive passes (render.cpp): samples [0, 1),
/// [1, 3), [3, 7), ..., [63, 64) of every pixel, pass after pass, so a pixel's consecutive
/// samples are fewer than in Cursor (the Sobol samplers memoize per-pixel work across them).
/// Covers a 64x64 window of the image so that a run goes through all passes several times.
struct PassCursor {
    static constexpr int kWindow = 64;
    int x = 0, y = 0, s = 0, s0 = 0, s1 = 1;
    void next() {
        if (++s < s1) return;
        s = s0;
        if (++x < kWindow) return;
        x = 0;
        if (++y < kWindow) return;
        y = 0;
        int size = std::min(2 * (s1 - s0), kSpp);
        s0 = s1 < kSpp ? s1 : 0;
        s1 = std::min(kSpp, s0 + (s0 == 0 ? 1 : size));
        s = s0;
    }
};

std::unique_ptr<Sampler> make(const std::string& name) {
    return make_sampler(name, kSpp, Vec2i{kRes, kRes}, 7);
}

void report(benchmark::State& state, int gets_per_iteration) {
    state.SetItemsProcessed(state.iterations() * gets_per_iteration);
    // CPU seconds per get (printed as e.g. "7.5ns").
    state.counters["per_get"] =
        benchmark::Counter(double(state.iterations()) * gets_per_iteration,
                           benchmark::Counter::kIsRate | benchmark::Counter::kInvert);
}

/// start_pixel_sample + 30 get_1d.
void BM_Get1D(benchmark::State& state, const std::string& name) {
    auto sp = make(name);
    Sampler& s = *sp;
    constexpr int kGets = 30;
    Cursor c;
    for (auto _ : state) {
        s.start_pixel_sample({c.x, c.y}, c.s);
        Float sum = 0;
        for (int i = 0; i < kGets; ++i) sum += s.get_1d();
        benchmark::DoNotOptimize(sum);
        c.next();
    }
    report(state, kGets);
}

/// start_pixel_sample + 15 get_2d.
void BM_Get2D(benchmark::State& state, const std::string& name) {
    auto sp = make(name);
    Sampler& s = *sp;
    constexpr int kGets = 15;
    Cursor c;
    for (auto _ : state) {
        s.start_pixel_sample({c.x, c.y}, c.s);
        Float sum = 0;
        for (int i = 0; i < kGets; ++i) {
            Point2 p = s.get_2d();
            sum += p.x + p.y;
        }
        benchmark::DoNotOptimize(sum);
        c.next();
    }
    report(state, kGets);
}

/// The path integrator's pattern: pixel 2D, wavelength 1D, lens 2D, then per bounce light 1D +
/// 2D, BSDF 1D + 2D, Russian roulette 1D; 5 bounces: 28 gets, 37 dimensions.
template <typename CursorT>
void path(benchmark::State& state, const std::string& name) {
    auto sp = make(name);
    Sampler& s = *sp;
    constexpr int kBounces = 5;
    constexpr int kGets = 3 + 5 * kBounces;
    CursorT c;
    for (auto _ : state) {
        s.start_pixel_sample({c.x, c.y}, c.s);
        Point2 p = s.get_pixel_2d();
        Float sum = p.x + p.y + s.get_1d();
        p = s.get_2d();
        sum += p.x + p.y;
        for (int b = 0; b < kBounces; ++b) {
            sum += s.get_1d();
            p = s.get_2d();
            sum += p.x + p.y + s.get_1d();
            p = s.get_2d();
            sum += p.x + p.y + s.get_1d();
        }
        benchmark::DoNotOptimize(sum);
        c.next();
    }
    report(state, kGets);
}

/// All 64 samples of a pixel consecutively.
void BM_Path(benchmark::State& state, const std::string& name) { path<Cursor>(state, name); }

/// The renderer's progressive passes (1, 2, 4, ... samples of a pixel at a time).
void BM_PathPasses(benchmark::State& state, const std::string& name) {
    path<PassCursor>(state, name);
}

#define SR_SAMPLER_BENCH(name)                             \
    BENCHMARK_CAPTURE(BM_Get1D, name, std::string(#name)); \
    BENCHMARK_CAPTURE(BM_Get2D, name, std::string(#name)); \
    BENCHMARK_CAPTURE(BM_Path, name, std::string(#name));  \
    BENCHMARK_CAPTURE(BM_PathPasses, name, std::string(#name))

SR_SAMPLER_BENCH(independent);
SR_SAMPLER_BENCH(stratified);
SR_SAMPLER_BENCH(zsobol);
SR_SAMPLER_BENCH(sobol);
SR_SAMPLER_BENCH(paddedsobol);

}  // namespace
}  // namespace sr
