// Feeds arbitrary bytes to the pbrt reader and, when it accepts them, builds the scene
// (parse_pbrt_string + build_scene: parameters, materials, textures, lights, meshes and the
// Embree structure; nothing is rendered). An accepted scene must have finite bounds, camera
// rays, light powers and selection probabilities, and film factors.
#include "fuzz_target.h"
#include "steradian/core/error_list.h"
#include "steradian/scene/build.h"
#include "steradian/scene/pbrt/parser.h"

namespace {

/// A "spectrum" "imagemap" texture builds the RGB-to-spectrum table, seconds (tens under
/// ASan) once per process: an input with one would take a short fuzzing run's whole time.
/// (Reading the image is OpenImageIO's work, not one of our readers.)
bool has_spectrum_imagemap(std::string_view s) {
    for (size_t i = s.find("\"imagemap\""); i != std::string_view::npos;
         i = s.find("\"imagemap\"", i + 1)) {
        size_t j = i;
        while (j > 0 && std::string_view(" \t\r\n").find(s[j - 1]) != std::string_view::npos) --j;
        if (s.substr(0, j).ends_with("\"spectrum\"")) return true;
    }
    return false;
}

void check_vec(sr::Vec3 v, const char* what) {
    sr::fuzz::check_finite(v.x, what);
    sr::fuzz::check_finite(v.y, what);
    sr::fuzz::check_finite(v.z, what);
}

void check_scene(const sr::Scene& s) {
    using sr::fuzz::check_finite;
    using sr::fuzz::fuzz_check;
    if (!s.bounds.empty()) {
        check_vec(s.bounds.lo, "scene bounds");
        check_vec(s.bounds.hi, "scene bounds");
    }
    fuzz_check(s.camera != nullptr, "no camera");
    fuzz_check(s.film.width() > 0 && s.film.height() > 0, "empty film");
    for (sr::Point2 p : {sr::Point2(0.5f, 0.5f),
                         sr::Point2(s.film.resolution.x * 0.5f, s.film.resolution.y * 0.5f),
                         sr::Point2(s.film.resolution.x - 0.5f, s.film.resolution.y - 0.5f)}) {
        sr::Ray r = s.camera->generate_ray(p, sr::Point2(0.5f, 0.5f));
        check_vec(sr::Vec3(r.o), "camera ray origin");
        check_vec(r.d, "camera ray direction");
    }
    check_finite(s.film.imaging_ratio, "film imaging ratio");
    for (const auto& row : s.film.rgb_from_sensor)
        for (sr::Float x : row) check_finite(x, "film colour matrix");
    for (size_t i = 0; i < s.lights.size(); ++i) {
        check_finite(sr::light_phi_y(s.lights[i]), "light power");
        if (!s.light_sampler.empty())
            check_finite(s.light_sampler.pmf(int(i)), "light selection probability");
    }
}

}  // namespace

STERADIAN_FUZZ_TARGET(scene_build) {
    // Files named by the input (Include, meshes, IES files, spectra, images) resolve against
    // a directory of the project's test scenes, which has one of each.
    static const std::string base_dir = STERADIAN_SOURCE_DIR "/tests/data/identical";
    const std::string name = "fuzz.pbrt";
    if (has_spectrum_imagemap(input)) return;
    sr::SceneDesc desc;
    try {
        desc = sr::parse_pbrt_string(std::string(input), name, base_dir);
    } catch (const sr::Error& e) {
        sr::fuzz::note_rejection(e);
        return;  // the pbrt_parser harness checks the reader's errors
    }
    try {
        check_scene(sr::build_scene(desc));
    } catch (const sr::Error& e) {
        sr::fuzz::note_rejection(e);
        // Errors of the builder are located at the directive or parameter (or name a file
        // the scene reads). Several at once come as an sr::ErrorList, which has no location
        // of its own: each of its entries must have one.
        for (const sr::ErrorEntry& entry : sr::error_entries(e))
            if (entry.loc.file.empty()) {
                std::fprintf(stderr, "build error without a location: %s\n",
                             entry.message.c_str());
                std::abort();
            }
    }
}
