// Integrator "mlt" against bdpt and the path tracer on the Cornell box: all three are
// consistent estimators of the same image, so their 16 x 16-pixel block means agree within
// standard errors taken from independent runs (fixed seeds, so the tests are deterministic),
// and so do their image means. Also: the same image on one and two threads, pbrt-v4's
// parameters with located errors, and what it refuses.
#include <gtest/gtest.h>

#include "steradian/core/error.h"
#include "support/block_stats.h"

namespace sr::test {
namespace {

constexpr int kRes = 64, kBlock = 16, kReplicas = 6;

/// The kBlock x kBlock-pixel block means of a res x res image, and the image mean last.
std::vector<double> blocks_and_mean(const std::vector<double>& y, int res) {
    std::vector<double> m = block_means(y, res, kBlock);
    double mean = 0;
    for (double v : y) mean += v / double(res * res);
    m.push_back(mean);
    return m;
}

BlockStats replicate(const std::string& text, int spp, uint64_t seed0) {
    std::vector<std::vector<double>> reps;
    for (int r = 0; r < kReplicas; ++r)
        reps.push_back(blocks_and_mean(render_seeded(text, spp, seed0 + uint64_t(r)).y, kRes));
    return stats_of(reps);
}

/// z-scores of a's blocks against b's (the image means last). With 6 replicas a side each z
/// is close to Student's t with about 10 degrees of freedom: mean square near 1.25, |z| > 6
/// with probability below 1e-4 per block.
void expect_agree(const BlockStats& a, const BlockStats& b, const char* what) {
    double ms = 0, mx = 0;
    const size_t n = a.mean.size() - 1;
    for (size_t i = 0; i < n; ++i) {
        const double z = (a.mean[i] - b.mean[i]) / std::sqrt(sqr(a.se[i]) + sqr(b.se[i]));
        ms += z * z / double(n);
        mx = std::max(mx, std::abs(z));
    }
    EXPECT_LT(ms, 2.0) << what;
    EXPECT_LT(mx, 6.0) << what;
    // The image means.
    const double z = (a.mean[n] - b.mean[n]) / std::sqrt(sqr(a.se[n]) + sqr(b.se[n]));
    EXPECT_LT(std::abs(z), 4.0) << what << ": image means " << a.mean[n] << " +- " << a.se[n]
                                << " and " << b.mean[n] << " +- " << b.se[n];
}

const char* kMlt =
    "Integrator \"mlt\" \"integer maxdepth\" [ 5 ] \"integer bootstrapsamples\" [ 100000 ] "
    "\"integer chains\" [ 256 ]";

// mlt, bdpt and path agree on the Cornell box's 16 x 16-pixel block means (direct view of the
// light included) and on the image mean, within the spread of independent runs.
TEST(Mlt, AgreesWithBdptAndPathOnTheCornellBox) {
    const BlockStats mlt = replicate(cornell_box(kMlt, kRes), 64, 500);
    const BlockStats bdpt =
        replicate(cornell_box("Integrator \"bdpt\" \"integer maxdepth\" [ 5 ]", kRes), 8, 200);
    const BlockStats path =
        replicate(cornell_box("Integrator \"path\" \"integer maxdepth\" [ 5 ]", kRes), 32, 100);
    expect_agree(mlt, bdpt, "mlt vs bdpt");
    expect_agree(mlt, path, "mlt vs path");
    // Not agreement by noise alone: mlt's blocks are precise to a few percent.
    std::vector<double> rel;
    for (size_t i = 0; i + 1 < mlt.mean.size(); ++i) rel.push_back(mlt.se[i] / mlt.mean[i]);
    std::sort(rel.begin(), rel.end());
    EXPECT_LT(rel[rel.size() / 2], 0.05);
}

// With a crop window the light subpaths connected to the camera (t = 1) are samples of the
// full film's light tracing, four times the crop window's area here: mlt and path agree on
// the window (the window's own 16 x 16-pixel blocks, and its mean).
TEST(Mlt, AgreesWithPathInACropWindow) {
    auto crop = [](std::string s) {
        replace_once(s, "\"bool savefp16\" [ false ]",
                     "\"bool savefp16\" [ false ] \"float cropwindow\" [ 0.5 1 0 0.5 ]");
        return s;
    };
    constexpr int kHalf = kRes / 2;
    auto rep = [&](const std::string& text, int spp, uint64_t seed0) {
        std::vector<std::vector<double>> reps;
        for (int r = 0; r < kReplicas; ++r) {
            const Rendered im = render_seeded(text, spp, seed0 + uint64_t(r));
            EXPECT_EQ(im.y.size(), size_t(kHalf * kHalf));
            reps.push_back(blocks_and_mean(im.y, kHalf));
        }
        return stats_of(reps);
    };
    const BlockStats mlt = rep(crop(cornell_box(kMlt, kRes)), 64, 700);
    const BlockStats path =
        rep(crop(cornell_box("Integrator \"path\" \"integer maxdepth\" [ 5 ]", kRes)), 32, 800);
    expect_agree(mlt, path, "mlt vs path, crop window");
}

// The same image on one and two threads (chains assigned by index, splats added in chain
// order), and a render stopped after m rounds is the render of m mutations per pixel.
TEST(Mlt, SameImageOnOneAndTwoThreads) {
    const std::string text = cornell_box(
        "Integrator \"mlt\" \"integer maxdepth\" [ 4 ] \"integer bootstrapsamples\" [ 2000 ] "
        "\"integer chains\" [ 37 ]",
        32);
    const Rendered a = render_seeded(text, 3, 1, 1), b = render_seeded(text, 3, 1, 2);
    ASSERT_EQ(a.rgb.data.size(), b.rgb.data.size());
    EXPECT_TRUE(a.rgb.data == b.rgb.data);
    double sum = 0;
    for (float v : a.rgb.data) sum += v;
    EXPECT_GT(sum, 0);
    EXPECT_EQ(a.stats.spp, 3);
    EXPECT_EQ(a.stats.nonfinite, 0u);
    // Another seed, another image.
    const Rendered c = render_seeded(text, 3, 2, 2);
    EXPECT_FALSE(a.rgb.data == c.rgb.data);
}

// pbrt-v4's parameters: out-of-range values are errors at their file:line:col; an unknown
// parameter is reported.
TEST(Mlt, ParameterErrorsNameTheirLocation) {
    const std::string head = "Camera \"perspective\"\n";
    const std::string world = "\nWorldBegin\nLightSource \"point\"\n";
    struct Case {
        const char* params;
        const char* what;
    };
    for (const Case& c : {Case{"\"integer chains\" [ 0 ]", "chains"},
                          Case{"\"integer bootstrapsamples\" [ -1 ]", "bootstrapsamples"},
                          Case{"\"integer mutationsperpixel\" [ 0 ]", "mutationsperpixel"},
                          Case{"\"float largestepprobability\" [ 1.5 ]", "largestepprobability"},
                          Case{"\"float sigma\" [ 0 ]", "sigma"},
                          Case{"\"float sigma\" [ -0.1 ]", "sigma"},
                          Case{"\"integer maxdepth\" [ -2 ]", "maxdepth"}}) {
        // The parameter starts at column 18 of line 2.
        const std::string text = head + "Integrator \"mlt\" " + c.params + world;
        try {
            build_scene(parse_pbrt_string(text, "<test>", "."), {});
            ADD_FAILURE() << c.params << " accepted";
        } catch (const Error& e) {
            const std::string msg = e.what();
            EXPECT_NE(msg.find("<test>:2:18"), std::string::npos) << msg;
            EXPECT_NE(msg.find(c.what), std::string::npos) << msg;
        }
    }
    try {
        build_scene(parse_pbrt_string(head + "Integrator \"mlt\" \"integer spp\" [ 4 ]" + world,
                                      "<test>", "."),
                    {});
        ADD_FAILURE() << "an unknown parameter accepted";
    } catch (const Error& e) {
        EXPECT_NE(std::string(e.what()).find("spp"), std::string::npos) << e.what();
        EXPECT_NE(std::string(e.what()).find("<test>:2:"), std::string::npos) << e.what();
    }
    // pbrt-v4's defaults.
    const Scene s = build_scene(parse_pbrt_string(head + "Integrator \"mlt\"" + world, "<test>", "."), {});
    EXPECT_EQ(s.integrator.type, "mlt");
    EXPECT_EQ(s.integrator.max_depth, 5);
    EXPECT_EQ(s.integrator.mlt.bootstrap_samples, 100000);
    EXPECT_EQ(s.integrator.mlt.chains, 1000);
    EXPECT_EQ(s.integrator.mlt.mutations_per_pixel, 100);
    EXPECT_FLOAT_EQ(s.integrator.mlt.large_step_probability, 0.3f);
    EXPECT_FLOAT_EQ(s.integrator.mlt.sigma, 0.01f);
}

// What the bidirectional kernels cannot trace is refused, as is a scene without light (media:
// bidir_media_test.cpp).
TEST(Mlt, RefusesWhatItCannotRender) {
    std::string ortho = cornell_box(kMlt, 16);
    replace_once(ortho, "Camera \"perspective\" \"float fov\" [ 39.3077 ]", "Camera \"orthographic\"");
    try {
        render_seeded(ortho, 1, 0);
        ADD_FAILURE() << "orthographic camera accepted";
    } catch (const Error& e) {
        EXPECT_NE(std::string(e.what()).find("perspective"), std::string::npos) << e.what();
    }
    const std::string dark = "Camera \"perspective\"\nIntegrator \"mlt\" \"integer bootstrapsamples\" [ 10 ]\n"
                             "WorldBegin\nShape \"sphere\"\n";
    try {
        render_seeded(dark, 1, 0);
        ADD_FAILURE() << "a scene without light rendered";
    } catch (const Error& e) {
        EXPECT_NE(std::string(e.what()).find("bootstrap"), std::string::npos) << e.what();
    }
}

}  // namespace
}  // namespace sr::test
