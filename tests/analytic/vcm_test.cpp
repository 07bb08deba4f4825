// Integrator "vcm" (vertex connection and merging) against a closed form, the path tracer and
// bdpt. Standard errors come from independent renders (fixed seeds), so the tests are
// deterministic; the merging's bias (it averages the light vertices' flux over a disk of the
// merge radius) is bounded separately and added to the tolerance where merging is on.
#include <gtest/gtest.h>

#include "steradian/core/error.h"
#include "support/block_stats.h"
#include "support/sds_mirrors.h"

namespace sr::test {
namespace {

bool debug() { return std::getenv("VCM_DEBUG") != nullptr; }

// ---- the specular-diffuse-specular scene ---------------------------------------------------

// vcm converges to the closed form (support/sds_mirrors.h) where bdpt sees nothing: the only
// strategy that can make the path light - M1 - floor - M2 - pinhole is merging at the floor,
// whose MIS weight is then 1.
//
// Bias bound (as tests/analytic/sppm_test.cpp derives it): a merge estimates the irradiance
// averaged over the disk of the radius r about the camera vertex, E + r^2/8 lap(E) + O(r^4);
// on this floor |lap E / E| <= 9/d^2 <= 1 (d >= 3), and r_i <= r_1 = 0.05, so the relative
// bias of every iteration is at most 0.05^2 / 8 = 3.2e-4. We allow 2e-3 of the expected value
// besides 5 standard errors (the blocks keep 2 r_1 from the floor's and the cone's edges).
TEST(Vcm, SpecularDiffuseSpecularMatchesTheClosedForm) {
    const std::string vcm =
        sds_scene("Integrator \"vcm\" \"integer maxdepth\" [ 5 ] \"float radius\" [ 0.05 ]");
    SceneDesc d = parse_pbrt_string(vcm, "<test>", std::string(STERADIAN_SOURCE_DIR) + "/scenes");
    const Scene scene = build_scene(d, {});
    const std::vector<double> want = sds_expected_blocks(scene, 0.1);
    size_t n_inside = 0;
    for (double v : want) n_inside += v > 0;
    ASSERT_GE(n_inside, 12u) << "the test's blocks do not see the lit floor";

    constexpr int kReps = 6;
    std::vector<std::vector<double>> reps;
    for (int r = 0; r < kReps; ++r)
        reps.push_back(block_means(render_seeded(vcm, 64, 10 + uint64_t(r)).y, kSdsRes, kSdsBlock));
    const BlockStats got = stats_of(reps);
    double ms = 0;
    for (size_t b = 0; b < want.size(); ++b) {
        if (want[b] <= 0) continue;
        const double tol = 5 * got.se[b] + 2e-3 * want[b];
        EXPECT_NEAR(got.mean[b], want[b], tol) << "block " << b;
        // And precise enough for that to mean something: a standard error below 1 %.
        EXPECT_LT(got.se[b], 0.01 * want[b]) << "block " << b;
        ms += sqr((got.mean[b] - want[b]) / got.se[b]) / double(n_inside);
        if (debug())
            std::fprintf(stderr, "block %zu: %g +- %g, closed form %g (ratio %.5f)\n", b,
                         got.mean[b], got.se[b], want[b], got.mean[b] / want[b]);
    }
    // z is about Student's t with 5 degrees of freedom: mean square 5/3.
    EXPECT_LT(ms, 3.0);

    // bdpt, and vcm without merging (a bidirectional path tracer): nothing there.
    for (const char* integ :
         {"Integrator \"bdpt\" \"integer maxdepth\" [ 5 ]",
          "Integrator \"vcm\" \"integer maxdepth\" [ 5 ] \"bool vertexmerging\" false"}) {
        const std::vector<double> other =
            block_means(render_seeded(sds_scene(integ), 16, 3).y, kSdsRes, kSdsBlock);
        for (size_t b = 0; b < want.size(); ++b)
            if (want[b] > 0) {
                EXPECT_LT(other[b], 1e-3 * want[b]) << integ << " block " << b;
            }
    }
}

// ---- inside a glowing sphere -----------------------------------------------------------------

// The camera at the centre of a sphere (radius 1) whose inside is a diffuse emitter of
// radiance Le and a Lambertian reflector of reflectance rho = 0.5: by symmetry the radiance
// is the same everywhere, and with paths of at most D = maxdepth scattering vertices it is
// Le (1 + rho + ... + rho^D). So the image mean is that series (63/32 for D = 5) times the
// image mean at maxdepth 0 (Le seen directly, weight 1). Rendering both with the same seed
// gives the iterations the same wavelengths, so the ratio has no spectral noise.
//
// Merging is unbiased here up to its cut-off of light vertices whose incoming direction lies
// below the camera vertex's tangent plane: the irradiance is uniform, and the part of the
// sphere within the distance r of a point is a cap of area exactly pi r^2 (Archimedes), but a
// light vertex up to r away has its normal tilted by up to r/R, and the cosine-weighted
// share of directions within that angle of grazing is sin^2(r/R) (1 % for r = 0.1, R = 1):
// we allow that of the series. With N = 256 light paths and r = 0.1, eta = 8 and merging
// takes most of the weight on these diffuse paths (the connections' ratio is about eta cos^2
// / (pi d^2) ~ 2.5 per vertex), so its MIS weights against the connections' are what the
// test checks; the connections alone and merging alone are checked too, and other counts of
// light paths than one per pixel (which change eta and the light paths' splat scale).
TEST(Vcm, InsideAGlowingSphereMatchesTheSeries) {
    auto scene = [](const std::string& integrator) {
        return "LookAt 0 0 0  0 0 1  0 1 0\n"
               "Camera \"perspective\" \"float fov\" [ 60 ]\n"
               "Film \"rgb\" \"integer xresolution\" [ 16 ] \"integer yresolution\" [ 16 ]\n"
               "Sampler \"independent\"\n" +
               integrator +
               "\nWorldBegin\n"
               "AttributeBegin\n"
               "  ReverseOrientation\n"
               "  AreaLightSource \"diffuse\" \"spectrum L\" [ 300 1 830 1 ]\n"
               "  Material \"diffuse\" \"spectrum reflectance\" [ 300 0.5 830 0.5 ]\n"
               "  Shape \"sphere\" \"float radius\" [ 1 ]\n"
               "AttributeEnd\n";
    };
    const double series = 63.0 / 32.0;
    const std::string base = "Integrator \"vcm\" \"float radius\" [ 0.1 ]";
    for (const char* variant :
         {"", " \"bool vertexmerging\" false", " \"bool vertexconnection\" false",
          // Fewer and more light paths than pixels (256).
          " \"integer lightpathsperiteration\" [ 100 ]", " \"integer lightpathsperiteration\" [ 1000 ]"}) {
        const std::string direct = scene(base + " \"integer maxdepth\" [ 0 ]" + variant);
        const std::string full = scene(base + " \"integer maxdepth\" [ 5 ]" + variant);
        constexpr int kReps = 6;
        std::vector<double> ratio;
        for (int r = 0; r < kReps; ++r) {
            double a = 0, b = 0;
            for (double v : render_seeded(full, 64, 50 + uint64_t(r)).y) a += v;
            for (double v : render_seeded(direct, 64, 50 + uint64_t(r)).y) b += v;
            ratio.push_back(a / b);
        }
        double mean = 0, var = 0;
        for (double x : ratio) mean += x / kReps;
        for (double x : ratio) var += sqr(x - mean) / (kReps - 1);
        const double se = std::sqrt(var / kReps);
        const bool merges = std::string(variant).find("vertexmerging") == std::string::npos;
        EXPECT_NEAR(mean, series, 5 * se + (merges ? 0.01 * series : 0)) << variant;
        // Precise enough for that to mean something.
        EXPECT_LT(se, 0.003 * series) << variant;
        if (debug())
            std::fprintf(stderr, "sphere%s: %.5f +- %.5f, series %.5f\n", variant, mean, se, series);
    }
}

// ---- the Cornell box -------------------------------------------------------------------------

constexpr int kRes = 64, kBlock = 8;

/// Block means and standard errors of `reps` renders of `text` at `spp` with seeds from
/// `seed0`.
BlockStats replicas(const std::string& text, int spp, uint64_t seed0, int reps) {
    std::vector<std::vector<double>> r;
    for (int i = 0; i < reps; ++i)
        r.push_back(block_means(render_seeded(text, spp, seed0 + uint64_t(i)).y, kRes, kBlock));
    return stats_of(r);
}

/// Compares a's block means with b's within `z` combined standard errors plus `bias` of b's
/// mean; returns the mean square of the z-scores (with bias/3 added to the standard error).
double compare(const BlockStats& a, const BlockStats& b, double bias, const char* what) {
    double ms = 0;
    for (size_t k = 0; k < a.mean.size(); ++k) {
        const double se = std::sqrt(sqr(a.se[k]) + sqr(b.se[k]));
        EXPECT_NEAR(a.mean[k], b.mean[k], 5 * se + bias * b.mean[k]) << what << " block " << k;
        if (debug())
            std::fprintf(stderr, "%s block %zu: %g +- %g vs %g +- %g (ratio %.4f)\n", what, k,
                         a.mean[k], a.se[k], b.mean[k], b.se[k], a.mean[k] / b.mean[k]);
        ms += sqr((a.mean[k] - b.mean[k]) / (se + bias * b.mean[k] / 3)) / double(a.mean.size());
    }
    // Over the whole image the edges' bias averages out to a third of the bound at most.
    double asum = 0, bsum = 0, se2 = 0;
    for (size_t k = 0; k < a.mean.size(); ++k) {
        asum += a.mean[k];
        bsum += b.mean[k];
        se2 += sqr(a.se[k]) + sqr(b.se[k]);
    }
    EXPECT_NEAR(asum / bsum, 1, bias / 3 + 5 * std::sqrt(se2) / bsum) << what << " image mean";
    if (debug()) std::fprintf(stderr, "%s: image mean ratio %.5f\n", what, asum / bsum);
    return ms;
}

// vcm and the path tracer agree on the Cornell box's 8 x 8-pixel block means (64 blocks, the
// light seen directly included) within their standard errors and a bound of the merging's
// bias.
//
// Bias bound (sppm_test.cpp's argument, which holds a fortiori for the merges' MIS-weighted
// share): a light vertex within r of a camera vertex but on another surface (a wall meeting
// the floor, a box's side) or where the irradiance changes across the disk moves the merged
// estimate; that concerns the camera vertices within r of such an edge, at most half of whose
// disk is wrong, so at most the fraction 2 r / w of a block of width w on the surface per edge
// crossing it, by at most its own value. With r_1 = 1 (the box is 556 wide; a block is 8
// pixels of about 8.7 at the back wall, w ~ 70) and at most two edges a block, the bound is
// 2 x 2 r_1 / w < 6% of the block's mean.
TEST(Vcm, AgreesWithThePathTracerOnTheCornellBox) {
    constexpr int kReps = 4;
    const BlockStats p = replicas(cornell_box("Integrator \"path\" \"integer maxdepth\" [ 5 ]", kRes),
                                  64, 100, kReps);
    const BlockStats v = replicas(
        cornell_box("Integrator \"vcm\" \"integer maxdepth\" [ 5 ] \"float radius\" [ 1 ]", kRes),
        64, 200, kReps);
    EXPECT_LT(compare(v, p, 0.06, "vcm/path"), 4.0);
}

// The same with glass (BK7, dispersive), gold and silver spheres in the box (the scene of
// tests/data/reference/cornell-box-glass-metal, at 64 x 64 with independent samples): paths
// through specular vertices and the glass sphere's caustic on the floor, which connections
// cannot reach and merging carries. The bias bound is the one above, doubled for the
// caustic's edge, where the irradiance changes across the merging disk.
TEST(Vcm, AgreesWithThePathTracerOnTheGlassAndMetalCornellBox) {
    auto with = [](const std::string& integ) { return glass_metal_box(integ, 64); };
    constexpr int kReps = 4;
    const BlockStats p =
        replicas(with("Integrator \"path\" \"integer maxdepth\" [ 8 ]"), 64, 700, kReps);
    const BlockStats v = replicas(
        with("Integrator \"vcm\" \"integer maxdepth\" [ 8 ] \"float radius\" [ 1 ]"), 32, 800,
        kReps);
    EXPECT_LT(compare(v, p, 0.12, "vcm/path glass and metal"), 4.0);
}

// sppm on the same glass-and-metal box: its visible points are the camera paths' first
// diffuse (or glossy) vertices behind the glass and in the metal, and it agrees with the path
// tracer within the standard errors and the merging bias bound of the Cornell box test
// (sppm_test.cpp: at most 12 % of a block with a radius small against a block's width).
TEST(Sppm, AgreesWithThePathTracerOnTheGlassAndMetalCornellBox) {
    auto with = [](const std::string& integ) { return glass_metal_box(integ, 64); };
    constexpr int kReps = 4;
    const BlockStats p =
        replicas(with("Integrator \"path\" \"integer maxdepth\" [ 8 ]"), 64, 700, kReps);
    const BlockStats q = replicas(with("Integrator \"sppm\" \"integer maxdepth\" [ 8 ] "
                                       "\"float radius\" [ 2 ] \"integer photonsperiteration\" "
                                       "[ 65536 ]"),
                                  32, 900, kReps);
    EXPECT_LT(compare(q, p, 0.12, "sppm/path glass and metal"), 4.0);
}

// Without merging, vcm is a bidirectional path tracer: unbiased, so it agrees with the path
// tracer within the standard errors alone (this checks the MIS weights of the connections,
// the light samples, the emitters found and the camera connections sum to one on every path:
// a weight off on one strategy shows as a bias).
TEST(Vcm, WithoutMergingIsUnbiased) {
    constexpr int kReps = 4;
    const BlockStats p = replicas(cornell_box("Integrator \"path\" \"integer maxdepth\" [ 5 ]", kRes),
                                  64, 300, kReps);
    const BlockStats v = replicas(
        cornell_box("Integrator \"vcm\" \"integer maxdepth\" [ 5 ] \"bool vertexmerging\" false",
                    kRes),
        64, 400, kReps);
    EXPECT_LT(compare(v, p, 0, "bpt/path"), 3.0);
}

// Without connections, vcm merges at every camera vertex and adds the emitters its camera
// paths find (photon mapping under MIS): it agrees with the path tracer within the standard
// errors and the bias bound of merging (above).
TEST(Vcm, WithoutConnectionsIsPhotonMapping) {
    constexpr int kReps = 4;
    const BlockStats p = replicas(cornell_box("Integrator \"path\" \"integer maxdepth\" [ 5 ]", kRes),
                                  64, 500, kReps);
    const BlockStats v = replicas(
        cornell_box("Integrator \"vcm\" \"integer maxdepth\" [ 5 ] \"float radius\" [ 1 ] "
                    "\"bool vertexconnection\" false",
                    kRes),
        64, 600, kReps);
    EXPECT_LT(compare(v, p, 0.06, "pm/path"), 4.0);
}

// The image does not depend on the number of threads: light vertices in fixed slots, merges
// in the grid's order, splats added in light path order.
TEST(Vcm, SameImageOnOneAndTwoThreads) {
    for (const char* params : {"\"float radius\" [ 8 ]", "\"float radius\" [ 100 ]",
                               "\"float radius\" [ 8 ] \"integer lightpathsperiteration\" [ 3000 ]"}) {
        const std::string text = cornell_box(
            std::string("Integrator \"vcm\" \"integer maxdepth\" [ 4 ] ") + params, 32);
        const Rendered a = render_seeded(text, 3, 1, 1), b = render_seeded(text, 3, 1, 2);
        ASSERT_EQ(a.rgb.data.size(), b.rgb.data.size());
        EXPECT_TRUE(a.rgb.data == b.rgb.data) << params;
        double sum = 0;
        for (float v : a.rgb.data) sum += v;
        EXPECT_GT(sum, 0);
        EXPECT_EQ(a.stats.spp, 3);
        EXPECT_EQ(a.stats.nonfinite, 0u);
    }
}

}  // namespace
}  // namespace sr::test
