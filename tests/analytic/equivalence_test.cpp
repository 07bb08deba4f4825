// Different ways of writing the same geometry must render the same image: a PLY file and
// the equivalent trianglemesh and bilinearmesh (bit-identical: same triangles), and
// ObjectInstance against explicit copies (equal within noise: the instance transform is
// applied by Embree in float, so individual paths differ).
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>

#include "steradian/integrators/path/path.h"
#include "support/render_util.h"

namespace sr::test {
namespace {

const char* kHeader = R"(
LookAt 0 2 -4  0 0.5 0  0 1 0
Camera "perspective" "float fov" [ 45 ]
Film "rgb" "integer xresolution" [ 32 ] "integer yresolution" [ 24 ] "string filename" "x.exr"
Sampler "zsobol" "integer pixelsamples" [ 16 ]
Integrator "path" "integer maxdepth" [ 4 ]
WorldBegin
LightSource "distant" "point3 from" [ 1 3 -1 ] "point3 to" [ 0 0 0 ] "float illuminance" [ 3 ]
LightSource "infinite" "rgb L" [ 0.2 0.25 0.3 ]
Material "diffuse" "rgb reflectance" [ 0.7 0.6 0.5 ]
)";

TEST(Equivalence, PlyTriangleMeshAndBilinearMeshRenderIdentically) {
    auto dir = std::filesystem::temp_directory_path() / "steradian_equiv_test";
    std::filesystem::create_directories(dir);
    {
        std::ofstream f(dir / "quad.ply");
        f << "ply\nformat ascii 1.0\nelement vertex 4\nproperty float x\nproperty float y\n"
             "property float z\nelement face 1\nproperty list uchar int vertex_indices\n"
             "end_header\n-2 0 -2\n2 0 -2\n2 0 2\n-2 0 2\n4 0 1 2 3\n";
    }
    // The PLY quad (0 1 2 3) is split along its 0-2 diagonal: triangles (0 1 2), (0 2 3).
    std::string tri = std::string(kHeader) +
                      "Shape \"trianglemesh\" \"point3 P\" [ -2 0 -2  2 0 -2  2 0 2  -2 0 2 ] "
                      "\"integer indices\" [ 0 1 2  0 2 3 ]\n";
    std::string ply = std::string(kHeader) + "Shape \"plymesh\" \"string filename\" \"quad.ply\"\n";
    Rendered a = render_string(tri, 2, 0, dir.string());
    Rendered b = render_string(ply, 2, 0, dir.string());
    ASSERT_EQ(a.rgb.data.size(), b.rgb.data.size());
    double sum = 0;
    for (size_t i = 0; i < a.rgb.data.size(); ++i) {
        ASSERT_EQ(a.rgb.data[i], b.rgb.data[i]) << "pixel value " << i;
        sum += a.rgb.data[i];
    }
    EXPECT_GT(sum, 0);
    std::filesystem::remove_all(dir);
}

TEST(Equivalence, ObjectInstancesMatchExplicitCopies) {
    std::string inst = std::string(kHeader) + R"(
Shape "bilinearmesh" "point3 P" [ -3 0 -3  3 0 -3  -3 0 3  3 0 3 ]
ObjectBegin "ball"
  Translate 0 0.5 0
  Shape "sphere" "float radius" [ 0.5 ]
ObjectEnd
AttributeBegin Translate -1 0 0 ObjectInstance "ball" AttributeEnd
AttributeBegin Translate 1 0 0.5 Scale 0.8 0.8 0.8 ObjectInstance "ball" AttributeEnd
)";
    std::string copies = std::string(kHeader) + R"(
Shape "bilinearmesh" "point3 P" [ -3 0 -3  3 0 -3  -3 0 3  3 0 3 ]
AttributeBegin Translate -1 0 0 Translate 0 0.5 0 Shape "sphere" "float radius" [ 0.5 ] AttributeEnd
AttributeBegin Translate 1 0 0.5 Scale 0.8 0.8 0.8 Translate 0 0.5 0 Shape "sphere" "float radius" [ 0.5 ] AttributeEnd
)";
    auto with_spp = [](std::string s) {
        s.replace(s.find("[ 16 ]"), 6, "[ 256 ]");
        return s;
    };
    Rendered a = render_string(with_spp(inst));
    Rendered b = render_string(with_spp(copies));
    // Per-pixel differences of two independent estimates: mean zero within its standard error.
    for (int by = 0; by < 3; ++by)
        for (int bx = 0; bx < 4; ++bx) {
            std::vector<double> d;
            for (int y = by * 8; y < by * 8 + 8; ++y)
                for (int x = bx * 8; x < bx * 8 + 8; ++x)
                    d.push_back(a.y[size_t(y) * a.width + x] - b.y[size_t(y) * b.width + x]);
            MeanSe m = mean_se(d);
            double ref = mean_se(region(b, bx * 8, by * 8, bx * 8 + 8, by * 8 + 8)).mean;
            EXPECT_NEAR(m.mean, 0.0, std::max(4.5 * m.se, 1e-6 * ref)) << "block " << bx << "," << by;
        }
}

}  // namespace
}  // namespace sr::test

namespace sr::test {
namespace {

// A crop window renders exactly the pixels of the full image it selects: every sample is a
// function of (pixel, index, dimension, seed) alone.
TEST(Equivalence, CropWindowIsARegionOfTheFullImage) {
    std::string full = std::string(kHeader) + "Shape \"sphere\" \"float radius\" [ 1 ]\n";
    std::string crop = full;
    crop.replace(crop.find("\"string filename\""), 17,
                 "\"float cropwindow\" [ 0.25 0.75 0.5 1 ] \"string filename\"");
    Rendered a = render_string(full);
    Rendered b = render_string(crop);
    ASSERT_EQ(b.width, 16);
    ASSERT_EQ(b.height, 12);
    for (int y = 0; y < b.height; ++y)
        for (int x = 0; x < b.width; ++x)
            for (int c = 0; c < 3; ++c)
                ASSERT_EQ(b.rgb.at(x, y, c), a.rgb.at(x + 8, y + 12, c)) << x << "," << y;
}

// The renderer traces a pixel's camera rays as packets, continues each path from its first
// hit and tests the first vertices' shadow rays as one packet afterwards. Its image must be
// the definition's: each sample on its own (filter, wavelengths and lens from the sampler's
// camera dimensions, then path_li), here rebuilt sample by sample. The scene exercises what
// the packets must get right: a thin lens, 9 stratified samples per pixel (a full packet and
// a partial one), an interface in front of the camera (paths cross it before their first
// scattering vertex), a sphere, a disk, an instance, a distant and an area light.
TEST(Equivalence, PacketRendererMatchesSampleBySamplePathLi) {
    const std::string scene = R"(
LookAt 0 2 -4  0 0.5 0  0 1 0
Camera "perspective" "float fov" [ 45 ] "float lensradius" [ 0.05 ] "float focaldistance" [ 4 ]
Film "rgb" "integer xresolution" [ 24 ] "integer yresolution" [ 18 ] "string filename" "x.exr"
Sampler "stratified" "integer xsamples" [ 3 ] "integer ysamples" [ 3 ]
Integrator "path" "integer maxdepth" [ 5 ]
WorldBegin
LightSource "distant" "point3 from" [ 1 3 -1 ] "point3 to" [ 0 0 0 ] "float illuminance" [ 3 ]
AttributeBegin
  AreaLightSource "diffuse" "rgb L" [ 4 4 4 ]
  Translate 0 3 0
  Rotate 90 1 0 0
  Shape "disk" "float radius" [ 0.7 ]
AttributeEnd
Material "diffuse" "rgb reflectance" [ 0.7 0.6 0.5 ]
Shape "bilinearmesh" "point3 P" [ -3 0 -3  3 0 -3  -3 0 3  3 0 3 ]
ObjectBegin "ball"
  Translate 0 0.5 0
  Shape "sphere" "float radius" [ 0.5 ]
ObjectEnd
AttributeBegin Translate -1 0 0 ObjectInstance "ball" AttributeEnd
AttributeBegin
  Material "interface"
  Translate 0 1 -2.5
  Shape "sphere" "float radius" [ 0.6 ]
AttributeEnd
)";
    Rendered packets = render_string(scene, 2);

    Scene s = build_scene(parse_pbrt_string(scene, "<test>"));
    Film film(s.film);
    std::unique_ptr<Sampler> sampler =
        make_stratified_sampler(s.sampler.x_samples, s.sampler.y_samples, s.sampler.jitter,
                                s.sampler.seed);
    std::vector<PixelSum> sums = film.make_buffer();
    const FilmParams& fp = film.params();
    ASSERT_TRUE(s.camera->uses_lens_sample());
    for (int y = fp.y0; y < fp.y1; ++y)
        for (int x = fp.x0; x < fp.x1; ++x)
            for (int si = 0; si < sampler->samples_per_pixel(); ++si) {
                sampler->start_pixel_sample(Vec2i(x, y), si);
                FilterSample fs = s.filter->sample(sampler->get_pixel_2d());
                SampledWavelengths lambda =
                    SampledWavelengths::sample_visible(sampler->get_pixel_1d());
                Point2 u_lens = sampler->get_2d();
                Ray ray = s.camera->generate_ray(
                    Point2(Float(x) + 0.5f + fs.offset.x, Float(y) + 0.5f + fs.offset.y), u_lens);
                PathCounters counters;
                SampledSpectrum L = path_li(s, ray, lambda, *sampler, counters);
                ASSERT_FALSE(L.has_nonfinite());
                film.add(sums, x, y, film.to_sensor(L, lambda), fs.weight);
            }
    film.merge(sums);
    Image single = film.rgb_image();

    ASSERT_EQ(single.data.size(), packets.rgb.data.size());
    EXPECT_EQ(packets.stats.nonfinite, 0u);
    double total = 0;
    for (size_t i = 0; i < single.data.size(); ++i) {
        // The same samples summed in another order: equal but for a few roundings.
        EXPECT_NEAR(packets.rgb.data[i], single.data[i], 1e-5 * std::abs(single.data[i]) + 1e-9)
            << "pixel value " << i;
        total += single.data[i];
    }
    EXPECT_GT(total, 0);
}


// pbrt-v4's "bool regularize" (PathIntegrator and VolPathIntegrator): once a path has made a
// non-specular bounce, every Trowbridge-Reitz distribution it meets has each alpha below 0.3
// doubled and clamped to [0.1, 0.3] (TrowbridgeReitzDistribution::Regularize). So a scene
// whose mirror is seen only after a diffuse bounce renders, with regularize, exactly as the
// same scene with the mirror's alpha replaced by the regularized one, without it. A spot
// light points down onto the mirror floor; the camera looks up at a diffuse ceiling that the
// spot does not light directly. A smooth mirror's caustic is unreachable by a path tracer
// (a delta light through a delta lobe): without regularize the image is exactly black.
std::string caustic_scene(const std::string& roughness, bool regularize) {
    return std::string(R"(
LookAt 0 0.2 0  0 1 0  0 0 1
Camera "perspective" "float fov" [ 40 ]
Film "rgb" "integer xresolution" [ 16 ] "integer yresolution" [ 16 ] "string filename" "x.exr"
Sampler "zsobol" "integer pixelsamples" [ 16 ]
Integrator "path" "integer maxdepth" [ 3 ] "bool regularize" [ )") +
           (regularize ? "true" : "false") + R"( ]
WorldBegin
LightSource "spot" "point3 from" [ 0.3 0.5 0 ] "point3 to" [ 0.3 0 0 ] "float coneangle" [ 30 ]
    "rgb I" [ 5 5 5 ]
AttributeBegin
  Material "conductor" "bool remaproughness" false "float roughness" [ )" + roughness + R"( ]
    "spectrum eta" "metal-Ag-eta" "spectrum k" "metal-Ag-k"
  Shape "bilinearmesh" "point3 P" [ -10 0 -10  10 0 -10  -10 0 10  10 0 10 ]
AttributeEnd
Material "diffuse" "rgb reflectance" [ 0.8 0.8 0.8 ]
Shape "bilinearmesh" "point3 P" [ -2 1 -2  -2 1 2  2 1 -2  2 1 2 ]
)";
}

void expect_identical(const Rendered& a, const Rendered& b, const char* what) {
    ASSERT_EQ(a.rgb.data.size(), b.rgb.data.size());
    for (size_t i = 0; i < a.rgb.data.size(); ++i)
        ASSERT_EQ(a.rgb.data[i], b.rgb.data[i]) << what << ", pixel value " << i;
}

TEST(Equivalence, RegularizeWidensLobesAfterTheFirstNonSpecularBounceAsPbrtV4) {
    auto sum = [](const Rendered& r) {
        double s = 0;
        for (float v : r.rgb.data) s += v;
        return s;
    };
    const Rendered smooth_plain = render_string(caustic_scene("0", false), 2);
    EXPECT_EQ(sum(smooth_plain), 0.0) << "a smooth mirror's caustic of a delta light";
    const Rendered smooth_regularized = render_string(caustic_scene("0", true), 2);
    EXPECT_GT(sum(smooth_regularized), 0.0);
    // alpha 0 -> 0.1 (the clamp's floor), 0.12 -> 0.24 (doubled), 0.2 -> 0.3 (the ceiling);
    // 0.35 is left alone.
    for (auto [given, widened] : {std::pair{"0", "0.1"}, std::pair{"0.12", "0.24"},
                                  std::pair{"0.2", "0.3"}, std::pair{"0.35", "0.35"}}) {
        const Rendered reg = render_string(caustic_scene(given, true), 2);
        const Rendered wide = render_string(caustic_scene(widened, false), 2);
        expect_identical(reg, wide, given);
    }
}

// The first vertex is never regularized (no non-specular bounce precedes it): the camera sees
// an emitting ceiling in the smooth mirror floor, one bounce only, with and without.
TEST(Equivalence, RegularizeLeavesTheFirstVertexAlone) {
    const std::string scene = R"(
LookAt 0 0.5 -2  0 0 0  0 1 0
Camera "perspective" "float fov" [ 40 ]
Film "rgb" "integer xresolution" [ 16 ] "integer yresolution" [ 16 ] "string filename" "x.exr"
Sampler "zsobol" "integer pixelsamples" [ 8 ]
Integrator "path" "integer maxdepth" [ 1 ] "bool regularize" [ REG ]
WorldBegin
Material "conductor" "float roughness" [ 0 ] "spectrum eta" "metal-Ag-eta" "spectrum k" "metal-Ag-k"
Shape "bilinearmesh" "point3 P" [ -10 0 -10  10 0 -10  -10 0 10  10 0 10 ]
AttributeBegin
  AreaLightSource "diffuse" "rgb L" [ 1 1 1 ]
  Material "diffuse"
  Shape "bilinearmesh" "point3 P" [ -10 2 -10  10 2 -10  -10 2 10  10 2 10 ]
AttributeEnd
)";
    auto with = [&](const char* reg) {
        std::string s = scene;
        s.replace(s.find("REG"), 3, reg);
        return render_string(s, 2);
    };
    const Rendered off = with("false"), on = with("true");
    expect_identical(on, off, "regularize on and off");
    double s = 0;
    for (float v : on.rgb.data) s += v;
    EXPECT_GT(s, 0.0);
}

}  // namespace
}  // namespace sr::test
