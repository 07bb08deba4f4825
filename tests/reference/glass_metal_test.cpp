// The glass-and-metal Cornell box (a dispersive BK7 sphere, a rough gold and a smooth
// silver sphere; tests/data/reference/cornell-box-glass-metal, pbrt-v4 commit 5f7a6068)
// against pbrt-v4's 1024-spp render: the materials issue asks for a region-by-region match
// within 1 %. Regions are the 16 blocks of 128 x 128 pixels. Rendered at 256 spp: the
// caustic paths through the glass sphere make 64-spp block means heavy-tailed (pbrt-v4's
// own 64-spp render misses its 1024-spp one by up to 1.7 % in the caustic block).
#include <gtest/gtest.h>

#include "steradian/film/image_io.h"
#include "support/render_util.h"

namespace sr::test {
namespace {

const std::string kData =
    std::string(STERADIAN_SOURCE_DIR) + "/tests/data/reference/cornell-box-glass-metal/";

double block_luminance(const Image& img, int bx, int by, int size) {
    double s = 0;
    for (int y = by; y < by + size; ++y)
        for (int x = bx; x < bx + size; ++x)
            s += 0.2126 * img.at(x, y, 0) + 0.7152 * img.at(x, y, 1) + 0.0722 * img.at(x, y, 2);
    return s / double(size * size);
}

TEST(GlassMetalBox, MatchesPbrtV4BlockByBlock) {
    Image ref = read_image(kData + "pbrt-v4-1024spp.exr");
    SceneDesc d = parse_pbrt_file(kData + "scene.pbrt");
    BuildOptions bo;
    bo.spp_override = 256;
    Scene s = build_scene(d, bo);
    Film film(s.film);
    RenderOptions ro;
    ro.spp = 256;
    RenderStats st = render(s, film, ro);
    EXPECT_EQ(st.nonfinite, 0u);
    Image ours = film.rgb_image();
    ASSERT_EQ(ours.width, ref.width);
    ASSERT_EQ(ours.height, ref.height);
    constexpr int B = 128;
    for (int by = 0; by + B <= ref.height; by += B)
        for (int bx = 0; bx + B <= ref.width; bx += B) {
            double a = block_luminance(ours, bx, by, B), b = block_luminance(ref, bx, by, B);
            std::printf("block (%3d, %3d) luminance ours/pbrt-v4 %.4f\n", bx, by, a / b);
            EXPECT_NEAR(a / b, 1.0, 0.01) << "block " << bx << "," << by;
        }
    std::printf("glass-metal box, 256 spp: %.1f CPU-s, %.1f s wall\n", st.cpu_seconds, st.wall_seconds);
}

}  // namespace
}  // namespace sr::test
