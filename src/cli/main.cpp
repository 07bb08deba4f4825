// steradian command line: `steradian render SCENE.pbrt [options]`,
// `steradian measure SCENE.pbrt [options]`, `steradian check SCENE.pbrt... [--json FILE]`.
// Built a second time with STERADIAN_MPI as `steradian-mpi`, which shares renders and
// measurements among the processes of `mpirun` (docs/distributed.md).
#include <signal.h>
#include <unistd.h>

#include <CLI/CLI.hpp>
#include <atomic>
#include <cerrno>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <functional>
#include <iostream>
#include <nlohmann/json.hpp>
#include <optional>
#include <set>
#include <sstream>
#include <thread>

#include "steradian/core/error.h"
#include "steradian/core/error_list.h"
#include "steradian/core/output_file.h"
#include "steradian/film/falsecolor.h"
#include "steradian/film/film.h"
#include "steradian/film/image_io.h"
#include "steradian/integrators/checkpoint.h"
#include "steradian/integrators/distributed.h"
#include "steradian/integrators/integrator.h"
#include "steradian/integrators/direct_light.h"
#include "steradian/integrators/measure.h"
#include "steradian/integrators/report.h"
#include "steradian/integrators/radiosity/radiosity.h"
#include "steradian/scene/build.h"
#include "steradian/scene/pbrt/parser.h"
#ifdef STERADIAN_MPI
#include "mpi/mpi_session.h"
#endif

namespace {

std::string human_bytes(size_t b) {
    const char* units[] = {"B", "KiB", "MiB", "GiB"};
    double v = double(b);
    int u = 0;
    while (v >= 1024 && u < 3) v /= 1024, ++u;
    return fmt::format("{:.1f} {}", v, units[u]);
}

std::string human_rate(double r) {
    if (r >= 1e9) return fmt::format("{:.2f} G", r / 1e9);
    if (r >= 1e6) return fmt::format("{:.2f} M", r / 1e6);
    if (r >= 1e3) return fmt::format("{:.2f} k", r / 1e3);
    return fmt::format("{:.0f} ", r);
}

/// A command-line number that must be finite (CLI11's range checks let NaN through).
const CLI::Validator kFinite(
    [](std::string& s) -> std::string {
        try {
            size_t used = 0;
            double v = std::stod(s, &used);
            if (used != s.size() || !std::isfinite(v)) return "must be a finite number";
        } catch (const std::exception&) {
            return "must be a finite number";
        }
        return "";
    },
    "FINITE");

/// A seed: a decimal integer in [0, 2^64) (CLI11 wraps larger and negative values).
const CLI::Validator kSeed(
    [](std::string& s) -> std::string {
        const char* err = "must be an integer from 0 to 18446744073709551615";
        if (s.empty() || s.find_first_not_of("0123456789") != std::string::npos) return err;
        errno = 0;
        char* end = nullptr;
        std::strtoull(s.c_str(), &end, 10);
        if (errno == ERANGE || *end != 0) return err;
        return "";
    },
    "SEED");

/// SIGINT and SIGTERM: the first asks the computation to stop after the pass (render) or
/// round (measure) in flight, so that what is done is written; a second exits at once.
std::atomic<bool> g_stop{false};
volatile sig_atomic_t g_signal = 0;

extern "C" void on_signal(int sig) {
    if (g_signal != 0) _exit(128 + sig);
    g_signal = sig;
    g_stop.store(true);
    static const char msg[] =
        "\nsteradian: interrupted: finishing the pass in flight, then writing what is done "
        "(interrupt again to quit at once)\n";
    ssize_t ignored = write(STDERR_FILENO, msg, sizeof msg - 1);
    (void)ignored;
}

void install_signal_handlers() {
    static_assert(std::atomic<bool>::is_always_lock_free);  // safe in a signal handler
    struct sigaction sa {};
    sa.sa_handler = on_signal;
    sigemptyset(&sa.sa_mask);
    sigaction(SIGINT, &sa, nullptr);
    sigaction(SIGTERM, &sa, nullptr);
}

/// The exit status after a completed computation: 128 + the signal that interrupted it.
int exit_status() { return g_signal != 0 ? 128 + int(g_signal) : 0; }

/// The most worker threads accepted: far more than any machine's cores, few enough that
/// the thread pool and the per-thread state always fit.
constexpr int kMaxThreads = 1024;

/// The processes of `steradian-mpi` under mpirun (docs/distributed.md); without MPI, or run
/// alone, there is one.
#ifdef STERADIAN_MPI
sr::mpi::Session* g_mpi = nullptr;
#endif
int g_rank = 0, g_size = 1;
/// Set once every process has loaded the scene: from then on an error on one process ends
/// the job (a worker aborts it; the coordinator ends the workers' session and fails).
[[maybe_unused]] bool g_dist_started = false;

/// A process other than the coordinator (process 0) of a distributed run.
bool is_worker() { return g_rank != 0; }

/// Under mpirun, once the scene is loaded (and the outputs checked, and the radiosity system
/// solved, which every process does): every process agrees that every other one loaded it
/// too (an error elsewhere: this one returns 1 quietly, the failing ones say why), that all
/// run the same executable on the same input files (a node with another build or a stale
/// copy of a file would compute another image), and that all solved the radiosity system to
/// the same bits. Then the workers compute what the coordinator hands out until it is done.
/// Returns the exit status for a worker, or -1 on the coordinator (or alone), which goes on.
int start_distributed(const sr::Scene& scene, int threads,
                      const sr::RadiositySolution* radiosity = nullptr) {
#ifdef STERADIAN_MPI
    if (g_size <= 1) return -1;
    if (g_mpi->count_failed(false) > 0) return 1;
    const std::string mine = sr::executable_id() + " " + sr::inputs_digest();
    const std::string root = g_mpi->broadcast(mine);
    const bool differs = root != mine;
    const std::string my_solution =
        radiosity ? fmt::format("{:016x}", radiosity->digest()) : std::string("none");
    // (Collective: every process takes part, whatever it found above.)
    const bool other_solution = g_mpi->broadcast(my_solution) != my_solution && !differs;
    const int n = g_mpi->count_failed(differs || other_solution);
    if (differs)
        std::fprintf(stderr,
                     "error (process %d of %d): another executable or other input files than "
                     "process 0's (executable and file hashes differ): every process must run the "
                     "same build on the same scene files (docs/distributed.md)\n",
                     g_rank, g_size);
    else if (other_solution)
        std::fprintf(stderr,
                     "error (process %d of %d): another radiosity solution than process 0's (its "
                     "hash %s differs): the processes' solves did not give the same bits "
                     "(docs/distributed.md)\n",
                     g_rank, g_size, my_solution.c_str());
    if (n > 0) return 1;
    g_dist_started = true;
    if (!is_worker()) return -1;
    const int nthreads = threads > 0 ? threads : int(std::thread::hardware_concurrency());
    sr::serve_work(*g_mpi,
                   {sr::render_job_handler(scene, threads, radiosity),
                    sr::measure_job_handler(scene, threads, radiosity),
                    sr::mlt_job_handler(scene, threads), sr::sppm_job_handler(scene, threads),
                    sr::vcm_job_handler(scene, threads)},
                   2 * nthreads);
    return 0;
#else
    (void)scene;
    (void)threads;
    (void)radiosity;
    return -1;
#endif
}

/// The coordinator's side of the processes (null alone).
std::optional<sr::WorkCoordinator> make_coordinator() {
#ifdef STERADIAN_MPI
    if (g_size > 1 && !is_worker()) return std::optional<sr::WorkCoordinator>(std::in_place, *g_mpi);
#endif
    return std::nullopt;
}

/// After the work: the CPU time of every process, when there are several.
void print_distributed_summary(std::optional<sr::WorkCoordinator>& coord, bool quiet) {
    if (!coord) return;
    coord->finish();
    if (!quiet)
        std::fprintf(stderr, "  processes       %d; CPU time of all %.2f s (this one's %.2f s)\n",
                     g_size, coord->workers_cpu_seconds() + sr::process_cpu_seconds(),
                     sr::process_cpu_seconds());
}

/// The readings as a table on stdout.
void print_readings(const sr::MeasureResult& r) {
    for (const sr::MeterReading& rd : r.readings) {
        const sr::Meter& m = rd.meter;
        std::printf("%s (%s, %s)%s\n", m.name.c_str(), m.type.c_str(), m.unit().c_str(),
                    rd.estimator == "monte carlo" ? "" : (", " + rd.estimator).c_str());
        for (size_t k = 0; k < rd.values.size(); ++k) {
            sr::Point3 p = m.points[k];
            double rel = rd.values[k] != 0 ? rd.stderrs[k] / std::abs(rd.values[k]) : 0;
            const bool exact = k < rd.exact.size() && rd.exact[k];
            std::printf("  %4zu  (%9.4g, %9.4g, %9.4g)  %12.6g +- %-10.3g (%s)%s\n", k, p.x, p.y,
                        p.z, rd.values[k], rd.stderrs[k],
                        exact ? "exact" : fmt::format("{:.3f}%", 100 * rel).c_str(),
                        rd.converged[k] ? "" : "  not converged");
        }
        if (m.kind == sr::MeterKind::Grid)
            std::printf("  E_avg %.6g +- %.3g   E_min %.6g   E_max %.6g   U0 %.4f\n", rd.avg,
                        rd.avg_stderr, rd.min, rd.max, rd.uniformity);
    }
}

void print_measure_summary(const sr::MeasureResult& r) {
    std::fflush(stdout);
    std::fprintf(stderr, "  meters          %zu, target relative standard error %.3g%%%s\n",
                 r.readings.size(), 100 * r.rel_error_target,
                 r.all_converged ? "" : (r.time_limited ? " (NOT reached: --time budget)"
                                                        : " (NOT reached: sample limit)"));
    std::fprintf(stderr, "  wall time       %.3f s\n", r.wall_seconds);
    std::fprintf(stderr, "  CPU time        %.3f s\n", r.cpu_seconds);
    std::fprintf(stderr, "  paths           %llu\n", (unsigned long long)r.paths);
    if (r.nonfinite > 0)
        std::fprintf(stderr, "warning: %llu samples were NaN or infinite and were zeroed\n",
                     (unsigned long long)r.nonfinite);
}

/// False-colour images of the grid meters: `path` for the first, `<stem>-<name><ext>` for
/// the others. Rows run along u; v points up in the image.
void write_grid_false_color(const sr::MeasureResult& r, const std::string& path, bool quiet) {
    bool first = true;
    for (const sr::MeterReading& rd : r.readings) {
        const sr::Meter& m = rd.meter;
        if (m.kind != sr::MeterKind::Grid) continue;
        sr::Image v;
        v.width = m.nu;
        v.height = m.nv;
        v.channels = 1;
        v.data.resize(size_t(m.nu) * m.nv);
        for (int j = 0; j < m.nv; ++j)
            for (int i = 0; i < m.nu; ++i)
                v.data[size_t(m.nv - 1 - j) * m.nu + i] = float(rd.values[size_t(j) * m.nu + i]);
        sr::FalseColorOptions fo;
        fo.unit = m.unit();
        fo.log_scale = false;
        std::filesystem::path out(path);
        if (!first) out.replace_filename(out.stem().string() + "-" + m.name + out.extension().string());
        sr::write_image(out.string(), sr::false_color(v, fo));
        if (!quiet) std::fprintf(stderr, "steradian: wrote %s (false colour, %s)\n", out.string().c_str(), m.name.c_str());
        first = false;
    }
    if (first) throw sr::Error("--falsecolor: the scene has no grid meter (Meter \"illuminancegrid\")");
}

struct MeasureArgs {
    std::string scene;
    std::string falsecolor;
    std::string report;
    std::string json, csv;
    double rel_error = 1e-3;
    double time_budget = 0;
    int threads = 0;
    uint64_t seed = 0;
    bool quiet = false;
    std::string checkpoint, resume;
    double checkpoint_every = 0;
    std::string method = "auto";
    std::string radiosity_mesh;
    int replicas = 32, pilot_samples = 32;
    bool sampled_direct = false;
};

/// Solves the scene by the radiosity pass (its Integrator's parameters, or the defaults),
/// says so on stderr, and writes the mesh if asked.
std::unique_ptr<sr::RadiositySolution> solve_radiosity_for(const sr::Scene& scene, int threads,
                                                           const std::string& mesh_out,
                                                           bool quiet) {
    auto sol = sr::solve_radiosity(scene, scene.integrator.radiosity, threads);
    const sr::RadiosityStats& rs = sol->stats();
    if (!quiet) {
        std::fprintf(stderr,
                     "steradian: radiosity: %zu patches, %zu unknowns, %zu form factors, %d "
                     "solve(s) in %d iterations to residual %.2g, %.2f s\n",
                     rs.patches, rs.unknowns, rs.pairs, rs.solves, rs.iterations, rs.residual,
                     rs.seconds);
    }
    for (const std::string& n : rs.notes)
        if (!is_worker()) std::fprintf(stderr, "steradian: radiosity: %s\n", n.c_str());
    if (!mesh_out.empty() && !is_worker()) {
        sr::write_radiosity_ply(*sol, mesh_out);
        if (!quiet) std::fprintf(stderr, "steradian: wrote %s (radiosity mesh)\n", mesh_out.c_str());
    }
    return sol;
}

std::string absolute_or_empty(const std::string& path) {
    return path.empty() ? "" : std::filesystem::absolute(path).string();
}

/// The checkpoint of a measurement: what decides its readings (the build, the scene's
/// contents, the target and the seed), the options to resume it with, and its state.
sr::Checkpoint measure_checkpoint(const MeasureArgs& a, const sr::MeasureOptions& mo,
                                  const std::string& exe, const std::string& digest) {
    sr::Checkpoint c;
    c.set("kind", "measure");
    c.set("executable", exe);
    c.set("scene-digest", digest);
    c.set("rel-error", fmt::format("{}", a.rel_error));
    c.set("seed", std::to_string(a.seed));
    c.set("estimator", fmt::format("{} replicas, {} to {} samples{}", mo.replicas, mo.first_samples,
                                   mo.max_samples,
                                   mo.deterministic_direct ? "" : ", sampled direct light"));
    c.set("scene", std::filesystem::absolute(a.scene).string());
    c.set("json", absolute_or_empty(a.json));
    c.set("csv", absolute_or_empty(a.csv));
    c.set("falsecolor", absolute_or_empty(a.falsecolor));
    c.set("report", absolute_or_empty(a.report));
    c.set_number("checkpoint-every", a.checkpoint_every);
    c.set("method", a.method);
    return c;
}

int run_measure(MeasureArgs a, const std::function<bool(const char*)>& given) {
    if (a.pilot_samples & (a.pilot_samples - 1))
        throw sr::Error(fmt::format("--pilot-samples {} is not a power of two", a.pilot_samples));
    std::optional<sr::Checkpoint> resume;
    if (!a.resume.empty()) {
        resume = sr::Checkpoint::load(a.resume);
        if (resume->get("kind") != "measure")
            throw sr::Error(fmt::format("checkpoint {} is a {} checkpoint, not a measurement's",
                                        a.resume, resume->get("kind")));
        if (a.scene.empty()) a.scene = resume->get("scene");
        if (!given("--json")) a.json = resume->get("json");
        if (!given("--csv")) a.csv = resume->get("csv");
        if (!given("--falsecolor")) a.falsecolor = resume->get("falsecolor");
        if (!given("--report") && resume->has("report")) a.report = resume->get("report");
        if (!given("--rel-error")) a.rel_error = resume->get_double("rel-error");
        if (!given("--seed")) a.seed = std::stoull(resume->get("seed"));
        if (!given("--checkpoint-every"))
            a.checkpoint_every = resume->get_double("checkpoint-every");
        if (!given("--method")) a.method = resume->get("method");
        if (a.checkpoint.empty()) a.checkpoint = a.resume;
    }
    const std::string& scene_path = a.scene;
    sr::SceneDesc desc = sr::parse_pbrt_file(scene_path);
    sr::Scene scene = sr::build_scene(desc, {});
    if (scene.meters.empty())
        throw sr::Error(fmt::format("{}: the scene has no Meter directives", scene_path));
    // Every output is checked before the measurement, not found unwritable after it.
    if (!is_worker()) {
        if (!a.json.empty()) sr::check_output_path(a.json, "--json");
        if (!a.csv.empty()) sr::check_output_path(a.csv, "--csv");
        if (!a.falsecolor.empty()) sr::check_image_output(a.falsecolor);
        if (!a.report.empty()) sr::check_output_path(a.report, "--report");
        if (!a.checkpoint.empty()) sr::check_output_path(a.checkpoint, "the checkpoint");
        if (!a.radiosity_mesh.empty())
            sr::check_output_path(a.radiosity_mesh, "--radiosity-mesh");
    }
    // The method: auto takes radiosity where it models every surface exactly (or the scene
    // asks for it), and says why. Distributed, every process decides the same (from the
    // scene) and solves the radiosity system itself (docs/distributed.md).
    std::string method = a.method, reason = "--method " + a.method, why;
    if (method == "auto") {
        if (sr::direct_light_deterministic(scene) && !sr::scene_may_scatter(scene)) {
            method = "path";
            reason = "auto: no surface scatters light, so the readings are direct light, "
                     "computed without sampling";
        } else if (scene.integrator.type == "radiosity") {
            method = "radiosity";
            reason = "auto: the scene's Integrator is \"radiosity\"";
        } else if (sr::radiosity_models_exactly(scene, &why)) {
            method = "radiosity";
            reason = "auto: every surface is diffuse";
        } else {
            method = "path";
            reason = "auto: " + why;
        }
    }
    if (!a.radiosity_mesh.empty() && method != "radiosity")
        throw sr::Error(fmt::format("--radiosity-mesh: the method is {} ({}), not radiosity",
                                    method, reason));
    if (!a.quiet && !is_worker())
        std::fprintf(stderr, "steradian: method %s (%s)\n", method.c_str(), reason.c_str());
    if (method == "light" && (resume || !a.checkpoint.empty()))
        throw sr::Error("--method light: checkpoints are not supported with light tracing yet");
    std::unique_ptr<sr::RadiositySolution> radiosity;
    if (method == "radiosity")
        radiosity =
            solve_radiosity_for(scene, a.threads, a.radiosity_mesh, a.quiet || is_worker());
    if (const int status = start_distributed(scene, a.threads, radiosity.get()); status >= 0)
        return status;
    std::optional<sr::WorkCoordinator> coord = make_coordinator();
    sr::MeasureOptions mo;
    mo.radiosity = radiosity.get();
    mo.light_trace = method == "light";
    mo.replicas = a.replicas;
    mo.first_samples = a.pilot_samples;
    mo.deterministic_direct = !a.sampled_direct;
    mo.rel_error = a.rel_error;
    mo.time_budget = a.time_budget;
    mo.threads = a.threads;
    mo.seed = a.seed;
    mo.stop = &g_stop;
    mo.distribute = coord ? &*coord : nullptr;
    std::string exe, digest;
    if (resume || !a.checkpoint.empty()) {
        exe = sr::executable_id();
        digest = sr::inputs_digest();
    }
    sr::MeasureState resumed;
    if (resume) {
        resume->expect("executable", exe, "another build of steradian (executable hash)",
                       "a measurement resumes only with the build that started it");
        resume->expect("scene-digest", digest, "a scene whose files hash to",
                       "the scene or a file it reads has changed since");
        resume->expect("rel-error", fmt::format("{}", a.rel_error), "--rel-error");
        resume->expect("seed", std::to_string(a.seed), "--seed");
        resume->expect("method", a.method, "--method");
        resume->expect("estimator",
                       fmt::format("{} replicas, {} to {} samples{}", mo.replicas, mo.first_samples,
                                   mo.max_samples,
                                   mo.deterministic_direct ? "" : ", sampled direct light"),
                       "--replicas, --pilot-samples and --sampled-direct");
        size_t values = 0;
        for (const sr::Meter& m : scene.meters) values += m.points.size();
        resumed = sr::get_measure_state(*resume, values);
        mo.resume = &resumed;
        if (!a.quiet)
            std::fprintf(stderr, "steradian: resuming %s at round %d\n", a.resume.c_str(),
                         resumed.round);
    }
    if (!a.checkpoint.empty()) {
        const sr::Checkpoint base = measure_checkpoint(a, mo, exe, digest);
        mo.checkpoint_every = a.checkpoint_every;
        mo.checkpoint = [&, base](const sr::MeasureState& state) {
            sr::Checkpoint c = base;
            sr::put_measure_state(c, state);
            c.save(a.checkpoint);
        };
    }
    sr::MeasureResult r = sr::measure(scene, mo);
    print_readings(r);
    if (!a.json.empty()) sr::write_text_file(a.json, sr::meters_json(r));
    if (!a.csv.empty()) sr::write_text_file(a.csv, sr::meters_csv(r));
    if (!a.falsecolor.empty()) write_grid_false_color(r, a.falsecolor, a.quiet);
    if (!a.report.empty()) {
        sr::ReportOptions ro;
        ro.scene_path = scene_path;
        sr::write_text_file(a.report, sr::measure_report_html(scene, r, ro));
        if (!a.quiet) std::fprintf(stderr, "steradian: wrote %s (report)\n", a.report.c_str());
    }
    if (!a.quiet) print_measure_summary(r);
    print_distributed_summary(coord, a.quiet);
    if (r.interrupted)
        std::fprintf(stderr, "steradian: interrupted: the readings above are those reached\n");
    if (!a.checkpoint.empty() && !r.all_converged && r.time_limited)
        std::fprintf(stderr, "steradian: checkpoint %s holds the measurement; continue with: "
                     "steradian measure --resume %s\n", a.checkpoint.c_str(), a.checkpoint.c_str());
    return exit_status();
}

struct RenderArgs {
    std::string scene;
    std::vector<std::string> outs;
    int spp = 0, threads = 0;
    uint64_t seed = 0;
    double time_budget = 0;
    bool quiet = false;
    float exposure = 0;
    std::string luminance_out, falsecolor_out;
    std::string checkpoint, resume;
    double checkpoint_every = 0;
    std::string radiosity_mesh;
};

/// The checkpoint of a render: what decides its result (the build, the scene's contents,
/// the sample count and seed) to be compared on resume, the options to resume it with, and
/// the film's state.
sr::Checkpoint render_checkpoint(const RenderArgs& a, const std::string& exe,
                                 const std::string& digest, int total_spp) {
    sr::Checkpoint c;
    c.set("kind", "render");
    c.set("executable", exe);
    c.set("scene-digest", digest);
    c.set("samples-per-pixel", std::to_string(total_spp));
    c.set("seed", std::to_string(a.seed));
    namespace fs = std::filesystem;
    c.set("scene", fs::absolute(a.scene).string());
    std::string outs;
    for (const std::string& o : a.outs) outs += fs::absolute(o).string() + "\n";
    c.set("outputs", outs);
    c.set("exposure", fmt::format("{}", a.exposure));
    c.set("luminance", a.luminance_out.empty() ? "" : fs::absolute(a.luminance_out).string());
    c.set("falsecolor", a.falsecolor_out.empty() ? "" : fs::absolute(a.falsecolor_out).string());
    c.set_number("checkpoint-every", a.checkpoint_every);
    return c;
}

/// `render --resume FILE`: the options the command line leaves out come from the checkpoint
/// (`given` says which it gave).
void complete_from_checkpoint(RenderArgs& a, const sr::Checkpoint& c,
                              const std::function<bool(const char*)>& given) {
    if (c.get("kind") != "render")
        throw sr::Error(fmt::format("checkpoint {} is a {} checkpoint, not a render's", c.path(),
                                    c.get("kind")));
    if (a.scene.empty()) a.scene = c.get("scene");
    if (!given("--output")) {
        a.outs.clear();
        std::string outs = c.get("outputs");
        for (size_t p = 0, nl; (nl = outs.find('\n', p)) != std::string::npos; p = nl + 1)
            a.outs.push_back(outs.substr(p, nl - p));
    }
    if (!given("--spp")) a.spp = int(std::stoi(c.get("samples-per-pixel")));
    if (!given("--seed")) a.seed = std::stoull(c.get("seed"));
    if (!given("--exposure")) a.exposure = float(c.get_double("exposure"));
    if (!given("--luminance")) a.luminance_out = c.get("luminance");
    if (!given("--falsecolor")) a.falsecolor_out = c.get("falsecolor");
    if (!given("--checkpoint-every")) a.checkpoint_every = c.get_double("checkpoint-every");
    if (a.checkpoint.empty()) a.checkpoint = a.resume;
}

int run_render(RenderArgs a, const std::function<bool(const char*)>& given) {
    auto wall0 = std::chrono::steady_clock::now();
    std::optional<sr::Checkpoint> resume;
    if (!a.resume.empty()) {
        resume = sr::Checkpoint::load(a.resume);
        complete_from_checkpoint(a, *resume, given);
    }
    if (a.scene.empty()) throw sr::Error("render: a scene file is required (or --resume)");
    sr::SceneDesc desc = sr::parse_pbrt_file(a.scene);
    sr::BuildOptions bo;
    bo.spp_override = a.spp;
    sr::Scene scene = sr::build_scene(desc, bo);
    double load_wall =
        std::chrono::duration<double>(std::chrono::steady_clock::now() - wall0).count();
    std::vector<std::string>& outs = a.outs;
    if (outs.empty()) outs.push_back(scene.film.filename);
    // Every output is checked before rendering, not found unwritable after it.
    std::filesystem::path meters_json(outs.front());
    meters_json.replace_extension(".meters.json");
    if (!is_worker()) {
        for (const std::string& out : outs) sr::check_image_output(out, scene.film.output_channels());
        if (!a.luminance_out.empty()) sr::check_image_output(a.luminance_out, 1);
        if (!a.falsecolor_out.empty()) sr::check_image_output(a.falsecolor_out);
        if (!a.checkpoint.empty()) sr::check_output_path(a.checkpoint, "the checkpoint");
        if (!scene.meters.empty())
            sr::check_output_path(meters_json.string(), "the meters' readings");
        if (!a.radiosity_mesh.empty()) {
            if (scene.integrator.type != "radiosity")
                throw sr::Error(fmt::format("--radiosity-mesh: the scene's integrator is \"{}\", "
                                            "not \"radiosity\"", scene.integrator.type));
            sr::check_output_path(a.radiosity_mesh, "--radiosity-mesh");
        }
    }
    // Integrator "radiosity": every process solves the system (the same one: the solve is
    // deterministic, and start_distributed checks the solutions' hashes).
    std::unique_ptr<sr::RadiositySolution> radiosity;
    if (scene.integrator.type == "radiosity")
        radiosity =
            solve_radiosity_for(scene, a.threads, a.radiosity_mesh, a.quiet || is_worker());
    if (const int status = start_distributed(scene, a.threads, radiosity.get()); status >= 0)
        return status;
    std::optional<sr::WorkCoordinator> coord = make_coordinator();
    sr::Film film(scene.film);
    sr::RenderOptions ro;
    ro.spp = a.spp;
    ro.threads = a.threads;
    ro.seed = a.seed;
    ro.time_budget = a.time_budget;
    ro.progress = !a.quiet && isatty(STDERR_FILENO);
    ro.stop = &g_stop;
    ro.radiosity = radiosity.get();
    ro.distribute = coord ? &*coord : nullptr;
    const int total_spp = sr::render_samples_per_pixel(scene, ro);
    std::string exe, digest;
    if (resume || !a.checkpoint.empty()) {
        exe = sr::executable_id();
        digest = sr::inputs_digest();
    }
    sr::RenderStats resumed;
    if (resume) {
        resume->expect("executable", exe, "another build of steradian (executable hash)",
                       "a render resumes only with the build that started it");
        resume->expect("scene-digest", digest, "a scene whose files hash to",
                       "the scene or a file it reads has changed since");
        resume->expect("samples-per-pixel", std::to_string(total_spp), "samples per pixel",
                       "resume with the sample count it was started with");
        resume->expect("seed", std::to_string(a.seed), "--seed");
        resumed = sr::get_render_state(*resume, film);
        ro.resume = &resumed;
        if (!a.quiet)
            std::fprintf(stderr, "steradian: resuming %s at %d of %d samples per pixel\n",
                         a.resume.c_str(), resumed.spp, total_spp);
    }
    if (!a.checkpoint.empty()) {
        const sr::Checkpoint base = render_checkpoint(a, exe, digest, total_spp);
        ro.checkpoint_every = a.checkpoint_every;
        ro.checkpoint = [&, base](const sr::RenderStats& so_far) {
            sr::Checkpoint c = base;
            sr::put_render_state(c, film, so_far);
            c.save(a.checkpoint);
        };
    }
    sr::RenderStats st = sr::render(scene, film, ro);
    const bool quiet = a.quiet;
    const float exposure = a.exposure;
    const std::string& luminance_out = a.luminance_out;
    const std::string& falsecolor_out = a.falsecolor_out;
    const int threads = a.threads;
    const uint64_t seed = a.seed;
    const double time_budget = a.time_budget;
    sr::WriteOptions wo;
    wo.exposure = exposure;
    wo.half_float = scene.film.half_float;
    sr::Image image = film.output_image();
    for (const std::string& out : outs) {
        sr::write_image(out, image, wo);
        if (!quiet)
            std::fprintf(stderr, "steradian: wrote %s (%dx%d)\n", out.c_str(), scene.film.width(),
                         scene.film.height());
    }
    // bdpt's visualizestrategies / visualizeweights images, beside the first output.
    for (const auto& [name, img] : st.strategy_images) {
        const std::string path =
            (std::filesystem::path(outs.front()).parent_path() / name).string();
        sr::write_image(path, img, wo);
        if (!quiet) std::fprintf(stderr, "steradian: wrote %s\n", path.c_str());
    }
    if (!quiet) {
        std::fprintf(stderr, "  scene load      %.2f s\n", load_wall);
        std::fprintf(stderr, "  wall time       %.2f s\n", st.wall_seconds);
        std::fprintf(stderr, "  CPU time        %.2f s\n", st.cpu_seconds);
        std::fprintf(stderr, "  samples/pixel   %d%s\n", st.spp,
                     st.time_limited  ? " (stopped by the --time budget)"
                     : st.interrupted ? " (interrupted)"
                                      : "");
        std::fprintf(stderr, "  camera paths/s  %s\n",
                     human_rate(double(st.camera_paths) / st.wall_seconds).c_str());
        std::fprintf(stderr, "  rays/s          %s\n",
                     human_rate(double(st.rays) / st.wall_seconds).c_str());
        std::fprintf(stderr, "  peak memory     %s\n", human_bytes(st.peak_rss_bytes).c_str());
        std::fprintf(stderr, "  NaN/Inf samples %llu discarded\n",
                     (unsigned long long)st.nonfinite);
        if (st.dist_splats > 0)
            std::fprintf(stderr, "  splats          %llu added in a fixed order in %.2f CPU s; %s of "
                         "splat lists from the other processes\n",
                         (unsigned long long)st.dist_splats, st.dist_splat_seconds,
                         human_bytes(size_t(st.dist_splat_bytes)).c_str());
    } else if (st.time_limited) {
        std::fprintf(stderr, "steradian: time budget reached after %d samples per pixel\n", st.spp);
    }
    if (st.interrupted)
        std::fprintf(stderr, "steradian: interrupted: the image has the %d completed samples per "
                     "pixel\n", st.spp);
    if (!a.checkpoint.empty() && st.spp < total_spp)
        std::fprintf(stderr, "steradian: checkpoint %s holds them; continue with: steradian "
                     "render --resume %s\n", a.checkpoint.c_str(), a.checkpoint.c_str());
    if (st.nonfinite > 0)
        std::fprintf(stderr, "warning: %llu samples were NaN or infinite and were zeroed\n",
                     (unsigned long long)st.nonfinite);
    if (!luminance_out.empty() || !falsecolor_out.empty()) {
        // Luminance in cd/m^2: the sensor's Y without the imaging ratio.
        sr::Image y;
        y.width = scene.film.width();
        y.height = scene.film.height();
        y.channels = 1;
        for (double v : film.luminance()) y.data.push_back(float(v / scene.film.imaging_ratio));
        if (!luminance_out.empty()) {
            sr::write_image(luminance_out, y);
            if (!quiet)
                std::fprintf(stderr, "steradian: wrote %s (luminance, cd/m2)\n", luminance_out.c_str());
        }
        if (!falsecolor_out.empty()) {
            sr::write_image(falsecolor_out, sr::false_color(y, {}));
            if (!quiet)
                std::fprintf(stderr, "steradian: wrote %s (false-colour luminance)\n",
                             falsecolor_out.c_str());
        }
    }
    if (!scene.meters.empty()) {
        sr::MeasureOptions mo;
        mo.radiosity = radiosity.get();
        mo.threads = threads;
        mo.seed = seed;
        mo.stop = &g_stop;
        mo.distribute = coord ? &*coord : nullptr;
        if (time_budget > 0) {
            // The budget covers the meters too: they get what the image left (at least their
            // pilot round, so that every reading has a standard error).
            double used =
                std::chrono::duration<double>(std::chrono::steady_clock::now() - wall0).count();
            mo.time_budget = std::max(time_budget - used, 1e-3);
        }
        sr::MeasureResult r = sr::measure(scene, mo);
        sr::write_text_file(meters_json.string(), sr::meters_json(r));
        if (!quiet) {
            std::fprintf(stderr, "steradian: wrote %s\n", meters_json.string().c_str());
            print_measure_summary(r);
        }
    }
    print_distributed_summary(coord, quiet);
    return exit_status();
}

/// `steradian check`: the most unsupported features and unknown parameters listed per scene
/// (render stops at kMaxReportedUnsupported; a check wants them all).
constexpr size_t kCheckMaxUnsupported = 1000;

/// What `steradian check` found for one scene.
struct SceneCheck {
    std::string scene;
    bool ok = false;
    bool truncated = false;  ///< the builder stopped at kCheckMaxUnsupported
    std::vector<sr::ErrorEntry> errors, warnings;
    size_t shapes = 0, triangles = 0, instances = 0, lights = 0, materials = 0, textures = 0;
    double seconds = 0;  ///< parse and build, wall time
};

SceneCheck check_scene(const std::string& path) {
    SceneCheck c;
    c.scene = path;
    sr::WarningCapture capture;
    const auto t0 = std::chrono::steady_clock::now();
    try {
        sr::SceneDesc desc = sr::parse_pbrt_file(path);
        sr::BuildOptions bo;
        bo.max_unsupported = kCheckMaxUnsupported;
        sr::Scene scene = sr::build_scene(desc, bo);
        c.ok = true;
        c.shapes = scene.shapes.size();
        for (const sr::ShapeEntry& s : scene.shapes)
            if (const auto* m = std::get_if<sr::TriangleMesh>(&s.geometry))
                c.triangles += m->num_triangles();
        c.instances = scene.instances.size();
        c.lights = scene.lights.size();
        c.materials = scene.materials.size();
        c.textures = scene.float_textures.size() + scene.spectrum_textures.size();
    } catch (const sr::ErrorList& e) {
        c.errors = e.entries();
        c.truncated = e.truncated();
    } catch (const sr::Error& e) {
        c.errors = sr::error_entries(e);
    } catch (const std::exception& e) {
        sr::ErrorEntry entry;  // no location: not an input error
        entry.message = e.what();
        c.errors.push_back(std::move(entry));
    }
    c.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    // Each distinct warning once, in the order first given.
    std::set<std::string> seen;
    for (sr::ErrorEntry& w : capture.take())
        if (seen.insert(w.loc.to_string() + w.message).second) c.warnings.push_back(std::move(w));
    return c;
}

std::string located(const sr::ErrorEntry& e) {
    return sr::terminal_safe(e.loc.file.empty() ? e.message : e.loc.to_string() + ": " + e.message);
}

void print_check(const SceneCheck& c, bool quiet) {
    if (c.ok) {
        std::printf(
            "%s: ok: %zu shapes (%zu triangles), %zu instances, %zu lights, %zu "
            "materials, %zu textures; parsed and built in %.2f s\n",
            sr::terminal_safe(c.scene).c_str(), c.shapes, c.triangles, c.instances, c.lights,
            c.materials, c.textures, c.seconds);
    } else {
        size_t unsupported = 0;
        for (const sr::ErrorEntry& e : c.errors) unsupported += e.unsupported ? 1 : 0;
        std::printf("%s: FAILED: %zu %s (%zu unsupported features or unknown parameters%s)\n",
                    sr::terminal_safe(c.scene).c_str(), c.errors.size(),
                    c.errors.size() == 1 ? "error" : "errors", unsupported,
                    c.truncated
                        ? fmt::format("; stopped at the first {}", kCheckMaxUnsupported).c_str()
                        : "");
        for (const sr::ErrorEntry& e : c.errors)
            std::printf("  %s%s\n",
                        e.unsupported ? "unsupported: " : "error: ", located(e).c_str());
    }
    if (!quiet)
        for (const sr::ErrorEntry& w : c.warnings)
            std::printf("  warning: %s\n", located(w).c_str());
}

nlohmann::ordered_json entries_json(const std::vector<sr::ErrorEntry>& entries, bool kind) {
    nlohmann::ordered_json a = nlohmann::ordered_json::array();
    for (const sr::ErrorEntry& e : entries) {
        nlohmann::ordered_json j;
        j["file"] = e.loc.file;
        j["line"] = e.loc.line;
        j["column"] = e.loc.column;
        j["message"] = e.message;
        if (kind) j["unsupported"] = e.unsupported;
        a.push_back(std::move(j));
    }
    return a;
}

std::string checks_json(const std::vector<SceneCheck>& checks) {
    nlohmann::ordered_json root;
    size_t ok = 0;
    nlohmann::ordered_json scenes = nlohmann::ordered_json::array();
    for (const SceneCheck& c : checks) {
        ok += c.ok ? 1 : 0;
        nlohmann::ordered_json j;
        j["scene"] = c.scene;
        j["ok"] = c.ok;
        j["seconds"] = c.seconds;
        if (c.ok)
            j["summary"] = {{"shapes", c.shapes},       {"triangles", c.triangles},
                            {"instances", c.instances}, {"lights", c.lights},
                            {"materials", c.materials}, {"textures", c.textures}};
        j["errors"] = entries_json(c.errors, true);
        j["errors_truncated"] = c.truncated;
        j["warnings"] = entries_json(c.warnings, false);
        scenes.push_back(std::move(j));
    }
    root["scenes_ok"] = ok;
    root["scenes"] = checks.size();
    root["results"] = std::move(scenes);
    // Invalid UTF-8 in a file name or message is replaced, not thrown on.
    return root.dump(2, ' ', false, nlohmann::ordered_json::error_handler_t::replace) + "\n";
}

struct CheckArgs {
    std::vector<std::string> scenes;
    std::string json;
    bool quiet = false;
};

int run_check(const CheckArgs& a) {
    if (!a.json.empty()) sr::check_output_path(a.json, "--json");
    std::vector<SceneCheck> checks;
    size_t ok = 0;
    for (const std::string& path : a.scenes) {
        checks.push_back(check_scene(path));
        ok += checks.back().ok ? 1 : 0;
        print_check(checks.back(), a.quiet);
        std::fflush(stdout);
    }
    if (checks.size() > 1) std::printf("%zu of %zu scenes parse and build\n", ok, checks.size());
    if (!a.json.empty()) sr::write_text_file(a.json, checks_json(checks));
    return ok == checks.size() ? 0 : 1;
}

}  // namespace

/// Reports an error and gives the exit status. Distributed, a load error is reported once
/// (by process 0 when every process has it, else by each process that has it, with its
/// number), and a worker's error once the work has started ends the job.
int fail(const std::string& what) {
    std::string prefix = "error: ";
#ifdef STERADIAN_MPI
    if (g_size > 1) {
        if (!g_dist_started) {
            const int n = g_mpi->count_failed(true);
            if (n == g_size && is_worker()) return 1;
            if (n < g_size) prefix = fmt::format("error (process {} of {}): ", g_rank, g_size);
        } else if (is_worker()) {
            std::fprintf(stderr, "error (process %d of %d): %s\n", g_rank, g_size,
                         sr::terminal_safe(what).c_str());
            g_mpi->abort(1);
        }
    }
#endif
    std::fprintf(stderr, "%s%s\n", prefix.c_str(), sr::terminal_safe(what).c_str());
    return 1;
}

int main(int argc, char** argv) {
#ifdef STERADIAN_MPI
    sr::mpi::Session mpi(argc, argv);
    g_mpi = &mpi;
    g_rank = mpi.rank();
    g_size = mpi.size();
#endif
    CLI::App app{"steradian: a spectral, physically based renderer and lighting simulator"};
    app.set_version_flag("--version", std::string("steradian ") + STERADIAN_VERSION);
    app.require_subcommand(1);

    auto* render = app.add_subcommand("render", "Render a pbrt-v4 scene to an image");
    RenderArgs ra;
    render->add_option("scene", ra.scene, "pbrt-v4 scene file (with --resume: the checkpoint's)");
    render->add_option("-o,--output", ra.outs,
                       "output image (.exr linear float, .pfm, .png 8-bit sRGB); may be given "
                       "several times; default: the Film's filename")
        ->allow_extra_args(false)
        ->take_all();
    render->add_option("--spp", ra.spp, "samples per pixel (default: the scene's Sampler)")
        ->check(CLI::Range(1, sr::kMaxSamplesPerPixel));
    render->add_option("--threads", ra.threads, "worker threads (default: all cores)")
        ->check(CLI::Range(0, kMaxThreads));
    render->add_option("--seed", ra.seed, "random seed added to the scene's sampler seed")
        ->check(kSeed);
    render->add_option("--time", ra.time_budget,
                       "time budget in seconds: stop after the last full pass within it (at "
                       "least one pass of 1 sample per pixel is always completed)")
        ->check(kFinite & CLI::NonNegativeNumber);
    render->add_option("--exposure", ra.exposure, "exposure in stops for 8-bit outputs (PNG)")
        ->check(kFinite & CLI::Range(-126.0, 127.0));
    render->add_flag("-q,--quiet", ra.quiet, "no progress bar or summary");
    render->add_option("--luminance", ra.luminance_out,
                       "also write the luminance image in cd/m2 (single-channel .exr)");
    render->add_option("--falsecolor", ra.falsecolor_out,
                       "also write a false-colour image of luminance with a labelled scale (.png)");
    render->add_option("--checkpoint", ra.checkpoint,
                       "save the render's state to this file at pass boundaries (atomically), "
                       "so that --resume can continue it after an interruption or a crash");
    render->add_option("--checkpoint-every", ra.checkpoint_every,
                       "seconds between checkpoints (default 0: at every pass boundary; passes "
                       "are sized to end about this often)")
        ->check(kFinite & CLI::NonNegativeNumber);
    render->add_option("--resume", ra.resume,
                       "continue the render saved in this checkpoint: same scene, samples per "
                       "pixel and seed, identical image; options not given come from it, and it "
                       "is updated as the render goes on");
    render->add_option("--radiosity-mesh", ra.radiosity_mesh,
                       "Integrator \"radiosity\": also write the solved mesh (.ply, per-vertex "
                       "colours)");

    auto* measure = app.add_subcommand(
        "measure", "Compute the scene's Meter readings (lx, W/m2, cd/m2) with standard errors");
    MeasureArgs margs;
    measure->add_option("scene", margs.scene,
                        "pbrt-v4 scene file with Meter directives (with --resume: the checkpoint's)");
    measure->add_option("--json", margs.json, "write the readings as JSON");
    measure->add_option("--csv", margs.csv, "write the readings as CSV");
    measure->add_option("--rel-error", margs.rel_error,
                        "target relative standard error of every value (default 0.001)")
        ->check(kFinite & CLI::PositiveNumber);
    measure->add_option("--time", margs.time_budget,
                        "time budget in seconds: report what is reached by then")
        ->check(kFinite & CLI::NonNegativeNumber);
    measure->add_option("--threads", margs.threads, "worker threads (default: all cores)")
        ->check(CLI::Range(0, kMaxThreads));
    measure->add_option("--seed", margs.seed, "random seed")->check(kSeed);
    measure->add_option("--falsecolor", margs.falsecolor,
                        "write false-colour images of the grid meters with a labelled scale (.png)");
    measure->add_option("--report", margs.report,
                        "write a lighting designer's report: one self-contained HTML page with "
                        "the luminaires' data and polar plots, each grid's figures, false-colour "
                        "and isolux plans, and the method's accuracy");
    measure->add_flag("-q,--quiet", margs.quiet, "no summary on stderr");
    measure->add_option("--method", margs.method,
                        "auto (default: radiosity if every surface is diffuse or the scene's "
                        "Integrator is \"radiosity\", else path), path, radiosity, or light "
                        "(cell-averaged illuminance grids by light tracing, every cell at once; "
                        "other meters by path)")
        ->check(CLI::IsMember({"auto", "path", "radiosity", "light"}));
    measure->add_option("--replicas", margs.replicas,
                        "independent replicas per value, whose spread gives the standard error "
                        "(default 32)")
        ->check(CLI::Range(2, 1024));
    measure->add_option("--pilot-samples", margs.pilot_samples,
                        "samples per replica of the pilot round (a power of two, default 32)")
        ->check(CLI::Range(1, 1 << 16));
    measure->add_flag("--sampled-direct", margs.sampled_direct,
                      "direct light by Monte Carlo like the rest, instead of exactly (delta "
                      "lights) and by quadrature (area lights)");
    measure->add_option("--radiosity-mesh", margs.radiosity_mesh,
                        "with the radiosity method: write the solved mesh (.ply, per-vertex colours)");
    measure->add_option("--checkpoint", margs.checkpoint,
                        "save the measurement's state to this file as it goes (atomically), so "
                        "that --resume can continue it after an interruption or a crash");
    measure->add_option("--checkpoint-every", margs.checkpoint_every,
                        "seconds between checkpoints (default 0: after every batch of work)")
        ->check(kFinite & CLI::NonNegativeNumber);
    measure->add_option("--resume", margs.resume,
                        "continue the measurement saved in this checkpoint: same scene, target and "
                        "seed, identical readings; options not given come from it");

    auto* check = app.add_subcommand(
        "check",
        "Parse and build scenes without rendering; report every error, unsupported "
        "feature and warning with its file:line:col (exit 0 only if all build)");
    CheckArgs ca;
    check->add_option("scenes", ca.scenes, "pbrt-v4 scene files")->required();
    check->add_option("--json", ca.json,
                      "also write the results as JSON (per scene: ok, errors and warnings with "
                      "their locations, the summary)");
    check->add_flag("-q,--quiet", ca.quiet, "no warnings on stdout (the JSON keeps them)");

    try {
        app.parse(argc, argv);
    } catch (const CLI::ParseError& e) {
        if (is_worker()) {  // process 0 says it
            std::ostringstream sink;
            return app.exit(e, sink, sink);
        }
        return app.exit(e);
    }
    // Under mpirun a signal ends every process (Open MPI forwards it, then kills the job):
    // no process could finish a pass, so none says it will (docs/distributed.md).
    if (g_size <= 1) install_signal_handlers();
    try {
        if (*render) {
            if (ra.scene.empty() && ra.resume.empty())
                throw sr::Error("render: a scene file is required (or --resume CHECKPOINT)");
            return run_render(ra, [&](const char* name) { return render->count(name) > 0; });
        }
        if (*measure) {
            if (margs.scene.empty() && margs.resume.empty())
                throw sr::Error("measure: a scene file is required (or --resume CHECKPOINT)");
            return run_measure(margs, [&](const char* name) { return measure->count(name) > 0; });
        }
        if (*check) return is_worker() ? 0 : run_check(ca);  // not shared: process 0 checks
    } catch (const std::exception& e) {
        return fail(e.what());
    }
    return 0;
}
