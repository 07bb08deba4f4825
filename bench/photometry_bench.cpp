/// Photometry benchmarks: the CIE 171:2006 test cases of tests/data/cie171 measured to the
/// issue's targets (direct cases to 0.1 % relative standard error, case 5.8 at rho = 0.8 to
/// 0.2 %). Each iteration is a whole `measure` (scene already built); the reported counters
/// are the CPU seconds of the measurement, the paths traced and the worst relative error
/// of the readings against the published values.
///   build/release/steradian_bench --benchmark_filter=Cie171
///
/// DirectGrid: a 50 x 50 illuminance grid over a 10 x 10 m black floor under one luminaire
/// 3 m up (docs/photometry.md, "Direct light without Monte Carlo"): the point form
/// (cos1000.ies), a rectangular opening (tests/data/identical/rect.ies, 0.3 x 0.2 m), the
/// issue's luminous box (0.28 x 0.20 x 0.019 m, a Lambertian box's distribution) and a
/// narrow-beam flood light (0.5 x 0.5 m opening, I = 20000 cos^200(gamma) cd, a 4.8-degree
/// half-value angle), each by the deterministic path and by sampling (`/1`) to 0.1 %.
///   build/ci/steradian_bench --benchmark_filter=DirectGrid
#include <benchmark/benchmark.h>
#include <fmt/format.h>

#include <cmath>
#include <filesystem>
#include <fstream>
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

/// A Type C IES file (absolute photometry) with the opening W x L x H (m) and intensity
/// f(gamma, C) on gamma 0..180 and C 0..90 at 0.5-degree steps.
std::string direct_ies(double w, double l, double h, double (*f)(double, double)) {
    std::string s = fmt::format(
        "IESNA:LM-63-2002\nTILT=NONE\n1 -1 1 361 181 1 2 {} {} {}\n1 1 0\n", w, l, h);
    for (int i = 0; i <= 360; ++i) s += fmt::format("{} ", 0.5 * i);
    s += "\n";
    for (int j = 0; j <= 180; ++j) s += fmt::format("{} ", 0.5 * j);
    s += "\n";
    const double deg = 3.14159265358979323846 / 180;
    for (int j = 0; j <= 180; ++j) {
        for (int i = 0; i <= 360; ++i) s += fmt::format("{:.9g} ", f(0.5 * i * deg, 0.5 * j * deg));
        s += "\n";
    }
    return s;
}

double box_intensity(double g, double c) {  // 5000 cd/m^2 on every face
    const double x = std::sin(g) * std::cos(c), y = std::sin(g) * std::sin(c), z = std::cos(g);
    return 5000 * (0.2 * 0.019 * std::abs(x) + 0.28 * 0.019 * std::abs(y) + 0.28 * 0.2 * std::abs(z));
}

double flood_intensity(double g, double) { return g < 1.5707963 ? 20000 * std::pow(std::cos(g), 200) : 0; }

void BM_DirectGrid(benchmark::State& state, int luminaire) {
    const bool sampled = state.range(0) != 0;
    const std::filesystem::path dir =
        std::filesystem::temp_directory_path() / fmt::format("steradian-bench-direct-{}", luminaire);
    std::filesystem::create_directories(dir);
    std::string file;
    switch (luminaire) {
        case 0: file = std::string(STERADIAN_SOURCE_DIR) + "/tests/data/cie171/cos1000.ies"; break;
        case 1: file = std::string(STERADIAN_SOURCE_DIR) + "/tests/data/identical/rect.ies"; break;
        case 2:
            file = (dir / "box.ies").string();
            std::ofstream(file) << direct_ies(0.2, 0.28, 0.019, box_intensity);
            break;
        default:
            file = (dir / "flood.ies").string();
            std::ofstream(file) << direct_ies(0.5, 0.5, 0, flood_intensity);
            break;
    }
    const std::string scene =
        "Camera \"perspective\"\nFilm \"rgb\" \"string filename\" \"x.exr\"\nWorldBegin\n"
        "Material \"diffuse\" \"spectrum reflectance\" [ 360 0 830 0 ]\n"
        "Shape \"trianglemesh\" \"point3 P\" [ -5 -5 0 5 -5 0 5 5 0 -5 5 0 ] \"integer indices\" [ 0 1 2 0 2 3 ]\n"
        "AttributeBegin\n Translate 0 0 3\n LightSource \"goniometric\" \"string filename\" \"" + file +
        "\"\nAttributeEnd\n"
        "Meter \"illuminancegrid\" \"point3 corner\" [ -5 -5 0 ] \"vector3 u\" [ 10 0 0 ] "
        "\"vector3 v\" [ 0 10 0 ] \"integer resolution\" [ 50 50 ] \"normal n\" [ 0 0 1 ]\n";
    sr::Scene sc = sr::build_scene(sr::parse_pbrt_string(scene, "<bench>", dir.string()), {});
    sr::MeasureOptions opt;
    opt.rel_error = 1e-3;
    opt.deterministic_direct = !sampled;
    double cpu = 0, worst_rel_err = 0, avg = 0;
    for (auto _ : state) {
        sr::MeasureResult r = sr::measure(sc, opt);
        cpu += r.cpu_seconds;
        const sr::MeterReading& m = r.readings[0];
        avg = m.avg;
        worst_rel_err = 0;
        for (size_t k = 0; k < m.values.size(); ++k)
            if (m.values[k] > 1e-3 * m.max)
                worst_rel_err = std::max(worst_rel_err, m.stderrs[k] / m.values[k]);
    }
    state.counters["cpu_s"] = benchmark::Counter(cpu, benchmark::Counter::kAvgIterations);
    state.counters["E_avg"] = avg;
    state.counters["max_rel_err"] = worst_rel_err;
    std::filesystem::remove_all(dir);
}
BENCHMARK_CAPTURE(BM_DirectGrid, PointForm, 0)->Arg(0)->Arg(1)->Unit(benchmark::kMillisecond)->UseRealTime();
BENCHMARK_CAPTURE(BM_DirectGrid, RectOpening, 1)->Arg(0)->Arg(1)->Unit(benchmark::kMillisecond)->UseRealTime();
BENCHMARK_CAPTURE(BM_DirectGrid, LuminousBox, 2)->Arg(0)->Arg(1)->Unit(benchmark::kMillisecond)->UseRealTime();
BENCHMARK_CAPTURE(BM_DirectGrid, NarrowFlood, 3)->Arg(0)->Arg(1)->Unit(benchmark::kMillisecond)->UseRealTime();

}  // namespace
