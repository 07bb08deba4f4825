// The bidirectional and photon integrators (bdpt, lightpath, mlt, sppm, vcm) on the Cornell
// box against pbrt-v4's own 1024-spp render of it (tests/data/reference/cornell-box, pbrt-v4
// commit 5f7a6068, its path tracer at maxdepth 16, as here): the luminance of every wall and block region (the
// regions of cornell_box_test.cpp) within 1 % plus four standard errors of our region mean.
// Rendered at pbrt-v4's 512 x 512 (a region's mean depends on the resolution near its edges,
// through the pixel filter's width) with few samples per pixel, three seeds each; the
// standard error is the seeds' spread / sqrt(3).
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>

#include "steradian/film/image_io.h"
#include "support/block_stats.h"

namespace sr::test {
namespace {

const std::string kData = std::string(STERADIAN_SOURCE_DIR) + "/tests/data/reference/cornell-box/";

struct Region {
    const char* name;
    int x0, y0, x1, y1;  ///< pixels at 512 x 512, [x0, x1) x [y0, y1)
};
constexpr Region kRegions[] = {
    {"red wall", 25, 110, 85, 400},    {"green wall", 430, 110, 490, 400},
    {"back wall", 280, 110, 380, 300}, {"ceiling", 150, 20, 360, 50},
    {"floor", 110, 470, 400, 500},     {"tall block", 165, 230, 250, 420},
    {"short block", 270, 350, 375, 460}, {"light", 160, 60, 360, 90},
};

/// Mean luminance (Rec. 709 weights of linear sRGB) over a region, the image being `scale`
/// times smaller than 512 (1 here).
double region_luminance(const Image& img, const Region& r, int scale) {
    double s = 0;
    int n = 0;
    for (int y = r.y0 / scale; y < r.y1 / scale; ++y)
        for (int x = r.x0 / scale; x < r.x1 / scale; ++x, ++n)
            s += 0.2126 * img.at(x, y, 0) + 0.7152 * img.at(x, y, 1) + 0.0722 * img.at(x, y, 2);
    return s / n;
}

void expect_matches_pbrt_v4(const std::string& integrator, int spp, bool light_region = true) {
    const Image ref = read_image(kData + "pbrt-v4-1024spp.exr");
    const std::string text = cornell_box(integrator, 512, true);
    constexpr int kSeeds = 3;
    std::vector<std::vector<double>> lum(std::size(kRegions));
    for (int s = 0; s < kSeeds; ++s) {
        const Image img = render_seeded(text, spp, 1000 + uint64_t(s)).rgb;
        ASSERT_EQ(img.width, 512);
        for (size_t r = 0; r < std::size(kRegions); ++r)
            lum[r].push_back(region_luminance(img, kRegions[r], 1));
    }
    for (size_t r = 0; r < std::size(kRegions); ++r) {
        if (!light_region && std::string(kRegions[r].name) == "light") continue;
        double mean = 0, var = 0;
        for (double v : lum[r]) mean += v / kSeeds;
        for (double v : lum[r]) var += sqr(v - mean) / (kSeeds - 1);
        const double se = std::sqrt(var / kSeeds);
        const double want = region_luminance(ref, kRegions[r], 1);
        std::printf("%-10s %-12s ours/pbrt-v4 %.4f (se %.4f)\n", integrator.substr(12, 8).c_str(),
                    kRegions[r].name, mean / want, se / want);
        EXPECT_NEAR(mean, want, 0.01 * want + 4 * se)
            << integrator << ", " << kRegions[r].name << ": se " << se;
    }
}

TEST(CornellBoxBidirectional, BdptMatchesPbrtV4) {
    expect_matches_pbrt_v4("Integrator \"bdpt\" \"integer maxdepth\" [ 16 ]", 1);
}
TEST(CornellBoxBidirectional, LightpathMatchesPbrtV4) {
    expect_matches_pbrt_v4("Integrator \"lightpath\" \"integer maxdepth\" [ 16 ]", 2);
}
TEST(CornellBoxBidirectional, MltMatchesPbrtV4) {
    expect_matches_pbrt_v4("Integrator \"mlt\" \"integer maxdepth\" [ 16 ]", 2);
}
TEST(CornellBoxBidirectional, SppmMatchesPbrtV4) {
    expect_matches_pbrt_v4("Integrator \"sppm\" \"integer maxdepth\" [ 16 ] \"float radius\" [ 2 ]",
                           2);
}
TEST(CornellBoxBidirectional, VcmMatchesPbrtV4) {
    expect_matches_pbrt_v4("Integrator \"vcm\" \"integer maxdepth\" [ 16 ] \"float radius\" [ 1 ]",
                           1);
}

}  // namespace
}  // namespace sr::test
