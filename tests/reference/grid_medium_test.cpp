// Our render of a heterogeneous "uniformgrid" medium (chromatic scattering, g = 0.4, a
// blackbody glow under an Lescale grid; tests/data/reference/grid-medium, written by its
// make_scene.py) against pbrt-v4's own 4096-spp render of the same file (pbrt-v4 commit
// 5f7a6068, built outside the project: `pbrt --spp 4096 --outfile pbrt-v4-4096spp.exr
// scene.pbrt`).
// Criterion, per block of 8 x 8 pixels (256 blocks) and of 16 x 16 (64): the mean of the per-pixel luminance
// difference (ours - pbrt-v4) is within 4.5 of its standard errors of zero (the standard error
// from the spread of the difference inside the block, where the image's structure cancels and
// both renders' noise remains); where that noise allows it, the block means agree within 2 %.
// The whole image's luminance and RGB agree within 1 % and within 4.5 standard errors.
#include <gtest/gtest.h>

#include <cmath>

#include "steradian/film/image_io.h"
#include "support/render_util.h"

namespace sr::test {
namespace {

const std::string kData =
    std::string(STERADIAN_SOURCE_DIR) + "/tests/data/reference/grid-medium/";

double channel(const Image& img, int x, int y, int c) {
    if (c < 3) return img.at(x, y, c);
    return 0.2126 * img.at(x, y, 0) + 0.7152 * img.at(x, y, 1) + 0.0722 * img.at(x, y, 2);
}

TEST(GridMedium, MatchesPbrtV4InBlocksOf8x8Pixels) {
    Image ref = read_image(kData + "pbrt-v4-4096spp.exr");
    SceneDesc d = parse_pbrt_file(kData + "scene.pbrt");
    Scene s = build_scene(d);
    ASSERT_TRUE(s.integrator.volumetric);
    Film film(s.film);
    RenderOptions ro;
    ro.spp = 512;
    RenderStats st = render(s, film, ro);
    EXPECT_EQ(st.nonfinite, 0u);
    Image ours = film.rgb_image();
    ASSERT_EQ(ours.width, ref.width);
    ASSERT_EQ(ours.height, ref.height);
    // Blocks of 8 x 8 pixels (256) and an 8 x 8 grid of blocks of 16 x 16 pixels (64).
    for (const int block : {8, 16}) {
        const int nbx = ours.width / block, nby = ours.height / block;
        int checked_2pc = 0;
        double worst = 0;
        for (int by = 0; by < nby; ++by)
            for (int bx = 0; bx < nbx; ++bx) {
                std::vector<double> diff;
                double mo = 0, mr = 0;
                for (int y = by * block; y < (by + 1) * block; ++y)
                    for (int x = bx * block; x < (bx + 1) * block; ++x) {
                        double a = channel(ours, x, y, 3), b = channel(ref, x, y, 3);
                        diff.push_back(a - b);
                        mo += a, mr += b;
                    }
                mo /= double(diff.size());
                mr /= double(diff.size());
                MeanSe m = mean_se(diff);
                EXPECT_LE(std::abs(m.mean), 4.5 * m.se + 1e-6)
                    << block << "-pixel block (" << bx << ", " << by << "): ours " << mo
                    << " pbrt-v4 " << mr << " se " << m.se;
                if (mr > 0 && 4.5 * m.se < 0.02 * mr) {
                    ++checked_2pc;
                    EXPECT_NEAR(mo / mr, 1.0, 0.02) << block << "-pixel block (" << bx << ", "
                                                    << by << ")";
                    worst = std::max(worst, std::abs(mo / mr - 1));
                }
            }
        std::printf("%dx%d-pixel blocks: all %d within 4.5 standard errors; precise enough for "
                    "the 2 %% check: %d, largest deviation among them %.4f\n",
                    block, block, nbx * nby, checked_2pc, worst);
    }
    for (int c = 0; c < 4; ++c) {
        std::vector<double> diff;
        double mo = 0, mr = 0;
        for (int y = 0; y < ours.height; ++y)
            for (int x = 0; x < ours.width; ++x) {
                double a = channel(ours, x, y, c), b = channel(ref, x, y, c);
                diff.push_back(a - b);
                mo += a, mr += b;
            }
        MeanSe m = mean_se(diff);
        std::printf("%s: ours/pbrt-v4 %.4f (standard error of the difference %.4f relative)\n",
                    c == 3 ? "luminance" : c == 0 ? "R" : c == 1 ? "G" : "B", mo / mr,
                    m.se * double(diff.size()) / mr);
        EXPECT_LE(std::abs(m.mean), 4.5 * m.se) << "channel " << c;
        EXPECT_NEAR(mo / mr, 1.0, 0.01) << "channel " << c;
    }
}

}  // namespace
}  // namespace sr::test
