// An image texture lit by a distant light of illuminance pi lux at normal incidence (so a
// Lambertian plane's luminance is its reflectance: L = rho E / pi), one bounce, through an
// orthographic camera: each texel's pixel must come back as the texel's linear RGB (the
// 8-bit sRGB code decoded by IEC 61966-2-1), within the RGB-uplift round-trip error and
// the render's standard error (spectral noise only).
#include <gtest/gtest.h>

#include <filesystem>

#include "steradian/spectrum/color.h"
#include "support/render_util.h"

namespace sr::test {
namespace {

void parse_and_build(const std::string& text) { build_scene(parse_pbrt_string(text, "<test>"), {}); }

TEST(Texture, ImageMapTexelsComeBackAsTheirLinearRgb) {
    auto dir = std::filesystem::temp_directory_path() / "steradian_texture_test";
    std::filesystem::create_directories(dir);
    // 2x2 colour blocks of 2x2 texels each (so bilinear filtering is constant inside a
    // block), written as 8-bit sRGB.
    const float lin[4][3] = {{0.8f, 0.2f, 0.1f}, {0.1f, 0.6f, 0.2f}, {0.2f, 0.3f, 0.7f}, {0.5f, 0.5f, 0.5f}};
    Image tex;
    tex.width = 4;
    tex.height = 4;
    tex.channels = 3;
    for (int y = 0; y < 4; ++y)
        for (int x = 0; x < 4; ++x)
            for (float v : lin[(y / 2) * 2 + x / 2]) tex.data.push_back(v);
    write_image((dir / "tex.png").string(), tex);
    std::string scene = lit_plane_scene(R"(
Texture "img" "spectrum" "imagemap" "string filename" "tex.png" "string wrap" "clamp"
Material "diffuse" "texture reflectance" "img"
)", 64);
    Rendered r = render_string(scene, 2, 0, dir.string());
    // Block (i, j) of the image (row j from the top) covers uv [i/2, (i+1)/2] x
    // [1 - (j+1)/2, 1 - j/2]; bilinear lookups are constant within 3/8 of the outer edges,
    // i.e. in the outer 6 of each quadrant's 8 pixel columns and rows: use 4 x 4 of them.
    for (int j = 0; j < 2; ++j)
        for (int i = 0; i < 2; ++i) {
            // The 8-bit code the PNG holds, decoded.
            for (int c = 0; c < 3; ++c) {
                float code = std::round(srgb_encode(lin[j * 2 + i][c]) * 255) / 255;
                double expected = srgb_decode(code);
                // With Scale -1 1 1 (as the Cornell box) raster x follows world +x = u;
                // raster y runs down, image rows too: block (i, j) is raster [8i, 8i+8) x
                // [8j, 8j+8); its constant part is the outer 6 columns and rows.
                int x0 = i == 0 ? 1 : 11, y0 = j == 0 ? 1 : 11;
                MeanSe m = mean_se(region(r, x0, y0, x0 + 4, y0 + 4, c));
                EXPECT_NEAR(m.mean, expected, 4.5 * m.se + 5e-3)
                    << "texel " << i << "," << j << " channel " << c << " se " << m.se;
            }
        }
    std::filesystem::remove_all(dir);
}

// pbrt-v4's composite textures: a 2x2 checkerboard (uscale = vscale = 2) whose squares are
// tex1 = "scale" (0.5 x a float "scale" texture 0.8 x 1 = 0.4) and tex2 = "mix" of 0.2 and
// 0.6 with amount 0.25 (itself a float "mix": 0.25 = (1 - 0.5) 0 + 0.5 x 0.5), i.e.
// 0.75 x 0.2 + 0.25 x 0.6 = 0.3. Spectrally flat values under a light of pi lux: each
// square's luminance is its reflectance.
TEST(Texture, CheckerboardScaleAndMix) {
    std::string scene = lit_plane_scene(R"(
Texture "k" "float" "scale" "float tex" 0.8 "float scale" 1
Texture "a" "float" "mix" "float tex1" 0 "float tex2" 0.5 "float amount" 0.5
Texture "s" "spectrum" "scale" "spectrum tex" [ 300 0.5 900 0.5 ] "texture scale" "k"
Texture "m" "spectrum" "mix" "spectrum tex1" [ 300 0.2 900 0.2 ] "spectrum tex2" [ 300 0.6 900 0.6 ]
    "texture amount" "a"
Texture "checks" "spectrum" "checkerboard" "texture tex1" "s" "texture tex2" "m"
    "float uscale" 2 "float vscale" 2
Material "diffuse" "texture reflectance" "checks"
)", 64);
    Rendered r = render_string(scene);
    // Block (i, j) (row j from the top) covers u in [i/2, (i+1)/2], v in [1 - (j+1)/2,
    // 1 - j/2]: floor(2u) + floor(2v) = i + (1 - j), even -> tex1 (0.4), odd -> tex2 (0.3).
    for (int j = 0; j < 2; ++j)
        for (int i = 0; i < 2; ++i) {
            double expected = (i + 1 - j) % 2 == 0 ? 0.4 : 0.3;
            int x0 = i == 0 ? 1 : 11, y0 = j == 0 ? 1 : 11;
            MeanSe m = mean_se(region(r, x0, y0, x0 + 4, y0 + 4, 3));
            EXPECT_NEAR(m.mean, expected, 4.5 * m.se + 1e-3) << "square " << i << "," << j;
        }
}

// pbrt-v4's "planar" mapping: s = p . v1 + udelta, t = p . v2 + vdelta with p in the
// texture's space (the CTM at the Texture directive). On the lit square [-1, 1]^2 (world x
// along raster x, y up) with the default v1 = x, v2 = y, unit checks make the quadrants
// alternate: floor(x) + floor(y) is even in the top right and bottom left; a texture defined
// after "Translate 1 0 0" sees x - 1, which swaps them.
TEST(Texture, PlanarMappingFollowsTheTexturesSpace) {
    for (int shifted = 0; shifted < 2; ++shifted) {
        std::string scene = lit_plane_scene(std::string(shifted ? "AttributeBegin\nTranslate 1 0 0\n" : "") + R"(
Texture "checks" "spectrum" "checkerboard" "string mapping" "planar"
    "spectrum tex1" [ 300 0.4 900 0.4 ] "spectrum tex2" [ 300 0.3 900 0.3 ]
)" + (shifted ? "AttributeEnd\n" : "") + R"(
Material "diffuse" "texture reflectance" "checks"
)", 64);
        Rendered r = render_string(scene);
        for (int j = 0; j < 2; ++j)
            for (int i = 0; i < 2; ++i) {
                // Block i = 1 is x in (0, 1), row j = 0 is y in (0, 1): floor(x) + floor(y)
                // = (i - 1) - j (one less with the shift).
                const bool even = (i - j + 1 + shifted) % 2 == 0;
                const double expected = even ? 0.4 : 0.3;
                int x0 = i == 0 ? 2 : 10, y0 = j == 0 ? 2 : 10;
                MeanSe m = mean_se(region(r, x0, y0, x0 + 4, y0 + 4, 3));
                EXPECT_NEAR(m.mean, expected, 4.5 * m.se + 1e-3)
                    << "square " << i << "," << j << " shifted " << shifted;
            }
    }
}

// pbrt-v4's "bilerp" (corners v00, v10, v01, v11 at (s, t) = (0,0), (1,0), (0,1), (1,1)):
// the average of a bilinear function over a block of pixels is its value at the block's
// centre, so each 4 x 4 block reads the corners' blend there. "directionmix" with
// dir = (0, 0.6, 0.8) on the plane of normal +z mixes 0.8 tex1 + 0.2 tex2.
TEST(Texture, BilerpAndDirectionMix) {
    Rendered r = render_string(lit_plane_scene(R"(
Texture "b" "spectrum" "bilerp" "spectrum v00" [ 300 0.1 900 0.1 ] "spectrum v10" [ 300 0.2 900 0.2 ]
    "spectrum v01" [ 300 0.3 900 0.3 ] "spectrum v11" [ 300 0.4 900 0.4 ]
Material "diffuse" "texture reflectance" "b"
)", 64));
    for (int by = 0; by < 4; ++by)
        for (int bx = 0; bx < 4; ++bx) {
            const double u = (bx * 4 + 2) / 16.0, v = 1 - (by * 4 + 2) / 16.0;
            const double expected =
                (1 - u) * (1 - v) * 0.1 + u * (1 - v) * 0.2 + (1 - u) * v * 0.3 + u * v * 0.4;
            MeanSe m = mean_se(region(r, bx * 4, by * 4, bx * 4 + 4, by * 4 + 4, 3));
            EXPECT_NEAR(m.mean, expected, 4.5 * m.se + 1e-3) << bx << "," << by;
        }
    Rendered d = render_string(lit_plane_scene(R"(
Texture "d" "spectrum" "directionmix" "spectrum tex1" [ 300 0.5 900 0.5 ]
    "spectrum tex2" [ 300 0.25 900 0.25 ] "vector3 dir" [ 0 0.6 0.8 ]
Material "diffuse" "texture reflectance" "d"
)", 64));
    MeanSe m = mean_se(region(d, 0, 0, 16, 16, 3));
    EXPECT_NEAR(m.mean, 0.8 * 0.5 + 0.2 * 0.25, 4.5 * m.se + 1e-3);
}

TEST(Texture, CompositeTextureErrors) {
    auto err = [](const std::string& tex) {
        try {
            parse_and_build(std::string("Camera \"perspective\"\nWorldBegin\n") + tex);
        } catch (const Error& e) {
            return std::string(e.what());
        }
        return std::string("no error");
    };
    EXPECT_NE(err("Texture \"c\" \"float\" \"checkerboard\" \"integer dimension\" 3\n").find("3D"),
              std::string::npos);
    EXPECT_NE(err("Texture \"c\" \"spectrum\" \"mix\" \"texture tex1\" \"nope\"\n").find("unknown spectrum texture"),
              std::string::npos);
    EXPECT_NE(err("Texture \"c\" \"float\" \"scale\" \"float bogus\" 1\n").find("bogus"), std::string::npos);
    EXPECT_NE(err("Texture \"c\" \"float\" \"checkerboard\" \"string mapping\" \"conical\"\n")
                  .find("unknown texture mapping \"conical\""),
              std::string::npos);
    // uscale belongs to the "uv" mapping only, as in pbrt-v4: unused elsewhere.
    EXPECT_NE(err("Texture \"c\" \"float\" \"checkerboard\" \"string mapping\" \"planar\" \"float uscale\" 2\n")
                  .find("uscale"),
              std::string::npos);
}

// A texture much finer than a pixel renders as its area average (pbrt-v4's MIP-mapped
// filtering over the pixel footprint), not as the aliased value of whichever texel a sample
// hits: a 256 x 256 checker of single texels 0.2 / 0.8 on a plane 16 pixels wide is 16
// texels per pixel; at 4 spp pbrt-v4's footprint scale is 1/2, i.e. 8 texels, which selects
// level 4 of the pyramid, whose texels are all exactly 0.5. So every pixel must equal, to
// float rounding, the same render of a uniform 0.5 image (same samples, same wavelengths):
// the comparison removes the spectral noise both share. Unfiltered, the pixels would be
// averages of 4 texel values, 0.2 to 0.8.
TEST(Texture, ATextureFinerThanAPixelRendersAsItsAreaAverage) {
    auto dir = std::filesystem::temp_directory_path() / "steradian_texture_filter_test";
    std::filesystem::create_directories(dir);
    Image fine;
    fine.width = fine.height = 256;
    fine.channels = 3;
    for (int y = 0; y < 256; ++y)
        for (int x = 0; x < 256; ++x)
            for (int c = 0; c < 3; ++c) fine.data.push_back((x + y) % 2 ? 0.8f : 0.2f);
    write_image((dir / "fine.exr").string(), fine);
    Image flat;
    flat.width = flat.height = 1;
    flat.channels = 3;
    flat.data = {0.5f, 0.5f, 0.5f};
    write_image((dir / "flat.exr").string(), flat);
    auto scene = [](const std::string& file, const std::string& filter) {
        return lit_plane_scene("Texture \"img\" \"spectrum\" \"imagemap\" \"string filename\" \"" +
                                   file + "\" \"string filter\" \"" + filter +
                                   "\"\nMaterial \"diffuse\" \"texture reflectance\" \"img\"\n",
                               4);
    };
    const Rendered ref = render_string(scene("flat.exr", "bilinear"), 2, 0, dir.string());
    for (const char* filter : {"bilinear", "trilinear", "ewa", "point"}) {
        const Rendered r = render_string(scene("fine.exr", filter), 2, 0, dir.string());
        double worst = 0;
        for (size_t i = 0; i < r.y.size(); ++i)
            worst = std::max(worst, std::abs(r.y[i] - ref.y[i]) / std::max(ref.y[i], 1e-3));
        // Every filter reads levels 3 and up here (EWA: the minor axis, 8 texels), all 0.5.
        EXPECT_LT(worst, 1e-4) << filter;
    }
    std::filesystem::remove_all(dir);
}

}  // namespace
}  // namespace sr::test
