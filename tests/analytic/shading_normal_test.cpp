// Shading-normal perturbations end to end: a Lambertian plane (reflectance 0.5, flat
// spectrum) under a distant light of pi lux from its geometric normal has luminance
// rho cos(t), t the angle between the perturbed shading normal and the light (L = rho/pi E
// |wi . ns|). A normal map of constant tilt and a linear bump (displacement) ramp each give
// a known t.
#include <gtest/gtest.h>

#include <filesystem>

#include "support/render_util.h"

namespace sr::test {
namespace {

std::string plane_scene(const std::string& material) { return lit_plane_scene(material, 32); }

struct TempDir {
    std::filesystem::path path = std::filesystem::temp_directory_path() / "steradian_shading_normal_test";
    TempDir() { std::filesystem::create_directories(path); }
    ~TempDir() { std::filesystem::remove_all(path); }
};

// Tangent-space normal (sin t, 0, cos t), t = 40 deg, stored linearly as (n + 1) / 2.
TEST(ShadingNormals, NormalMapTiltsTheShadingNormal) {
    TempDir dir;
    const double t = 40 * kPi / 180;
    Image nm;
    nm.width = nm.height = 4;
    nm.channels = 3;
    for (int i = 0; i < 16; ++i)
        for (double c : {(std::sin(t) + 1) / 2, 0.5, (std::cos(t) + 1) / 2}) nm.data.push_back(float(c));
    write_image((dir.path / "n.exr").string(), nm);
    Rendered r = render_string(
        plane_scene(R"(Material "diffuse" "spectrum reflectance" [ 300 0.5 900 0.5 ] "string normalmap" "n.exr")"),
        2, 0, dir.path.string());
    MeanSe m = mean_se(region(r, 2, 2, 14, 14, 3));
    EXPECT_NEAR(m.mean, 0.5 * std::cos(t), 4.5 * m.se + 1e-3);
    // Without the map: rho.
    Rendered flat = render_string(plane_scene(R"(Material "diffuse" "spectrum reflectance" [ 300 0.5 900 0.5 ])"));
    MeanSe f = mean_se(region(flat, 2, 2, 14, 14, 3));
    EXPECT_NEAR(f.mean, 0.5, 4.5 * f.se + 1e-3);
}

// Displacement d = 0.25 x a 2x1 float image (0, 1) with clamp: between the texel centres
// (u in [0.25, 0.75]) d = 0.25 (2u - 0.5), so dd/du = 0.5. On the 2 x 2 plane dpdu = 2 x,
// dpdv = 2 y: dpdu' = (2, 0, 0.5), n' ~ dpdu' x dpdv = (-1, 0, 4), cos t = 4 / sqrt(17).
TEST(ShadingNormals, BumpMapFromADisplacementRamp) {
    TempDir dir;
    Image ramp;
    ramp.width = 2;
    ramp.height = 1;
    ramp.channels = 3;
    ramp.data = {0, 0, 0, 1, 1, 1};
    write_image((dir.path / "ramp.exr").string(), ramp);
    Rendered r = render_string(plane_scene(R"(
Texture "bump" "float" "imagemap" "string filename" "ramp.exr" "string wrap" "clamp" "float scale" 0.25
Material "diffuse" "spectrum reflectance" [ 300 0.5 900 0.5 ] "texture displacement" "bump")"),
                               2, 0, dir.path.string());
    // u in [0.25, 0.75] is raster x in [4, 12); stay clear of the ends of the ramp.
    MeanSe m = mean_se(region(r, 5, 2, 11, 14, 3));
    EXPECT_NEAR(m.mean, 0.5 * 4 / std::sqrt(17.0), 4.5 * m.se + 1e-3);
}

TEST(ShadingNormals, Errors) {
    auto err = [](const std::string& material) {
        try {
            render_string(plane_scene(material), 1, 1);
        } catch (const Error& e) {
            return std::string(e.what());
        }
        return std::string("no error");
    };
    EXPECT_NE(err(R"(Material "diffuse" "string normalmap" "missing.png")").find("normalmap"), std::string::npos);
    EXPECT_NE(err(R"(Material "interface" "string normalmap" "n.png")").find("normalmap"), std::string::npos);
}

}  // namespace
}  // namespace sr::test
