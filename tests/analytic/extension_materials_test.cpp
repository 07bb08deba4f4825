// The extension materials end to end, in a white furnace: a sphere under a uniform environment
// of radiance 1, path traced. A material whose albedo is at most 1 everywhere cannot look
// brighter than the environment (L <= 1 at every pixel, in expectation); a Lambertian limit
// (Ks = 0) is invisible (L = 1); "phong" and "modifiedphong" have the same BRDF and differ only
// in sampling, so their images agree in expectation. Tolerances are multiples of the standard
// errors estimated from the renders.
#include <gtest/gtest.h>

#include "support/render_util.h"

namespace sr::test {
namespace {

constexpr double kZ = 4.5;  // tolerance in standard errors

Rendered furnace(const std::string& material) {
    return render_string(furnace_scene(material, 64, 1000));
}

class ConservingMaterial : public ::testing::TestWithParam<const char*> {};
TEST_P(ConservingMaterial, IsNoBrighterThanTheFurnace) {
    Rendered r = furnace(GetParam());
    MeanSe m = mean_se(region(r, 4, 4, 12, 12));  // the sphere covers the centre
    std::printf("%s: %.5f +- %.5f (<= 1)\n", GetParam(), m.mean, m.se);
    EXPECT_LE(m.mean, 1 + kZ * m.se);
    EXPECT_GT(m.mean, 0.5);  // and reflects most of it (albedos near 1)
    EXPECT_EQ(r.stats.nonfinite, 0u);
}
INSTANTIATE_TEST_SUITE_P(
    Extension, ConservingMaterial,
    ::testing::Values(
        R"(Material "phong" "float Kd" 0.3 "float Ks" 0.7 "float exponent" 40)",
        R"(Material "modifiedphong" "float Kd" 0.5 "float Ks" 0.5 "float exponent" 5)",
        R"(Material "ward" "float Kd" 0.2 "float Ks" 0.8 "float alpha_x" 0.3 "float alpha_y" 0.05)",
        R"(Material "ward" "float Kd" 0 "float Ks" 1 "float alpha_x" 0.6)",
        R"(Material "lafortune" "float diffuse" 0.3 "float Cx" [-1] "float Cy" [-1] )"
        R"("float Cz" [1] "float n" [20] "float rhos" [2.4])"));

class LambertianLimit : public ::testing::TestWithParam<const char*> {};
TEST_P(LambertianLimit, IsInvisibleInTheFurnace) {
    Rendered r = furnace(GetParam());
    MeanSe m = mean_se(region(r, 4, 4, 12, 12));
    std::printf("%s: %.5f +- %.5f (expected 1)\n", GetParam(), m.mean, m.se);
    EXPECT_NEAR(m.mean, 1, kZ * m.se + 1e-4);
}
INSTANTIATE_TEST_SUITE_P(Extension, LambertianLimit,
                         ::testing::Values(R"(Material "phong" "float Kd" 1 "float Ks" 0)",
                                           R"(Material "modifiedphong" "float Kd" 1 "float Ks" 0)",
                                           R"(Material "ward" "float Kd" 1 "float Ks" 0)",
                                           R"(Material "lafortune" "float diffuse" 1)"));

TEST(Extension, PhongAndModifiedPhongAgree) {
    const char* params = R"("float Kd" 0.4 "float Ks" 0.5 "float exponent" 15)";
    Rendered a = furnace(fmt::format("Material \"phong\" {}", params));
    Rendered b = furnace(fmt::format("Material \"modifiedphong\" {}", params));
    MeanSe ma = mean_se(region(a, 4, 4, 12, 12)), mb = mean_se(region(b, 4, 4, 12, 12));
    std::printf("phong %.5f +- %.5f, modifiedphong %.5f +- %.5f\n", ma.mean, ma.se, mb.mean, mb.se);
    EXPECT_NEAR(ma.mean, mb.mean, kZ * std::hypot(ma.se, mb.se));
}

}  // namespace
}  // namespace sr::test
