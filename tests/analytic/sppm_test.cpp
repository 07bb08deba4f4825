// Integrator "sppm" (stochastic progressive photon mapping) against closed forms and the
// path tracer. Standard errors come from independent renders (fixed seeds), so the tests are
// deterministic; the photon estimate's bias (it averages the photons' flux over a disk of
// the search radius) is bounded separately and added to the tolerance.
#include <gtest/gtest.h>

#include "steradian/bsdf/fresnel.h"
#include "steradian/camera/camera.h"
#include "steradian/core/error.h"
#include "support/block_stats.h"
#include "support/sds_mirrors.h"

namespace sr::test {
namespace {

// SPPM converges to the closed form where path tracing and bdpt see nothing.
//
// Bias bound: each photon estimate is the flux of the photons within the pixel's radius r of
// its visible point; for a smooth irradiance E its expectation is E averaged over the disk,
// E + r^2/8 lap(E) + O(r^4). Radii only shrink (r <= r0 = 0.05), so the relative bias of
// every iteration's estimate is at most r0^2/8 max|lap E| / E. For E = I h / d^3 (d^2 =
// rho^2 + h^2, rho the distance from the foot of the image source) lap E / E = -6/d^2 +
// 15 rho^2/d^4, at most 9/d^2 <= 1 on this floor (d >= 3), which bounds the relative bias by
// 3.2e-4 (R(c1) varies far more slowly). We allow 2e-3 of the
// expected value besides 5 standard errors (the disk also crosses no edge: the blocks keep
// 2 r0 from the floor's edges and the cone's).
TEST(Sppm, SpecularDiffuseSpecularMatchesTheClosedForm) {
    const std::string sppm = sds_scene(
        "Integrator \"sppm\" \"integer maxdepth\" [ 5 ] \"float radius\" [ 0.05 ] "
        "\"integer photonsperiteration\" [ 65536 ]");
    SceneDesc d = parse_pbrt_string(sppm, "<test>", std::string(STERADIAN_SOURCE_DIR) + "/scenes");
    const Scene scene = build_scene(d, {});
    const std::vector<double> want = sds_expected_blocks(scene, 0.1);
    size_t n_inside = 0;
    for (double v : want) n_inside += v > 0;
    ASSERT_GE(n_inside, 12u) << "the test's blocks do not see the lit floor";

    constexpr int kReps = 6;
    std::vector<std::vector<double>> reps;
    for (int r = 0; r < kReps; ++r)
        reps.push_back(block_means(render_seeded(sppm, 16, 10 + uint64_t(r)).y, kSdsRes, kSdsBlock));
    const BlockStats got = stats_of(reps);
    double ms = 0;
    for (size_t b = 0; b < want.size(); ++b) {
        if (want[b] <= 0) continue;
        const double tol = 5 * got.se[b] + 2e-3 * want[b];
        EXPECT_NEAR(got.mean[b], want[b], tol) << "block " << b;
        // And precise enough for that to mean something: a standard error below 0.4 %.
        EXPECT_LT(got.se[b], 0.004 * want[b]) << "block " << b;
        ms += sqr((got.mean[b] - want[b]) / got.se[b]) / double(n_inside);
        if (std::getenv("SPPM_DEBUG"))
            std::fprintf(stderr, "block %zu: %g +- %g, closed form %g (ratio %.5f)\n", b,
                         got.mean[b], got.se[b], want[b], got.mean[b] / want[b]);
    }
    // z is about Student's t with 5 degrees of freedom: mean square 5/3.
    EXPECT_LT(ms, 3.0);

    // bdpt and the path tracer: nothing there (no strategy can connect two vertices of the
    // path light - M1 - floor - M2 - pinhole).
    for (const char* integ : {"Integrator \"bdpt\" \"integer maxdepth\" [ 5 ]",
                              "Integrator \"path\" \"integer maxdepth\" [ 5 ]"}) {
        const std::vector<double> other =
            block_means(render_seeded(sds_scene(integ), 16, 3).y, kSdsRes, kSdsBlock);
        for (size_t b = 0; b < want.size(); ++b)
            if (want[b] > 0) {
                EXPECT_LT(other[b], 1e-3 * want[b]) << integ << " block " << b;
            }
    }
}

// ---- the Cornell box -------------------------------------------------------------------------

// SPPM and the path tracer agree on the Cornell box's 8 x 8-pixel block means (64 blocks, the
// light seen directly included) within their standard errors and SPPM's bias bound.
//
// Bias bound: a photon within r of a visible point but on another surface (a wall meeting the
// floor, a box's side) or where the irradiance changes across the disk moves the estimate; it
// concerns the visible points within r of such an edge, at most half of whose disk is
// wrong, so at most the fraction 2 r / w of a block of width w on the surface is affected per
// edge crossing it, by at most its own value. With r0 = 2 (the box is 556 wide; a block is
// 8 pixels of about 8.7 at the back wall, w ~ 70) and at most two edges a block, the
// bound is 2 x 2 r0 / w < 12% of the block's mean, falling as the radii shrink (r ~ N^-1/6).
// Without photons (only the direct light) the blocks are 20-60% too dark, so the test sees
// the photons' contribution.
TEST(Sppm, AgreesWithThePathTracerOnTheCornellBox) {
    constexpr int kRes = 64, kBlock = 8, kReps = 4;
    const std::string path = cornell_box("Integrator \"path\" \"integer maxdepth\" [ 5 ]", kRes);
    const std::string sppm = cornell_box(
        "Integrator \"sppm\" \"integer maxdepth\" [ 5 ] \"float radius\" [ 2 ] "
        "\"integer photonsperiteration\" [ 65536 ]",
        kRes);
    std::vector<std::vector<double>> pr, sr_, direct;
    for (int r = 0; r < kReps; ++r) {
        pr.push_back(block_means(render_seeded(path, 64, 100 + uint64_t(r)).y, kRes, kBlock));
        sr_.push_back(block_means(render_seeded(sppm, 64, 200 + uint64_t(r)).y, kRes, kBlock));
    }
    const BlockStats p = stats_of(pr), s = stats_of(sr_);
    // The path tracer's direct light alone (maxdepth 1), to show the photons matter.
    const std::vector<double> d1 = block_means(
        render_seeded(cornell_box("Integrator \"path\" \"integer maxdepth\" [ 1 ]", kRes), 64, 7).y, kRes,
        kBlock);
    double ms = 0, indirect = 0, total = 0;
    for (size_t b = 0; b < p.mean.size(); ++b) {
        const double se = std::sqrt(sqr(p.se[b]) + sqr(s.se[b]));
        const double bias = 0.12 * p.mean[b];
        EXPECT_NEAR(s.mean[b], p.mean[b], 5 * se + bias) << "block " << b;
        if (std::getenv("SPPM_DEBUG"))
            std::fprintf(stderr, "block %zu: sppm %g +- %g, path %g +- %g (ratio %.4f)\n", b,
                         s.mean[b], s.se[b], p.mean[b], p.se[b], s.mean[b] / p.mean[b]);
        ms += sqr((s.mean[b] - p.mean[b]) / (se + bias / 3)) / double(p.mean.size());
        indirect += p.mean[b] - d1[b];
        total += p.mean[b];
    }
    EXPECT_LT(ms, 4.0);
    EXPECT_GT(indirect, 0.2 * total);
    // Over the whole image the edge bias averages out to a few percent at most.
    double ssum = 0, psum = 0, se2 = 0;
    for (size_t b = 0; b < p.mean.size(); ++b) {
        ssum += s.mean[b];
        psum += p.mean[b];
        se2 += sqr(p.se[b]) + sqr(s.se[b]);
    }
    EXPECT_NEAR(ssum / psum, 1, 0.03 + 5 * std::sqrt(se2) / psum);
}

// The image does not depend on the number of threads: each chunk of photons keeps its
// deposits and the chunks are added in order. With a radius of 300 (the box is 556 wide)
// every photon meets thousands of visible points, and the chunks shrink to a few photons to
// bound their deposit lists: the same holds.
TEST(Sppm, SameImageOnOneAndTwoThreads) {
    for (const char* radius : {"8", "300"}) {
        const std::string text = cornell_box(
            std::string("Integrator \"sppm\" \"integer maxdepth\" [ 4 ] \"float radius\" [ ") +
                radius + " ] \"integer photonsperiteration\" [ 5000 ]",
            32);
        const Rendered a = render_seeded(text, 3, 1, 1), b = render_seeded(text, 3, 1, 2);
        ASSERT_EQ(a.rgb.data.size(), b.rgb.data.size());
        EXPECT_TRUE(a.rgb.data == b.rgb.data) << "radius " << radius;
        double sum = 0;
        for (float v : a.rgb.data) sum += v;
        EXPECT_GT(sum, 0);
        EXPECT_EQ(a.stats.spp, 3);
    }
}

}  // namespace
}  // namespace sr::test
