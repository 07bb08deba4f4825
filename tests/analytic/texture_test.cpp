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
    std::string scene = R"(
Scale -1 1 1
LookAt 0 0 5  0 0 0  0 1 0
Camera "orthographic" "float screenwindow" [ -1 1 -1 1 ]
Film "rgb" "integer xresolution" [ 16 ] "integer yresolution" [ 16 ] "string filename" "x.exr"
Sampler "zsobol" "integer pixelsamples" [ 64 ]
Integrator "path" "integer maxdepth" [ 1 ]
PixelFilter "box"
WorldBegin
LightSource "distant" "point3 from" [ 0 0 1 ] "point3 to" [ 0 0 0 ] "float illuminance" [ 3.14159265358979 ]
Texture "img" "spectrum" "imagemap" "string filename" "tex.png" "string wrap" "clamp"
Material "diffuse" "texture reflectance" "img"
Shape "bilinearmesh" "point3 P" [ -1 -1 0  1 -1 0  -1 1 0  1 1 0 ]
    "point2 uv" [ 0 0  1 0  0 1  1 1 ]
)";
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

}  // namespace
}  // namespace sr::test
