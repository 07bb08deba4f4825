// Our render of the Cornell box against pbrt-v4's own renders of the same file
// (tests/data/reference/cornell-box: pbrt-v4 commit 5f7a6068 at 1024 and 64 spp).
// Pass criteria from the foundation issue: the mean of every wall and block region within
// 1 % of pbrt-v4's 1024-spp image (checked at 256 spp, where the region means' own noise is
// well below 1 %), and the RMSE of our 64-spp image against it no worse than pbrt-v4's own
// 64-spp image.
#include <gtest/gtest.h>

#include <algorithm>

#include "steradian/film/image_io.h"
#include "support/render_util.h"

namespace sr::test {
namespace {

const std::string kData = std::string(STERADIAN_SOURCE_DIR) + "/tests/data/reference/cornell-box/";

struct Region {
    const char* name;
    int x0, y0, x1, y1;
};
// Pixel rectangles [x0,x1) x [y0,y1) inside each surface (checked on the reference image).
constexpr Region kRegions[] = {
    {"red wall", 25, 110, 85, 400},    {"green wall", 430, 110, 490, 400},
    {"back wall", 280, 110, 380, 300}, {"ceiling", 150, 20, 360, 50},
    {"floor", 110, 470, 400, 500},     {"tall block", 165, 230, 250, 420},
    {"short block", 270, 350, 375, 460}, {"light", 160, 60, 360, 90},
};

double region_mean(const Image& img, const Region& r, int c) {
    double s = 0;
    for (int y = r.y0; y < r.y1; ++y)
        for (int x = r.x0; x < r.x1; ++x) s += img.at(x, y, c);
    return s / double((r.x1 - r.x0) * (r.y1 - r.y0));
}

double region_luminance(const Image& img, const Region& r) {
    return 0.2126 * region_mean(img, r, 0) + 0.7152 * region_mean(img, r, 1) +
           0.0722 * region_mean(img, r, 2);
}

/// The RGB channels of an image (EXR files may carry alpha).
Image rgb_only(const Image& img) {
    Image t;
    t.width = img.width, t.height = img.height, t.channels = 3;
    for (int y = 0; y < img.height; ++y)
        for (int x = 0; x < img.width; ++x)
            for (int c = 0; c < 3; ++c) t.data.push_back(img.at(x, y, c));
    return t;
}

double rmse(const Image& a, const Image& b) {
    double s = 0;
    for (size_t i = 0; i < a.data.size(); ++i) s += sqr(double(a.data[i]) - b.data[i]);
    return std::sqrt(s / double(a.data.size()));
}

TEST(CornellBox, MatchesPbrtV4RegionByRegionAndInRmse) {
    Image ref = rgb_only(read_image(kData + "pbrt-v4-1024spp.exr"));
    Image pbrt64 = rgb_only(read_image(kData + "pbrt-v4-64spp.exr"));
    SceneDesc d = parse_pbrt_file(std::string(STERADIAN_SOURCE_DIR) + "/scenes/cornell-box.pbrt");
    Scene s = build_scene(d);
    ASSERT_EQ(s.sampler.spp, 64);
    Film film(s.film);
    RenderOptions ro;
    RenderStats st = render(s, film, ro);
    EXPECT_EQ(st.nonfinite, 0u);
    Image ours = film.rgb_image();
    ASSERT_EQ(ours.width, ref.width);
    ASSERT_EQ(ours.height, ref.height);
    // The region means are compared at 256 spp: the 64-spp image averaged with an
    // independent 192-spp one (another seed), weighted by sample count. At 64 spp the darkest
    // region's mean is itself noisy at the 1 % level: pbrt-v4's own 64-spp image is 0.95 %
    // above its 1024-spp one in the short block's green channel, and our 64-spp images with
    // seeds 0 and 1 differ by 1 % there.
    Film film_more(s.film);
    RenderOptions ro_more;
    ro_more.spp = 192;
    ro_more.seed = 1;
    EXPECT_EQ(render(s, film_more, ro_more).nonfinite, 0u);
    Image more = film_more.rgb_image();
    Image mean256 = ours;
    for (size_t i = 0; i < mean256.data.size(); ++i)
        mean256.data[i] = 0.25f * ours.data[i] + 0.75f * more.data[i];
    // Luminance, and every RGB channel that carries at least 10 % of the region's largest
    // channel, within 1 %. (A channel far below that, such as blue on the red wall at 2e-3
    // of red, is a small difference of large XYZ terms; its relative noise says nothing
    // about the radiance. At 512 spp ours matches it within 0.2 %.)
    for (const Region& r : kRegions) {
        double a = region_luminance(mean256, r), b = region_luminance(ref, r);
        std::printf("%-12s luminance ours/pbrt-v4 %.4f\n", r.name, a / b);
        EXPECT_NEAR(a / b, 1.0, 0.01) << r.name << ": ours " << a << " pbrt-v4 " << b;
        double max_c = std::max({region_mean(ref, r, 0), region_mean(ref, r, 1), region_mean(ref, r, 2)});
        for (int c = 0; c < 3; ++c) {
            double ac = region_mean(mean256, r, c), bc = region_mean(ref, r, c);
            if (bc < 0.1 * max_c) continue;
            EXPECT_NEAR(ac / bc, 1.0, 0.01) << r.name << " channel " << c;
        }
    }
    double e_ours = rmse(ours, ref);
    double e_pbrt = rmse(pbrt64, ref);
    RecordProperty("rmse_ours", std::to_string(e_ours));
    RecordProperty("rmse_pbrt64", std::to_string(e_pbrt));
    std::printf("RMSE vs pbrt-v4 1024 spp: ours(64 spp) %.5f, pbrt-v4(64 spp) %.5f, ratio %.3f\n",
                e_ours, e_pbrt, e_ours / e_pbrt);
    // The foundation issue's criterion: no more error than pbrt-v4 at the same sample count.
    // (The pixels that straddle the light's edge dominate both errors; there the wavelengths
    // of the samples that see the light must stay stratified, see Sampler::get_pixel_1d.)
    EXPECT_LE(e_ours, e_pbrt);
}

}  // namespace
}  // namespace sr::test
