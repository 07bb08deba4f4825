#include "steradian/integrators/glare.h"

#include <cmath>
#include <numbers>

#include <gtest/gtest.h>

#include "steradian/lights/photometric/photometric.h"

namespace sr {
namespace {

constexpr double kPiD = std::numbers::pi;

PhotometricData opening(double w, double l, double h) {
    PhotometricData d;
    d.shape = classify_luminous_shape(w, l, h);
    d.width = std::abs(w);
    d.length = std::abs(l);
    d.height = std::abs(h);
    return d;
}

/// The mean over all directions of the projected area, by a Fibonacci lattice on the sphere.
double mean_projected_area(const PhotometricData& d) {
    const int n = 200000;
    const double golden = kPiD * (3 - std::sqrt(5.0));
    double sum = 0;
    for (int i = 0; i < n; ++i) {
        const double z = 1 - (2 * i + 1.0) / n, r = std::sqrt(1 - z * z), phi = golden * i;
        sum += luminous_projected_area(d, Vec3(Float(r * std::cos(phi)), Float(r * std::sin(phi)),
                                               Float(z)));
    }
    return sum / n;
}

/// Ramanujan's second approximation of an ellipse's perimeter (relative error below 1e-9
/// for the axis ratios used here).
double ellipse_perimeter(double a, double b) {
    const double h = (a - b) * (a - b) / ((a + b) * (a + b));
    return kPiD * (a + b) * (1 + 3 * h / (10 + std::sqrt(4 - 3 * h)));
}

// Cauchy's surface-area formula: the shadow of a convex body, averaged over all directions,
// is a quarter of its surface area (a flat opening counts both faces). LM-63 dimensions:
// width along y (C90), length along x (C0), height along z; negative means round.
TEST(Glare, ProjectedAreasObeyCauchysFormula) {
    struct Case {
        double w, l, h, surface;
    };
    const double pi = kPiD;
    const Case cases[] = {
        {0.3, 0.6, 0, 2 * 0.3 * 0.6},                                        // rectangle
        {0.2, 0.3, 0.1, 2 * (0.2 * 0.3 + 0.2 * 0.1 + 0.3 * 0.1)},            // box
        {-0.4, -0.4, 0, 2 * pi * 0.2 * 0.2},                                 // disk
        {-0.2, -0.5, 0, 2 * pi * 0.1 * 0.25},                                // ellipse
        {-0.2, -0.2, 0.5, 2 * pi * 0.01 + 2 * pi * 0.1 * 0.5},               // vertical cylinder
        {-0.2, -0.4, 0.5, 2 * pi * 0.1 * 0.2 + ellipse_perimeter(0.1, 0.2) * 0.5},
        {-0.2, 0.5, -0.2, 2 * pi * 0.01 + 2 * pi * 0.1 * 0.5},               // horizontal, along
        {-0.2, 0.5, -0.3, 2 * pi * 0.1 * 0.15 + ellipse_perimeter(0.1, 0.15) * 0.5},
        {0.5, -0.2, -0.2, 2 * pi * 0.01 + 2 * pi * 0.1 * 0.5},               // horizontal, across
        {-0.3, -0.3, -0.3, 4 * pi * 0.15 * 0.15},                            // sphere
        {-0.3, 0, -0.3, 2 * pi * 0.15 * 0.15},                               // vertical disk
        {0, -0.3, -0.2, 2 * pi * 0.15 * 0.1},                                // vertical ellipse
    };
    for (const Case& c : cases) {
        PhotometricData d = opening(c.w, c.l, c.h);
        EXPECT_NE(d.shape, LuminousShape::Unknown);
        EXPECT_NEAR(mean_projected_area(d), c.surface / 4, 2e-4 * c.surface)
            << to_string(d.shape) << " " << c.w << " " << c.l << " " << c.h;
    }
    // An ellipsoid's shadow along its axes: pi times the product of the other two semi-axes.
    PhotometricData e = opening(-0.2, -0.4, -0.6);
    EXPECT_EQ(e.shape, LuminousShape::Ellipsoid);
    EXPECT_NEAR(luminous_projected_area(e, Vec3(0, 0, 1)), kPiD * 0.2 * 0.1, 1e-7);
    EXPECT_NEAR(luminous_projected_area(e, Vec3(1, 0, 0)), kPiD * 0.1 * 0.3, 1e-7);
    EXPECT_NEAR(luminous_projected_area(e, Vec3(0, 1, 0)), kPiD * 0.2 * 0.3, 1e-7);
    EXPECT_EQ(luminous_projected_area(opening(0, 0, 0), Vec3(0, 0, 1)), 0);
}

// Guth's index in Levin's form: 1 on the line of sight, undefined (-1) behind the eye, the
// same left and right and (as applied here) above and below, and for a luminaire straight
// above the line of sight (tau = 0) at sigma = 45 degrees
//   ln p = (35.2 - 1.22) 1e-3 * 45 + 21e-5 * 45^2 = 1.95435.
TEST(Glare, PositionIndex) {
    const Vec3 view(0, 1, 0), up(0, 0, 1);
    EXPECT_DOUBLE_EQ(guth_position_index(view, view, up), 1);
    EXPECT_LT(guth_position_index(Vec3(0, -1, 0), view, up), 0);
    EXPECT_LT(guth_position_index(Vec3(1, 0, 0), view, up), 0);  // sigma = 90 degrees
    const Float s = Float(std::sqrt(0.5));
    // (Float directions: tau comes out within about 0.02 degrees of 0, which moves p by a few
    // parts in 1e5.)
    EXPECT_NEAR(guth_position_index(Vec3(0, s, s), view, up), std::exp(1.95435), 2e-4 * 7.06);
    // tau = 90 (level with the eye, 45 degrees to the side):
    //   ln p = (35.2 - 28.7001 - 1.22 e^-20) 1e-3 * 45 + (21 + 24.0003 - 24.0003) 1e-5 * 2025.
    const double tau90 = (35.2 - 0.31889 * 90 - 1.22 * std::exp(-20.0)) * 1e-3 * 45 +
                         (21 + 0.26667 * 90 - 0.002963 * 8100) * 1e-5 * 2025;
    EXPECT_NEAR(guth_position_index(Vec3(s, s, 0), view, up), std::exp(tau90), 2e-4 * std::exp(tau90));
    for (Vec3 v : {Vec3(0.3f, 0.8f, 0.4f), Vec3(-0.5f, 0.7f, 0.2f)}) {
        v = normalize(v);
        const double p = guth_position_index(v, view, up);
        EXPECT_GT(p, 1);
        EXPECT_NEAR(guth_position_index(Vec3(-v.x, v.y, v.z), view, up), p, 1e-5 * p);
        EXPECT_NEAR(guth_position_index(Vec3(v.x, v.y, -v.z), view, up), p, 1e-5 * p);
    }
    // The up vector need not be perpendicular to the view: only its part across it counts.
    EXPECT_NEAR(guth_position_index(Vec3(0, s, s), view, Vec3(0, 0.5f, 1)), std::exp(1.95435),
                2e-4 * 7.06);
}

}  // namespace
}  // namespace sr
