// steradian command line: `steradian render SCENE.pbrt [options]`.
#include <unistd.h>

#include <CLI/CLI.hpp>
#include <cstdio>
#include <filesystem>
#include <iostream>

#include "steradian/core/error.h"
#include "steradian/film/film.h"
#include "steradian/integrators/integrator.h"
#include "steradian/scene/build.h"
#include "steradian/scene/pbrt/parser.h"

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

int run_render(const std::string& scene_path, std::vector<std::string> outs, int spp, int threads,
               uint64_t seed, double time_budget, bool quiet, float exposure) {
    auto wall0 = std::chrono::steady_clock::now();
    sr::SceneDesc desc = sr::parse_pbrt_file(scene_path);
    sr::BuildOptions bo;
    bo.spp_override = spp;
    sr::Scene scene = sr::build_scene(desc, bo);
    double load_wall =
        std::chrono::duration<double>(std::chrono::steady_clock::now() - wall0).count();
    if (outs.empty()) outs.push_back(scene.film.filename);
    sr::Film film(scene.film);
    sr::RenderOptions ro;
    ro.spp = spp;
    ro.threads = threads;
    ro.seed = seed;
    ro.time_budget = time_budget;
    ro.progress = !quiet && isatty(STDERR_FILENO);
    sr::RenderStats st = sr::render(scene, film, ro);
    sr::WriteOptions wo;
    wo.exposure = exposure;
    wo.half_float = scene.film.half_float;
    sr::Image image = film.rgb_image();
    for (const std::string& out : outs) {
        sr::write_image(out, image, wo);
        if (!quiet)
            std::fprintf(stderr, "steradian: wrote %s (%dx%d)\n", out.c_str(), scene.film.width(),
                         scene.film.height());
    }
    if (!quiet) {
        std::fprintf(stderr, "  scene load      %.2f s\n", load_wall);
        std::fprintf(stderr, "  wall time       %.2f s\n", st.wall_seconds);
        std::fprintf(stderr, "  CPU time        %.2f s\n", st.cpu_seconds);
        std::fprintf(stderr, "  samples/pixel   %d%s\n", st.spp,
                     st.time_limited ? " (stopped by the --time budget)" : "");
        std::fprintf(stderr, "  camera paths/s  %s\n",
                     human_rate(double(st.camera_paths) / st.wall_seconds).c_str());
        std::fprintf(stderr, "  rays/s          %s\n",
                     human_rate(double(st.rays) / st.wall_seconds).c_str());
        std::fprintf(stderr, "  peak memory     %s\n", human_bytes(st.peak_rss_bytes).c_str());
        std::fprintf(stderr, "  NaN/Inf samples %llu discarded\n",
                     (unsigned long long)st.nonfinite);
    } else if (st.time_limited) {
        std::fprintf(stderr, "steradian: time budget reached after %d samples per pixel\n", st.spp);
    }
    if (st.nonfinite > 0)
        std::fprintf(stderr, "warning: %llu samples were NaN or infinite and were zeroed\n",
                     (unsigned long long)st.nonfinite);
    return 0;
}

}  // namespace

int main(int argc, char** argv) {
    CLI::App app{"steradian: a spectral, physically based renderer and lighting simulator"};
    app.set_version_flag("--version", std::string("steradian ") + STERADIAN_VERSION);
    app.require_subcommand(1);

    auto* render = app.add_subcommand("render", "Render a pbrt-v4 scene to an image");
    std::string scene;
    std::vector<std::string> outs;
    int spp = 0, threads = 0;
    uint64_t seed = 0;
    double time_budget = 0;
    bool quiet = false;
    float exposure = 0;
    render->add_option("scene", scene, "pbrt-v4 scene file")->required();
    render->add_option("-o,--output", outs,
                       "output image (.exr linear float, .pfm, .png 8-bit sRGB); may be given "
                       "several times; default: the Film's filename")
        ->allow_extra_args(false)
        ->take_all();
    render->add_option("--spp", spp, "samples per pixel (default: the scene's Sampler)")
        ->check(CLI::PositiveNumber);
    render->add_option("--threads", threads, "worker threads (default: all cores)")
        ->check(CLI::NonNegativeNumber);
    render->add_option("--seed", seed, "random seed added to the scene's sampler seed");
    render->add_option("--time", time_budget,
                       "time budget in seconds: stop after the last full pass within it")
        ->check(CLI::NonNegativeNumber);
    render->add_option("--exposure", exposure, "exposure in stops for 8-bit outputs (PNG)");
    render->add_flag("-q,--quiet", quiet, "no progress bar or summary");

    try {
        app.parse(argc, argv);
    } catch (const CLI::ParseError& e) {
        return app.exit(e);
    }
    try {
        if (*render) return run_render(scene, outs, spp, threads, seed, time_budget, quiet, exposure);
    } catch (const sr::Error& e) {
        std::fprintf(stderr, "error: %s\n", e.what());
        return 1;
    } catch (const std::exception& e) {
        std::fprintf(stderr, "error: %s\n", e.what());
        return 1;
    }
    return 0;
}
