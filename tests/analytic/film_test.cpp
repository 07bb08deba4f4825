// The films of pbrt-v4 end to end: a camera sensor's image of a uniformly lit white plane,
// the gbuffer film's auxiliary channels and the spectral film's buckets, each against the
// value the chain of definitions predicts (derivations in the comments).
#include <gtest/gtest.h>

#include <algorithm>
#include <filesystem>
#include <functional>

#include "steradian/film/image_io.h"
#include "steradian/film/sensor.h"
#include "steradian/spectrum/camera_sensors.h"
#include "support/render_util.h"

namespace sr::test {
namespace {

constexpr double kZ = 4.5;  // tolerance in standard errors (two-sided p ~ 7e-6)

/// A plane of constant reflectance rho lit head-on by a distant light of pi lux whose
/// spectrum is a 3000 K blackbody, seen through `film` by an orthographic camera it fills.
/// A Lambertian surface reflects L(l) = rho E(l) / pi; a light of illuminance E_v (lux) and
/// spectrum S has E(l) = E_v S(l) / sum_l ybar S (pbrt-v4's photometric normalisation, 1 nm
/// sums), so L(l) = rho S(l) / sum_l ybar S.
std::string blackbody_plane(const std::string& film, const std::string& camera_extra, double rho,
                            int spp) {
    return fmt::format(R"(
LookAt 0 0 5  0 0 0  0 1 0
Camera "orthographic" "float screenwindow" [ -1 1 -1 1 ] {}
{}
Sampler "zsobol" "integer pixelsamples" [ {} ]
Integrator "path" "integer maxdepth" [ 1 ]
PixelFilter "box"
WorldBegin
LightSource "distant" "point3 from" [ 0 0 1 ] "point3 to" [ 0 0 0 ]
    "blackbody L" [ 3000 ] "float illuminance" [ 3.14159265358979 ]
Material "diffuse" "spectrum reflectance" [ 300 {} 900 {} ]
Shape "bilinearmesh" "point3 P" [ -2 -2 0  2 -2 0  -2 2 0  2 2 0 ]
)",
                       camera_extra, film, spp, rho, rho);
}

/// Planck's law at 3000 K normalised by its 1 nm sum against ybar over 360..830 nm.
std::function<double(double)> normalised_blackbody_3000() {
    double y = 0;
    for (int l = 360; l <= 830; ++l) y += planck(l, 3000) * double(cie_y()(Float(l)));
    return [y](double l) { return planck(l, 3000) / y; };
}

/// Simpson's rule over each 10 nm segment of a piecewise-linear curve times f.
double curve_integral(const PiecewiseLinearSpectrum& c, const std::function<double(double)>& f) {
    const auto &l = *c.lambdas, &v = *c.values;
    double sum = 0;
    for (size_t i = 0; i + 1 < l.size(); ++i) {
        const double a = l[i], b = l[i + 1], h = (b - a) / 100;
        auto g = [&](double x) { return (v[i] + (v[i + 1] - v[i]) * (x - a) / (b - a)) * f(x); };
        double s = g(a) + g(b);
        for (int k = 1; k < 100; ++k) s += (k % 2 ? 4 : 2) * g(a + k * h);
        sum += s * h / 3;
    }
    return sum;
}

// Through a camera sensor (pbrt-v4's PixelSensor), a pixel is
//   rgb = sRGB_from_XYZ * M * (ratio * integral of {r, g, b}(l) L(l) dl)
// with M the least-squares XYZ-from-sensor matrix for daylight of the white balance
// temperature (6500 K by default for a camera), and the imaging ratio
// ratio = exposure time * iso / 100 (here 0.5 s at iso 400: 2). The plane's radiance is
// L(l) = rho S(l) / sum ybar S. Each channel's pixel mean is compared with that prediction
// within 4.5 standard errors estimated from the pixels.
TEST(CameraSensorFilm, WhitePlaneGivesThePredictedSensorRgb) {
    for (const char* wb : {"", "\"float whitebalance\" [ 4000 ]"}) {
        const double rho = 0.8;
        const std::string film = fmt::format(
            R"(Film "rgb" "integer xresolution" [ 16 ] "integer yresolution" [ 16 ]
    "string filename" "x.exr" "string sensor" "nikon_d850" "float iso" [ 400 ] {})",
            wb);
        Rendered r = render_string(blackbody_plane(
            film, R"("float shutteropen" [ 0 ] "float shutterclose" [ 0.5 ])", rho, 64));
        const auto curves = *camera_sensor_curves("nikon_d850");
        const auto L = normalised_blackbody_3000();
        double sensor[3];
        for (int c = 0; c < 3; ++c)
            sensor[c] = 2.0 * curve_integral(curves[c], [&](double l) { return rho * L(l); });
        const Matrix3 m = multiply(
            srgb_from_xyz_matrix(),
            fit_xyz_from_sensor_rgb({curves[0], curves[1], curves[2]},
                                    cie_d_illuminant(*wb ? 4000 : 6500), srgb_illuminant()));
        for (int c = 0; c < 3; ++c) {
            const double expected = m[c][0] * sensor[0] + m[c][1] * sensor[1] + m[c][2] * sensor[2];
            const MeanSe px = mean_se(region(r, 0, 0, 16, 16, c));
            std::printf("wb '%s' channel %d: %.5f +- %.5f (expected %.5f)\n", wb, c, px.mean, px.se,
                        expected);
            EXPECT_GT(expected, 0.05);
            EXPECT_NEAR(px.mean, expected, kZ * px.se + 1e-4 * expected) << c;
        }
    }
}

TEST(CameraSensorFilm, UnknownSensorIsALocatedErrorListingTheNames) {
    const std::string scene = blackbody_plane(
        R"(Film "rgb" "integer xresolution" [ 4 ] "integer yresolution" [ 4 ]
    "string filename" "x.exr" "string sensor" "nikon_d900")",
        "", 0.5, 1);
    try {
        render_string(scene);
        FAIL() << "no error";
    } catch (const Error& e) {
        const std::string msg = e.what();
        EXPECT_NE(msg.find("<test>:5:"), std::string::npos) << msg;
        EXPECT_NE(msg.find("nikon_d900"), std::string::npos) << msg;
        EXPECT_NE(msg.find("cie1931"), std::string::npos) << msg;
        for (const std::string& n : camera_sensor_names())
            EXPECT_NE(msg.find(n), std::string::npos) << n;
    }
}

/// Renders `pbrt` and returns the film's output written to an EXR file and read back.
Image render_to_exr(const std::string& pbrt, const std::string& name) {
    SceneDesc d = parse_pbrt_string(pbrt, "<test>", ".");
    Scene s = build_scene(d, BuildOptions{});
    Film film(s.film);
    RenderOptions ro;
    ro.threads = 2;
    render(s, film, ro);
    const std::string path =
        (std::filesystem::temp_directory_path() / ("steradian_film_test_" + name + ".exr"))
            .string();
    write_image(path, film.output_image());
    Image img = read_exr_channels(path);
    std::filesystem::remove(path);
    return img;
}

int channel(const Image& img, const std::string& name) {
    for (int c = 0; c < img.channels; ++c)
        if (img.channel_names[size_t(c)] == name) return c;
    ADD_FAILURE() << "no channel " << name;
    return 0;
}

/// The plane z = x/2 (world), uv (0,0)..(1,1) over x, y in [-2, 2], reflectance rho, lit head
/// on by a distant light of pi lux, seen by an orthographic camera at z = 5 looking down
/// (screen [-1, 1]^2 on 16 x 16 pixels: 1/8 a pixel) through `film`.
std::string tilted_plane(const std::string& film, int spp) {
    return fmt::format(R"(
LookAt 0 0 5  0 0 0  0 1 0
Camera "orthographic" "float screenwindow" [ -1 1 -1 1 ]
{}
Sampler "zsobol" "integer pixelsamples" [ {} ]
Integrator "path" "integer maxdepth" [ 1 ]
PixelFilter "box"
WorldBegin
LightSource "distant" "point3 from" [ 0 0 1 ] "point3 to" [ 0 0 0 ] "float illuminance" [ 3.14159265358979 ]
Material "diffuse" "spectrum reflectance" [ 300 0.6 900 0.6 ]
Shape "bilinearmesh" "point3 P" [ -2 -2 -1  2 -2 1  -2 2 -1  2 2 1 ]
    "point2 uv" [ 0 0  1 0  0 1  1 1 ]
)",
                       film, spp);
}

// pbrt-v4's camera space (LookAt from (0,0,5) to the origin, up +y): z_c = 5 - z, x_c = -x,
// y_c = y; raster x runs along +x_c and raster y along -y_c, each pixel 1/8 wide. Pixel (i, j)
// centre: x_c = -1 + (i + 1/2)/8, y_c = 1 - (j + 1/2)/8, and on the plane z = x/2 = -x_c/2,
// so depth z_c = 5 + x_c/2. Averaged over the pixel with the box filter, position and uv
// (linear across the pixel) are those of the centre. The normal facing the camera is
// (-1/2, 0, 1)/|.| in world space, (1/2, 0, -1)/|.| in camera space. One pixel in raster x
// changes z_c by 1/16; pbrt-v4 scales ray differentials by max(1/8, 1/sqrt(spp)) = 1/4 at
// 16 spp, so dzdx = 1/64 and dzdy = 0. The albedo of a Lambertian surface is its reflectance,
// 0.6, written as the colour of that reflectance under D65 (0.6 times the sRGB of D65).
TEST(GBufferFilm, TiltedPlaneGivesExactGeometryChannels) {
    const int spp = 16;
    for (const char* cs : {"camera", "world"}) {
        const bool cam = std::string(cs) == "camera";
        Image img =
            render_to_exr(tilted_plane(fmt::format(R"(Film "gbuffer" "integer xresolution" [ 16 ]
    "integer yresolution" [ 16 ] "string filename" "g.exr" "string coordinatesystem" "{}")",
                                                   cs),
                                       spp),
                          cs);
        ASSERT_EQ(img.channels, 25);
        for (const char* n : {"R",
                              "G",
                              "B",
                              "Albedo.R",
                              "Albedo.G",
                              "Albedo.B",
                              "P.X",
                              "P.Y",
                              "P.Z",
                              "dzdx",
                              "dzdy",
                              "N.X",
                              "N.Y",
                              "N.Z",
                              "Ns.X",
                              "Ns.Y",
                              "Ns.Z",
                              "u",
                              "v",
                              "Variance.R",
                              "Variance.G",
                              "Variance.B",
                              "RelativeVariance.R",
                              "RelativeVariance.G",
                              "RelativeVariance.B"})
            channel(img, n);
        // The sample mean of a position uniform over a pixel of width 1/8 has a standard
        // deviation of (1/8)/sqrt(12 spp) (less with stratified samples).
        const double tol = 4.5 * 0.125 / std::sqrt(12.0 * spp);
        const Xyz d65 = spectrum_to_xyz(srgb_illuminant());
        const auto m = srgb_from_xyz_matrix();
        std::vector<double> albedo[3];
        for (int j = 0; j < 16; ++j)
            for (int i = 0; i < 16; ++i) {
                const double xc = -1 + (i + 0.5) / 8, yc = 1 - (j + 0.5) / 8;
                const double zc = 5 + xc / 2;
                const double px = cam ? xc : -xc, pz = cam ? zc : 5 - zc;
                EXPECT_NEAR(img.at(i, j, channel(img, "P.X")), px, tol) << i << " " << j;
                EXPECT_NEAR(img.at(i, j, channel(img, "P.Y")), yc, tol) << i << " " << j;
                EXPECT_NEAR(img.at(i, j, channel(img, "P.Z")), pz, tol / 2) << i << " " << j;
                const double k = 1 / std::sqrt(1.25);
                const double n[3] = {cam ? 0.5 * k : -0.5 * k, 0, cam ? -k : k};
                for (const char* nn : {"N", "Ns"})
                    for (int c = 0; c < 3; ++c)
                        EXPECT_NEAR(img.at(i, j, channel(img, std::string(nn) + "." + "XYZ"[c])),
                                    n[c], 1e-5);
                EXPECT_NEAR(img.at(i, j, channel(img, "dzdx")), 1.0 / 64, 1e-5);
                EXPECT_NEAR(img.at(i, j, channel(img, "dzdy")), 0, 1e-5);
                // u runs along world x over [-2, 2], v along y.
                EXPECT_NEAR(img.at(i, j, channel(img, "u")), (-xc + 2) / 4, tol / 4);
                EXPECT_NEAR(img.at(i, j, channel(img, "v")), (yc + 2) / 4, tol / 4);
                for (const char* v : {"Variance.G", "RelativeVariance.G"})
                    EXPECT_GE(img.at(i, j, channel(img, v)), 0);
                for (int c = 0; c < 3; ++c)
                    albedo[c].push_back(
                        img.at(i, j, channel(img, std::string("Albedo.") + "RGB"[c])));
            }
        for (int c = 0; c < 3; ++c) {
            const double expected = 0.6 * (m[c][0] * d65.x + m[c][1] * d65.y + m[c][2] * d65.z);
            const MeanSe a = mean_se(albedo[c]);
            std::printf("%s albedo %d: %.5f +- %.5f (expected %.5f)\n", cs, c, a.mean, a.se,
                        expected);
            EXPECT_NEAR(a.mean, expected, kZ * a.se + 1e-5);
        }
    }
}

TEST(GBufferFilm, OnlyExrAndKnownCoordinateSystems) {
    auto scene = [](const std::string& extra) {
        return tilted_plane(
            R"(Film "gbuffer" "integer xresolution" [ 4 ] "integer yresolution" [ 4 ]
    )" + extra,
            1);
    };
    for (const char* bad : {R"("string filename" "g.png")", R"("string filename" "g.pfm")",
                            R"("string filename" "g.exr" "string coordinatesystem" "screen")"}) {
        try {
            render_string(scene(bad));
            ADD_FAILURE() << bad;
        } catch (const Error& e) {
            const std::string msg = e.what();
            EXPECT_NE(msg.find("<test>:5:"), std::string::npos) << msg;
            EXPECT_TRUE(msg.find("EXR") != std::string::npos ||
                        msg.find("expected camera or world") != std::string::npos)
                << msg;
        }
    }
}

// A Lambertian plane of reflectance rho = 0.5 lit head on by a distant light of pi lux with
// the linear spectrum S(l) = 0.5 + (l - 360)/470 reflects L(l) = rho S(l) / sum ybar S. The
// spectral film samples wavelengths uniformly over [lambdamin, lambdamax] = [400, 700] and
// writes each of its 6 buckets' mean radiance times pbrt-v4's CIE_Y_integral; S being
// linear, a bucket's mean is S at the bucket's centre.
TEST(SpectralFilm, BucketsHoldTheBucketAveragesOfTheRadiance) {
    const std::string scene = R"(
LookAt 0 0 5  0 0 0  0 1 0
Camera "orthographic" "float screenwindow" [ -1 1 -1 1 ]
Film "spectral" "integer xresolution" [ 16 ] "integer yresolution" [ 16 ] "string filename" "s.exr"
    "integer nbuckets" [ 6 ] "float lambdamin" [ 400 ] "float lambdamax" [ 700 ]
Sampler "zsobol" "integer pixelsamples" [ 64 ]
Integrator "path" "integer maxdepth" [ 1 ]
PixelFilter "box"
WorldBegin
LightSource "distant" "point3 from" [ 0 0 1 ] "point3 to" [ 0 0 0 ]
    "spectrum L" [ 360 0.5 830 1.5 ] "float illuminance" [ 3.14159265358979 ]
Material "diffuse" "spectrum reflectance" [ 300 0.5 900 0.5 ]
Shape "bilinearmesh" "point3 P" [ -2 -2 0  2 -2 0  -2 2 0  2 2 0 ]
)";
    Image img = render_to_exr(scene, "spectral");
    ASSERT_EQ(img.channels, 3 + 6);
    auto S = [](double l) { return 0.5 + (l - 360) / 470; };
    double ys = 0;
    for (int l = 360; l <= 830; ++l) ys += S(l) * double(cie_y()(Float(l)));
    bool has_version = false;
    for (const auto& [k, v] : img.attributes)
        has_version |= k == "spectralLayoutVersion" && v == "1.0";
    EXPECT_TRUE(has_version);
    for (int b = 0; b < 6; ++b) {
        const double centre = 400 + 50 * (b + 0.5);
        const std::string name = fmt::format("S0.{:.3f}nm", centre);
        std::string pbrt_name = name;
        std::replace(pbrt_name.begin(), pbrt_name.end(), '.', ',');
        pbrt_name[2] = '.';  // "S0." keeps its layer separator
        const int c = channel(img, pbrt_name);
        std::vector<double> v;
        for (int j = 0; j < 16; ++j)
            for (int i = 0; i < 16; ++i) v.push_back(img.at(i, j, c));
        const MeanSe m = mean_se(v);
        const double expected = kCieYIntegral * 0.5 * S(centre) / ys;
        std::printf("bucket %s: %.5f +- %.5f (expected %.5f)\n", pbrt_name.c_str(), m.mean, m.se,
                    expected);
        EXPECT_NEAR(m.mean, expected, kZ * m.se + 1e-5 * expected) << pbrt_name;
    }
}

}  // namespace
}  // namespace sr::test
