// Solid-angle sampling of triangles (Arvo 1995): checked against the octant, whose
// spherical triangle (1,0,0), (0,1,0), (0,0,1) seen from the origin has area 4 pi / 8 and
// direction moments E[x] = E[y] = E[z] = (pi/4) / (pi/2) = 1/2 under uniform sampling.
#include <gtest/gtest.h>

#include "steradian/geometry/shapes.h"
#include "steradian/sampling/rng.h"
#include "steradian/sampling/stats.h"

namespace sr {
namespace {

TriangleMesh octant(Float scale) {
    TriangleMesh m;
    m.p = std::make_shared<std::vector<Point3>>(std::vector<Point3>{
        {scale, 0, 0}, {0, scale, 0}, {0, 0, scale}, {0, 0, 0}});  // + Embree padding
    m.n = std::make_shared<std::vector<Normal3>>();
    m.uv = std::make_shared<std::vector<Point2>>();
    m.indices = std::make_shared<std::vector<uint32_t>>(std::vector<uint32_t>{0, 1, 2});
    return m;
}

TEST(SphericalTriangle, SolidAngleOfTheOctantTriangle) {
    // The flat triangle subtends the same solid angle as the octant's spherical triangle.
    EXPECT_NEAR(octant(1).solid_angle(0, Point3(0, 0, 0)), kPi / 2, 1e-5);
    EXPECT_NEAR(octant(7).solid_angle(0, Point3(0, 0, 0)), kPi / 2, 1e-5);
    // Far away it tends to area * cos / d^2: triangle of area sqrt(3)/2 seen along (1,1,1).
    Point3 far(100, 100, 100);
    Float d = length(far - Point3(1.f / 3, 1.f / 3, 1.f / 3));
    EXPECT_NEAR(octant(1).solid_angle(0, far), std::sqrt(3.f) / 2 / (d * d),
                1e-3 * std::sqrt(3.f) / 2 / (d * d));
}

TEST(SphericalTriangle, SamplesAreUniformInSolidAngle) {
    TriangleMesh m = octant(2);
    Pcg32 rng(11);
    const int n = 200000;
    double sx = 0, sy = 0, sz = 0, sx2 = 0;
    for (int i = 0; i < n; ++i) {
        ShapeSample s =
            m.sample_triangle_from(0, Point3(0, 0, 0), Point2(rng.next_float(), rng.next_float()));
        ASSERT_NEAR(s.pdf, 2 / kPi, 1e-4);
        // The point lies on the triangle's plane x + y + z = 2.
        ASSERT_NEAR(s.p.x + s.p.y + s.p.z, 2, 1e-4);
        Vec3 w = normalize(s.p);
        sx += w.x, sy += w.y, sz += w.z, sx2 += w.x * w.x;
        EXPECT_NEAR(m.pdf_triangle_from(0, Point3(0, 0, 0), s.p, s.n), s.pdf, 1e-4);
    }
    double var = sx2 / n - sqr(sx / n);
    double se = std::sqrt(var / n);
    EXPECT_NEAR(sx / n, 0.5, 4.5 * se);
    EXPECT_NEAR(sy / n, 0.5, 4.5 * se);
    EXPECT_NEAR(sz / n, 0.5, 4.5 * se);
    // E[x^2] over the octant = (1/3) by symmetry of x^2 + y^2 + z^2 = 1.
    EXPECT_NEAR(sx2 / n, 1.0 / 3, 4.5 * std::sqrt(1.0 / n));
}

// Seen from afar (estimated solid angle below kSphericalSampleEstimate) a triangle is sampled
// by area, from nearby uniformly in solid angle. Either way E[1 / pdf_sa] is the solid angle
// the triangle subtends, and pdf_triangle_from returns the density the sample was drawn with.
TEST(SphericalTriangle, AreaSamplingFarAwayAndSphericalNearbyBothIntegrateToTheSolidAngle) {
    TriangleMesh m = octant(1);  // area sqrt(3)/2, normal (1,1,1)/sqrt(3)
    const Float area = std::sqrt(3.f) / 2;
    for (Float dist : {0.5f, 4.f}) {
        // On the normal through the centroid, at distance dist from the plane.
        Point3 c(1.f / 3, 1.f / 3, 1.f / 3);
        Point3 ref = c + Vec3(1, 1, 1) * (dist / std::sqrt(3.f));
        Float estimate = area / (dist * dist);
        bool spherical = estimate >= TriangleMesh::kSphericalSampleEstimate;
        ASSERT_EQ(spherical, dist < 1) << "the two cases straddle the threshold";
        Float omega = m.solid_angle(0, ref);
        Pcg32 rng(5, uint64_t(dist * 10));
        const int n = 100000;
        double sum = 0, sum2 = 0;
        for (int k = 0; k < n; ++k) {
            ShapeSample s =
                m.sample_triangle_from(0, ref, Point2(rng.next_float(), rng.next_float()));
            ASSERT_NEAR(s.p.x + s.p.y + s.p.z, 1, 1e-5);
            Vec3 d = s.p - ref;
            Float area_pdf = length_squared(d) / (area * absdot(s.n, normalize(d)));
            ASSERT_NEAR(s.pdf / (spherical ? 1 / omega : area_pdf), 1, 1e-4) << "dist " << dist;
            ASSERT_NEAR(m.pdf_triangle_from(0, ref, s.p, s.n) / s.pdf, 1, 1e-5);
            sum += 1 / double(s.pdf);
            sum2 += sqr(1 / double(s.pdf));
        }
        double mean = sum / n, se = std::sqrt(std::max(0.0, sum2 / n - mean * mean) / n);
        if (spherical) {
            EXPECT_NEAR(mean / omega, 1, 1e-4);  // constant
        } else {
            EXPECT_GT(z_test_p(mean, omega, se), 1e-3) << mean << " vs " << omega;
        }
    }
}

}  // namespace
}  // namespace sr
