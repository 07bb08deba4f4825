#include "steradian/integrators/path/path.h"

#include <gtest/gtest.h>

#include "steradian/scene/build.h"
#include "steradian/scene/pbrt/parser.h"
#include "steradian/scene/scene.h"

namespace sr {
namespace {

// The renderer's form of the estimator (camera rays traced as a packet, each path continued
// from its first hit, the first vertices' shadow rays tested afterwards as one packet) is the
// plain one, path_li(), summed in another order: per path the two agree to float rounding
// (so a deferred contribution is neither lost nor counted twice), both trace as many rays (the
// deferred shadow ray is one the plain path traces), and the packet's verdict on each deferred
// shadow ray is occluded()'s.
TEST(PathLiFrom, PacketsAndADeferredFirstShadowRayGiveWhatPathLiGives) {
    Scene scene = build_scene(
        parse_pbrt_file(std::string(STERADIAN_SOURCE_DIR) + "/scenes/cornell-box.pbrt"));
    std::unique_ptr<Sampler> sampler = make_sampler("zsobol", 64, Vec2i(512, 512), 7);
    constexpr int kN = Scene::kRayPacket;
    int compared = 0, deferred = 0, blocked_total = 0, lit = 0;
    for (int py = 20; py < 512; py += 37)
        for (int px = 15; px < 512; px += 41) {
            const Vec2i pixel(px, py);
            Ray rays[kN];
            SampledWavelengths lambdas[kN];
            for (int k = 0; k < kN; ++k) {
                sampler->start_pixel_sample(pixel, k);
                Point2 up = sampler->get_pixel_2d();
                lambdas[k] = SampledWavelengths::sample_visible(sampler->get_pixel_1d());
                rays[k] = scene.camera->generate_ray(Point2(Float(px) + up.x, Float(py) + up.y),
                                                     Point2(0.5f, 0.5f));
            }
            SurfaceHit hits[kN];
            const unsigned found = scene.intersect_packet(rays, (1u << kN) - 1, hits);
            SampledSpectrum from[kN];
            DeferredShadowRay shadows[kN];
            Ray shadow_rays[kN];
            unsigned pending = 0;
            for (int k = 0; k < kN; ++k) {
                PathCounters counters;
                SampledWavelengths lambda = lambdas[k];
                sampler->start_pixel_sample(pixel, k, kCameraDimensions);
                from[k] = path_li_from(scene, rays[k], (found >> k) & 1, hits[k], lambda, *sampler,
                                       counters, &shadows[k]);
                shadow_rays[k] = shadows[k].ray;
                pending |= unsigned(shadows[k].pending) << k;
            }
            const unsigned blocked = scene.occluded_packet(shadow_rays, pending);
            for (int k = 0; k < kN; ++k) {
                // The plain estimator; and path_li_from from a single ray's first hit, which
                // defers the same shadow ray as from the packet's.
                PathCounters plain_counters, from_counters;
                SampledWavelengths l1 = lambdas[k], l2 = lambdas[k];
                sampler->start_pixel_sample(pixel, k, kCameraDimensions);
                SampledSpectrum plain = path_li(scene, rays[k], l1, *sampler, plain_counters);
                sampler->start_pixel_sample(pixel, k, kCameraDimensions);
                SurfaceHit h;
                bool f = scene.intersect(rays[k], h);
                DeferredShadowRay d;
                path_li_from(scene, rays[k], f, h, l2, *sampler, from_counters, &d);
                EXPECT_EQ(plain_counters.rays, from_counters.rays) << px << "," << py;
                EXPECT_EQ(d.pending, shadows[k].pending);
                if (shadows[k].pending) {
                    ++deferred;
                    EXPECT_EQ(bool((blocked >> k) & 1), scene.occluded(shadow_rays[k]));
                    blocked_total += (blocked >> k) & 1;
                }
                SampledSpectrum total = from[k];
                if (((pending & ~blocked) >> k) & 1) total += shadows[k].contribution;
                for (int i = 0; i < kSpectrumSamples; ++i) {
                    // Sums of the same non-negative terms: equal but for a few roundings.
                    EXPECT_NEAR(total[i], plain[i], 1e-5f * std::abs(plain[i]))
                        << "pixel " << px << "," << py << " sample " << k << " lambda " << i;
                }
                lit += plain.max_value() > 0;
                ++compared;
            }
        }
    // Most paths see a lit surface; among their first light samples, the blocks stop some.
    EXPECT_GT(lit, compared / 2);
    EXPECT_GT(deferred, compared / 2);
    EXPECT_GT(blocked_total, 0);
}

}  // namespace
}  // namespace sr
