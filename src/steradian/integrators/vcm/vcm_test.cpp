// Integrator "vcm": its parameters, the located errors of bad ones, what it refuses, its time
// budget. (The estimator itself: tests/analytic/vcm_test.cpp.)
#include <gtest/gtest.h>

#include <cmath>
#include <string>

#include "steradian/core/error.h"
#include "steradian/film/film.h"
#include "steradian/integrators/integrator.h"
#include "steradian/scene/build.h"
#include "steradian/scene/pbrt/parser.h"
#include "steradian/scene/scene.h"

namespace sr {
namespace {

std::string scene_with(const std::string& integrator, const std::string& camera = "") {
    return "Film \"rgb\" \"integer xresolution\" [ 8 ] \"integer yresolution\" [ 8 ]\n"
           "Sampler \"independent\" \"integer pixelsamples\" [ 2 ]\n" +
           integrator + "\n" + camera +
           "WorldBegin\n"
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

std::string render_error_of(const Scene& s, Film& film, RenderOptions ro = {}) {
    try {
        render(s, film, ro);
    } catch (const Error& e) {
        return e.what();
    }
    return "";
}

TEST(VcmParams, NamesAndDefaults) {
    const Scene d = build(scene_with("Integrator \"vcm\""));
    EXPECT_EQ(d.integrator.type, "vcm");
    EXPECT_EQ(d.integrator.max_depth, 5);
    EXPECT_EQ(d.integrator.vcm.radius, 0.0f);  // 0.003 x the scene's radius
    EXPECT_EQ(d.integrator.vcm.alpha, 0.75f);
    EXPECT_EQ(d.integrator.vcm.seed, 0);
    EXPECT_EQ(d.integrator.vcm.light_paths, -1);
    EXPECT_TRUE(d.integrator.vcm.connect);
    EXPECT_TRUE(d.integrator.vcm.merge);
    EXPECT_EQ(d.integrator.light_sampler, "power");
    const Scene s = build(scene_with(
        "Integrator \"vcm\" \"integer maxdepth\" [ 3 ] \"float radius\" [ 0.25 ] "
        "\"float radiusalpha\" [ 0.5 ] \"integer seed\" [ 7 ] \"bool vertexmerging\" false "
        "\"integer lightpathsperiteration\" [ 1000 ]"));
    EXPECT_EQ(s.integrator.max_depth, 3);
    EXPECT_EQ(s.integrator.vcm.radius, 0.25f);
    EXPECT_EQ(s.integrator.vcm.alpha, 0.5f);
    EXPECT_EQ(s.integrator.vcm.seed, 7);
    EXPECT_TRUE(s.integrator.vcm.connect);
    EXPECT_FALSE(s.integrator.vcm.merge);
    EXPECT_EQ(s.integrator.vcm.light_paths, 1000);
}

TEST(VcmParams, BadValuesAreLocated) {
    // Line 3 is the Integrator directive; the first parameter's declaration is at column 18.
    struct Case {
        const char* params;
        const char* where;
        const char* says;
    } cases[] = {
        {"\"float radius\" [ -1 ]", "<test>:3:18", "radius"},
        {"\"float radius\" [ inf ]", "<test>:3:", "radius"},
        {"\"float radiusalpha\" [ 0 ]", "<test>:3:18", "radiusalpha"},
        {"\"float radiusalpha\" [ 1.5 ]", "<test>:3:18", "radiusalpha"},
        {"\"integer maxdepth\" [ -1 ]", "<test>:3:18", "maxdepth"},
        {"\"bool vertexconnection\" false \"bool vertexmerging\" false", "<test>:3:", "both"},
        {"\"integer photonsperiteration\" [ 100 ]", "<test>:3:", "photonsperiteration"},
        {"\"string radius\" \"big\"", "<test>:3:", "radius"},
    };
    for (const Case& c : cases) {
        const std::string e = error_of(scene_with(std::string("Integrator \"vcm\" ") + c.params));
        EXPECT_NE(e.find(c.where), std::string::npos) << c.params << ": " << e;
        EXPECT_NE(e.find(c.says), std::string::npos) << c.params << ": " << e;
    }
}

TEST(VcmRender, RefusesWhatItCannotRender) {
    const Scene s = build(scene_with("Integrator \"vcm\""));
    // A film with channels besides the image.
    FilmParams fp = s.film;
    fp.kind = FilmKind::Spectral;
    Film spectral(fp);
    EXPECT_NE(render_error_of(s, spectral).find("\"rgb\" film"), std::string::npos);
    // Checkpoints.
    Film rgb(s.film);
    RenderOptions ro;
    ro.checkpoint = [](const RenderStats&) {};
    EXPECT_NE(render_error_of(s, rgb, ro).find("checkpoints"), std::string::npos);
    // A camera without importance.
    const Scene ortho = build(scene_with("Integrator \"vcm\"", "Camera \"orthographic\"\n"));
    Film f2(ortho.film);
    EXPECT_NE(render_error_of(ortho, f2).find("perspective"), std::string::npos);
    // An emissive participating medium (other media are traced: tests/analytic/
    // bidir_media_test.cpp).
    const std::string media =
        "Film \"rgb\" \"integer xresolution\" [ 8 ] \"integer yresolution\" [ 8 ]\n"
        "Integrator \"vcm\"\n"
        "MakeNamedMedium \"fog\" \"string type\" \"homogeneous\" \"rgb Le\" [ 1 1 1 ] "
        "\"float Lescale\" [ 1 ]\n"
        "MediumInterface \"\" \"fog\"\n"
        "Camera \"perspective\"\n"
        "WorldBegin\n"
        "LightSource \"point\" \"point3 from\" [ 0 0 1 ]\n";
    std::string e;
    try {
        const Scene m = build(media);
        Film f3(m.film);
        e = render_error_of(m, f3);
    } catch (const std::exception& ex) {
        e = ex.what();
    }
    EXPECT_NE(e.find("emissive participating media"), std::string::npos) << e;
}

// A time budget ends the render after a whole iteration (the first always completes), and the
// image is that of the iterations done.
TEST(VcmRender, TimeBudgetStopsAfterWholeIterations) {
    const Scene s = build(scene_with("Integrator \"vcm\" \"float radius\" [ 0.2 ]"));
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

}  // namespace
}  // namespace sr
