/// Photometry benchmarks: the CIE 171:2006 test cases of tests/data/cie171 measured to the
/// issue's targets (direct cases to 0.1 % relative standard error, case 5.8 at rho = 0.8 to
/// 0.2 %). Each iteration is a whole `measure` (scene already built); the reported counters
/// are the CPU seconds of the measurement, the paths traced and the worst relative error
/// of the readings against the published values.
///   build/release/steradian_bench --benchmark_filter=Cie171
#include <benchmark/benchmark.h>
#include <fmt/format.h>

#include <cmath>
#include <string>
#include <vector>

#include "steradian/integrators/measure.h"
#include "steradian/scene/build.h"
#include "steradian/scene/pbrt/parser.h"

namespace {

const std::string kDir = std::string(STERADIAN_SOURCE_DIR) + "/tests/data/cie171/";

/// Measures `file` to `rel_error`; `published` lists the expected values of the readings'
/// values in order (grids: their averages), or is empty.
void run_case(benchmark::State& state, const std::string& file, double rel_error,
              const std::vector<double>& published, bool grids_only_first = false) {
    sr::Scene scene = sr::build_scene(sr::parse_pbrt_file(kDir + file), {});
    if (grids_only_first) scene.meters.resize(1);
    sr::MeasureOptions opt;
    opt.rel_error = rel_error;
    double cpu = 0, worst = 0, paths = 0;
    for (auto _ : state) {
        sr::MeasureResult r = sr::measure(scene, opt);
        cpu += r.cpu_seconds;
        paths += double(r.paths);
        size_t k = 0;
        worst = 0;
        for (const sr::MeterReading& m : r.readings) {
            if (m.meter.kind == sr::MeterKind::Grid) {
                if (k < published.size()) worst = std::max(worst, std::abs(m.avg / published[k++] - 1));
            } else {
                for (double v : m.values)
                    if (k < published.size()) worst = std::max(worst, std::abs(v / published[k++] - 1));
            }
        }
    }
    state.counters["cpu_s"] = benchmark::Counter(cpu, benchmark::Counter::kAvgIterations);
    state.counters["paths"] = benchmark::Counter(paths, benchmark::Counter::kAvgIterations);
    state.counters["max_rel_err"] = worst;
}

void BM_Cie171_5_2_PointSource(benchmark::State& state) {
    run_case(state, "case-5.2.pbrt", 1e-3,
             {111.111, 105.186, 90.000, 71.111, 99.723, 85.663, 68.053, 74.380, 59.975, 49.383});
}
BENCHMARK(BM_Cie171_5_2_PointSource)->Unit(benchmark::kMillisecond)->UseRealTime();

void BM_Cie171_5_3_AreaSource(benchmark::State& state) {
    run_case(state, "case-5.3.pbrt", 1e-3,
             {61.424, 79.255, 95.667, 105.778, 32.677, 75.194, 81.323, 69.061, 53.404, 40.002});
}
BENCHMARK(BM_Cie171_5_3_AreaSource)->Unit(benchmark::kMillisecond)->UseRealTime();

void BM_Cie171_5_8_Indirect(benchmark::State& state) {
    // Only the indirect face average (the case's quantity): rho Phi / (S (1 - rho)).
    const double rho = double(state.range(0)) / 100;
    run_case(state, fmt::format("case-5.8-rho{}.pbrt", rho), 2e-3, {rho * 10000 / (96 * (1 - rho))},
             true);
}
// rho = 0.8 is the target case (0.2 % in under 2 s); the others for scale.
BENCHMARK(BM_Cie171_5_8_Indirect)->Arg(80)->Arg(20)->Arg(50)->Arg(95)->Unit(benchmark::kMillisecond)->UseRealTime();

}  // namespace
