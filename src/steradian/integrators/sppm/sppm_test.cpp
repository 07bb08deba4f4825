// Integrator "sppm": its parameters as pbrt-v4's SPPMIntegrator::Create reads them, and the
// located errors of bad ones. (The estimator itself: tests/analytic/sppm_test.cpp.)
#include <gtest/gtest.h>

#include <atomic>
#include <string>

#include "steradian/core/error.h"
#include "steradian/film/film.h"
#include "steradian/integrators/integrator.h"
#include "steradian/scene/build.h"
#include "steradian/scene/pbrt/parser.h"
#include "steradian/scene/scene.h"

namespace sr {
namespace {

std::string scene_with(const std::string& integrator) {
    return "Film \"rgb\" \"integer xresolution\" [ 8 ] \"integer yresolution\" [ 8 ]\n"
           "Sampler \"independent\" \"integer pixelsamples\" [ 2 ]\n" +
           integrator +
           "\nWorldBegin\n"
           "LightSource \"point\" \"point3 from\" [ 0 0 1 ] \"float scale\" [ 10 ]\n"
           "Material \"diffuse\"\n"
           "Translate 0 0 4\n"
           "Shape \"sphere\" \"float radius\" [ 1 ]\n";
}

Scene build(const std::string& text) {
    return build_scene(parse_pbrt_string(text, "<test>", "."), {});
}

std::string error_of(const std::string& text) {
    try {
        build(text);
    } catch (const std::exception& e) {
        return e.what();
    }
    return "";
}

TEST(SppmParams, PbrtV4NamesAndDefaults) {
    const Scene d = build(scene_with("Integrator \"sppm\""));
    EXPECT_EQ(d.integrator.type, "sppm");
    EXPECT_EQ(d.integrator.max_depth, 5);
    EXPECT_EQ(d.integrator.sppm.photons_per_iteration, -1);
    EXPECT_EQ(d.integrator.sppm.radius, 1.0f);
    EXPECT_EQ(d.integrator.sppm.seed, 0);
    const Scene s = build(scene_with(
        "Integrator \"sppm\" \"integer maxdepth\" [ 3 ] \"integer photonsperiteration\" [ 1000 ] "
        "\"float radius\" [ 0.25 ] \"integer seed\" [ 7 ]"));
    EXPECT_EQ(s.integrator.max_depth, 3);
    EXPECT_EQ(s.integrator.sppm.photons_per_iteration, 1000);
    EXPECT_EQ(s.integrator.sppm.radius, 0.25f);
    EXPECT_EQ(s.integrator.sppm.seed, 7);
}

TEST(SppmParams, BadValuesAreLocated) {
    // Line 3 is the Integrator directive; the radius's declaration string is at column 19.
    std::string e = error_of(scene_with("Integrator \"sppm\" \"float radius\" [ -1 ]"));
    EXPECT_NE(e.find("<test>:3:19"), std::string::npos) << e;
    EXPECT_NE(e.find("radius"), std::string::npos) << e;
    e = error_of(scene_with("Integrator \"sppm\" \"integer maxdepth\" [ -1 ]"));
    EXPECT_NE(e.find("<test>:3:"), std::string::npos) << e;
    EXPECT_NE(e.find("maxdepth"), std::string::npos) << e;
    // pbrt-v3's iteration count: pbrt-v4 takes the Sampler's pixel samples.
    e = error_of(scene_with("Integrator \"sppm\" \"integer iterations\" [ 64 ]"));
    EXPECT_NE(e.find("<test>:3:19"), std::string::npos) << e;
    EXPECT_NE(e.find("pixelsamples"), std::string::npos) << e;
    // A parameter pbrt-v4's sppm does not read.
    e = error_of(scene_with("Integrator \"sppm\" \"bool regularize\" true"));
    EXPECT_NE(e.find("<test>:3:"), std::string::npos) << e;
    EXPECT_NE(e.find("regularize"), std::string::npos) << e;
    // A wrong type.
    e = error_of(scene_with("Integrator \"sppm\" \"string radius\" \"big\""));
    EXPECT_NE(e.find("<test>:3:"), std::string::npos) << e;
}

// A time budget ends the render after a whole iteration (the first always completes), and the
// image is that of the iterations done.
TEST(SppmRender, TimeBudgetStopsAfterWholeIterations) {
    std::string text = scene_with("Integrator \"sppm\" \"float radius\" [ 0.2 ]");
    const Scene s = build(text);
    Film film(s.film);
    RenderOptions ro;
    ro.threads = 1;
    ro.spp = 100000;
    ro.time_budget = 1e-9;
    const RenderStats st = render(s, film, ro);
    EXPECT_EQ(st.spp, 1);
    EXPECT_TRUE(st.time_limited);
    double sum = 0;
    for (float v : film.rgb_image().data) sum += v;
    EXPECT_GT(sum, 0);
}

TEST(SppmRender, RefusesWhatItCannotRender) {
    const Scene s = build(scene_with("Integrator \"sppm\""));
    FilmParams fp = s.film;
    fp.kind = FilmKind::Spectral;
    Film film(fp);
    RenderOptions ro;
    EXPECT_THROW(render(s, film, ro), Error);
    Film rgb(s.film);
    ro.checkpoint = [](const RenderStats&) {};
    EXPECT_THROW(render(s, rgb, ro), Error);
}

}  // namespace
}  // namespace sr
