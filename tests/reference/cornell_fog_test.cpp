// Our render of the Cornell box filled with fog (a homogeneous medium held by a closed
// interface box, Integrator "volpath") against pbrt-v4's own 512-spp render of the same file
// (tests/data/reference/cornell-box-fog, pbrt-v4 commit 5f7a6068).
// Criterion: in each of the 8 x 8 blocks of 32 x 32 pixels, the mean of the per-pixel
// luminance difference (ours - pbrt-v4) is within 4.5 of its standard errors of zero; the
// standard error comes from the spread of that difference inside the block, in which the
// image's structure cancels and both renders' noise remains. Where that noise allows (few
// blocks at 128 spp: the fog's noise is high), the block means must also agree within 2 %;
// the whole image's mean luminance and RGB must agree within 1 % and within 4.5 standard
// errors.
#include <gtest/gtest.h>

#include <cmath>

#include "steradian/film/image_io.h"
#include "support/render_util.h"

namespace sr::test {
namespace {

const std::string kData =
    std::string(STERADIAN_SOURCE_DIR) + "/tests/data/reference/cornell-box-fog/";

double luminance(const Image& img, int x, int y) {
    return 0.2126 * img.at(x, y, 0) + 0.7152 * img.at(x, y, 1) + 0.0722 * img.at(x, y, 2);
}

TEST(CornellBoxFog, MatchesPbrtV4BlockByBlock) {
    Image ref = read_image(kData + "pbrt-v4-512spp.exr");
    SceneDesc d = parse_pbrt_file(kData + "scene.pbrt");
    Scene s = build_scene(d);
    ASSERT_TRUE(s.integrator.volumetric);
    Film film(s.film);
    RenderOptions ro;
    ro.spp = 128;
    RenderStats st = render(s, film, ro);
    EXPECT_EQ(st.nonfinite, 0u);
    Image ours = film.rgb_image();
    ASSERT_EQ(ours.width, ref.width);
    ASSERT_EQ(ours.height, ref.height);
    constexpr int kBlocks = 8;
    const int bw = ours.width / kBlocks, bh = ours.height / kBlocks;
    int checked_2pc = 0;
    double worst = 0;
    for (int by = 0; by < kBlocks; ++by)
        for (int bx = 0; bx < kBlocks; ++bx) {
            std::vector<double> diff;
            double mo = 0, mr = 0;
            for (int y = by * bh; y < (by + 1) * bh; ++y)
                for (int x = bx * bw; x < (bx + 1) * bw; ++x) {
                    double a = luminance(ours, x, y), b = luminance(ref, x, y);
                    diff.push_back(a - b);
                    mo += a, mr += b;
                }
            mo /= double(diff.size());
            mr /= double(diff.size());
            MeanSe m = mean_se(diff);
            EXPECT_LE(std::abs(m.mean), 4.5 * m.se + 1e-6)
                << "block (" << bx << ", " << by << "): ours " << mo << " pbrt-v4 " << mr << " se "
                << m.se;
            if (mr > 0 && 4.5 * m.se < 0.02 * mr) {
                ++checked_2pc;
                EXPECT_NEAR(mo / mr, 1.0, 0.02) << "block (" << bx << ", " << by << ")";
                worst = std::max(worst, std::abs(mo / mr - 1));
            }
        }
    std::printf("blocks within 2 %% checked: %d of %d; largest deviation %.4f\n", checked_2pc,
                kBlocks * kBlocks, worst);
    for (int c = 0; c < 4; ++c) {
        std::vector<double> diff;
        double mo = 0, mr = 0;
        for (int y = 0; y < ours.height; ++y)
            for (int x = 0; x < ours.width; ++x) {
                double a = c == 3 ? luminance(ours, x, y) : ours.at(x, y, c);
                double b = c == 3 ? luminance(ref, x, y) : ref.at(x, y, c);
                diff.push_back(a - b);
                mo += a, mr += b;
            }
        MeanSe m = mean_se(diff);
        std::printf("%s: ours/pbrt-v4 %.4f (standard error of the difference %.4f relative)\n",
                    c == 3   ? "luminance"
                    : c == 0 ? "R"
                    : c == 1 ? "G"
                             : "B",
                    mo / mr, m.se * double(diff.size()) / mr);
        EXPECT_LE(std::abs(m.mean), 4.5 * m.se) << "channel " << c;
        EXPECT_NEAR(mo / mr, 1.0, 0.01) << "channel " << c;
    }
}

}  // namespace
}  // namespace sr::test
