#include "steradian/geometry/hit.h"

#include <gtest/gtest.h>

#include <bit>
#include <cmath>
#include <limits>
#include <vector>

#include "steradian/sampling/rng.h"

namespace sr {
namespace {

void expect_same_bits(Point3 a, Point3 b, const char* what) {
    for (int i = 0; i < 3; ++i)
        EXPECT_EQ(std::bit_cast<uint32_t>(a[i]), std::bit_cast<uint32_t>(b[i]))
            << what << " component " << i << ": " << a[i] << " vs " << b[i];
}

// The oracle is offset_ray_origin_per_component, pbrt-v4's definition written one component
// at a time; its steps are checked against std::nextafter here first.
TEST(OffsetRayOrigin, NextFloatSteps) {
    constexpr Float kMin = std::numeric_limits<Float>::denorm_min();
    constexpr Float kInf = std::numeric_limits<Float>::infinity();
    constexpr Float kMax = std::numeric_limits<Float>::max();
    EXPECT_EQ(next_float_up(0.f), kMin);
    EXPECT_EQ(next_float_up(-0.f), kMin);
    EXPECT_EQ(next_float_down(0.f), -kMin);
    EXPECT_EQ(next_float_down(-0.f), -kMin);
    EXPECT_EQ(next_float_up(1.f), std::nextafter(1.f, 2.f));
    EXPECT_EQ(next_float_down(-1.f), std::nextafter(-1.f, -2.f));
    EXPECT_EQ(next_float_up(kInf), kInf);
    EXPECT_EQ(next_float_down(-kInf), -kInf);
    EXPECT_EQ(next_float_down(kInf), kMax);
    EXPECT_EQ(next_float_up(-kInf), -kMax);
}

// Every sign combination of p, the normal and the side of w, with p at 0, -0, denormals,
// ordinary values, the largest float and infinity, and offsets that are zero in some
// components (axis-aligned normals, including -0 components), and offsets that land exactly
// on 0 (stepped to the smallest denormal of the offset's sign).
TEST(OffsetRayOrigin, MatchesDefinitionBitForBit) {
    constexpr Float kInf = std::numeric_limits<Float>::infinity();
    const std::vector<Float> special = {0.f,
                                        -0.f,
                                        std::numeric_limits<Float>::denorm_min(),
                                        -std::numeric_limits<Float>::denorm_min(),
                                        1e-30f,
                                        -3.5f,
                                        278.f,
                                        -548.7f,
                                        std::numeric_limits<Float>::max(),
                                        -std::numeric_limits<Float>::max(),
                                        kInf,
                                        -kInf};
    const std::vector<Normal3> normals = {Normal3(0, 1, 0),   Normal3(0, -1, 0),
                                          Normal3(-0.f, 0, 1), Normal3(1, -0.f, 0),
                                          normalize(Normal3(1, -2, 3)),
                                          normalize(Normal3(-0.3f, 0.1f, -0.9f))};
    const std::vector<Vec3> errors = {Vec3(0, 0, 0), Vec3(1e-5f, 2e-5f, 3e-5f),
                                      Vec3(1e-38f, 1e-38f, 1e-38f), Vec3(1, 1, 1)};
    int checked = 0;
    for (Float x : special)
        for (Float y : {0.f, -1.f, 1.f, 5.f})  // y = -+1 with a unit offset: po.y = 0
            for (Normal3 n : normals)
                for (Vec3 err : errors)
                    for (Float side : {1.f, -1.f}) {
                        Point3 p(x, y, x == 0 ? -2.f : 0.5f * x);
                        Vec3 w = n * side;
                        expect_same_bits(offset_ray_origin(p, err, n, w),
                                         offset_ray_origin_per_component(p, err, n, w), "special");
                        ++checked;
                    }
    EXPECT_GT(checked, 1000);
}

TEST(OffsetRayOrigin, MatchesDefinitionOnRandomInputs) {
    Pcg32 rng(7);
    auto sym = [&](Float scale) { return (2 * rng.next_float() - 1) * scale; };
    for (int k = 0; k < 200000; ++k) {
        Float scale = std::ldexp(1.f, int(rng.next_u32() % 40) - 20);
        Point3 p(sym(scale), sym(scale), sym(scale));
        Vec3 err = Vec3(std::abs(p.x), std::abs(p.y), std::abs(p.z)) * gamma_bound(7);
        Normal3 n = normalize(Normal3(sym(1), sym(1), sym(1)));
        Vec3 w(sym(1), sym(1), sym(1));
        expect_same_bits(offset_ray_origin(p, err, n, w), offset_ray_origin_per_component(p, err, n, w),
                         "random");
        if (HasFailure()) break;
    }
}

// What the offset is for: the origin leaves the error box on w's side of the surface.
TEST(OffsetRayOrigin, LeavesErrorBoxOnTheSideOfW) {
    Pcg32 rng(11);
    for (int k = 0; k < 10000; ++k) {
        Point3 p(rng.next_float() * 1000, rng.next_float() * 1000 - 500, -rng.next_float());
        Vec3 err = Vec3(std::abs(p.x), std::abs(p.y), std::abs(p.z)) * gamma_bound(7);
        Normal3 n = normalize(Normal3(rng.next_float() - 0.5f, rng.next_float() - 0.5f, 0.3f));
        Vec3 w = (k & 1) ? Vec3(n) : -Vec3(n);
        Point3 po = offset_ray_origin(p, err, n, w);
        // The displacement along n, computed in double, exceeds the error box's extent
        // along n (the box's support |n| . err).
        double along = (double(po.x) - p.x) * n.x + (double(po.y) - p.y) * n.y +
                       (double(po.z) - p.z) * n.z;
        double support = std::abs(n.x) * double(err.x) + std::abs(n.y) * double(err.y) +
                         std::abs(n.z) * double(err.z);
        EXPECT_GE(along * ((k & 1) ? 1 : -1), support * (1 - 1e-6)) << k;
    }
}

}  // namespace
}  // namespace sr
