// Feeds arbitrary bytes to the pbrt reader (parse_pbrt_string, scene/pbrt/parser.h) as the
// text of a scene file, and checks the SceneDesc of an accepted scene: every number of every
// parameter is finite and within the range of a float.
#include <limits>

#include "fuzz_target.h"
#include "steradian/scene/pbrt/parser.h"

namespace {

void check_params(const sr::ParamSet& ps) {
    for (const sr::Param& p : ps.params())
        for (double x : p.numbers)
            sr::fuzz::fuzz_check(std::abs(x) <= double(std::numeric_limits<float>::max()),
                                 "a parameter value is not a finite float");
}

void check_scene(const sr::SceneDesc& d) {
    for (const sr::EntityDesc* e : {static_cast<const sr::EntityDesc*>(&d.camera), &d.film,
                                    &d.sampler, &d.integrator, &d.filter, &d.accelerator})
        check_params(e->params);
    check_params(d.options);
    for (const auto& m : d.materials) check_params(m.params);
    for (const auto& t : d.float_textures) check_params(t.params);
    for (const auto& t : d.spectrum_textures) check_params(t.params);
    for (const auto& l : d.lights) check_params(l.params);
    for (const auto& a : d.area_lights) check_params(a.params);
    for (const auto& s : d.shapes) check_params(s.params);
    for (const auto& [name, def] : d.instances)
        for (const auto& s : def.shapes) check_params(s.params);
    for (const auto& m : d.meters) check_params(m.params);
}

}  // namespace

STERADIAN_FUZZ_TARGET(pbrt_parser) {
    // Include and Import resolve against a directory of the project's test scenes, so
    // that inputs can reach the files those scenes use.
    static const std::string base_dir = STERADIAN_SOURCE_DIR "/tests/data/identical";
    const std::string name = "fuzz.pbrt";
    try {
        check_scene(sr::parse_pbrt_string(std::string(input), name, base_dir));
    } catch (const sr::Error& e) {
        sr::fuzz::note_rejection(e);
        // Every error of the reader is located at file:line:col (the file may be one that
        // the input Includes).
        sr::fuzz::fuzz_check(!e.loc().file.empty() && e.loc().line >= 1 && e.loc().column >= 1,
                             "a parse error without file:line:col");
    }
}
