// The bundled scenes parse, build and render without NaN/Inf samples (small and fast: the
// images themselves are checked elsewhere, e.g. the Cornell box against pbrt-v4).
#include <gtest/gtest.h>

#include "steradian/film/film.h"
#include "steradian/integrators/integrator.h"
#include "steradian/scene/build.h"
#include "steradian/scene/pbrt/parser.h"

namespace sr::test {
namespace {

TEST(BundledScenes, MaterialsGalleryRendersCleanly) {
    SceneDesc d = parse_pbrt_file(std::string(STERADIAN_SOURCE_DIR) + "/scenes/materials.pbrt");
    Scene s = build_scene(d, {});
    Film film(s.film);
    RenderOptions ro;
    ro.spp = 2;
    ro.threads = 2;
    RenderStats st = render(s, film, ro);
    EXPECT_EQ(st.nonfinite, 0u);
    EXPECT_EQ(st.spp, 2);
    double sum = 0;
    for (double y : film.luminance()) sum += y;
    EXPECT_GT(sum, 0);
}

}  // namespace
}  // namespace sr::test
