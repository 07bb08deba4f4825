// Perlin's improved noise and the noise textures, against their definitions: gradient noise
// vanishes at lattice points and repeats every 256 cells; FBm and turbulence are the stated
// octave sums; pbrt-v4's dots are disks of radius 0.35 in the cells that have one.
#include "steradian/core/noise.h"

#include <gtest/gtest.h>

#include <cmath>

#include "steradian/material/texture.h"

namespace sr {
namespace {

TEST(PerlinNoise, ZeroAtLatticePointsAndPeriodic) {
    for (int x = -3; x < 300; x += 7)
        for (int y = -5; y < 40; y += 3)
            for (int z = -2; z < 5; ++z) EXPECT_EQ(perlin_noise(Float(x), Float(y), Float(z)), 0);
    double sum_sq = 0;
    int n = 0;
    for (int i = 0; i < 2000; ++i) {
        // Dyadic coordinates, so that x + 256 is exact in float.
        const Float x = Float(i % 97) / 16, y = Float(i % 37) / 8, z = Float(i % 11) / 32;
        const Float v = perlin_noise(x, y, z);
        EXPECT_EQ(v, perlin_noise(x + 256, y, z)) << i;  // the lattice repeats every 256
        EXPECT_LT(std::abs(v), 1.1f);  // |improved noise| stays near 1 (its maximum ~1.04)
        sum_sq += double(v) * v;
        ++n;
    }
    EXPECT_GT(sum_sq / n, 0.01);  // not identically zero between lattice points
}

TEST(PerlinNoise, FbmAndTurbulenceAreTheirOctaveSums) {
    const Point3 p(0.3f, 1.7f, -2.2f);
    EXPECT_EQ(fbm(p, 0.5f, 1), perlin_noise(p));
    const Point3 p2(p.x * 1.99f, p.y * 1.99f, p.z * 1.99f);
    EXPECT_NEAR(fbm(p, 0.5f, 2), perlin_noise(p) + 0.5f * perlin_noise(p2), 1e-6f);
    EXPECT_EQ(turbulence(p, 0.7f, 0), 0.2f);
    EXPECT_NEAR(turbulence(p, 0.7f, 1), std::abs(perlin_noise(p)) + 0.7f * 0.2f, 1e-6f);
}

TEST(DotsTexture, DotsAreDisksOfRadius035) {
    UvMapping m;  // (s, t) = (u, v)
    int cells_with_dots = 0;
    for (int cell = 0; cell < 40; ++cell) {
        const int cs = cell % 8, ct = cell / 8;
        int inside = 0;
        const int k = 200;
        for (int j = 0; j < k; ++j)
            for (int i = 0; i < k; ++i) {
                SurfaceHit h;
                h.uv = Point2(Float(cs) - 0.5f + (Float(i) + 0.5f) / k,
                              Float(ct) - 0.5f + (Float(j) + 0.5f) / k);
                inside += dots_inside(m, h);
            }
        if (inside == 0) continue;
        ++cells_with_dots;
        // A whole disk inside its cell (centre within 0.15 of the middle): area pi 0.35^2,
        // up to the grid's resolution (the perimeter's cells: 2 pi r / (1/k) of them).
        const double area = double(inside) / (k * k);
        EXPECT_NEAR(area, M_PI * 0.35 * 0.35, 2 * M_PI * 0.35 / k) << cell;
    }
    EXPECT_GT(cells_with_dots, 5);
    EXPECT_LT(cells_with_dots, 35);
}

}  // namespace
}  // namespace sr
