#include "steradian/integrators/bdpt/bdpt.h"

#include <gtest/gtest.h>

#include "steradian/integrators/integrator.h"
#include "steradian/sampling/rng.h"
#include "steradian/scene/build.h"
#include "steradian/scene/pbrt/parser.h"
#include "steradian/scene/scene.h"

namespace sr {
namespace {

// A closed box of diffuse walls with a one-sided area light, a glass sphere, a mirror
// sphere and a rough metal block: paths through specular, glossy and diffuse vertices.
const char* kMixedScene = R"(
LookAt 0 1 -3.5  0 1 0  0 1 0
Camera "perspective" "float fov" [ 50 ]
Film "rgb" "integer xresolution" [ 32 ] "integer yresolution" [ 32 ] "string filename" "x.exr"
Sampler "independent" "integer pixelsamples" [ 4 ]
Integrator "bdpt" "integer maxdepth" [ 8 ]
WorldBegin
AttributeBegin
  Material "diffuse" "rgb reflectance" [ 0.7 0.7 0.7 ]
  Shape "trianglemesh" "point3 P" [ -2 0 -4  2 0 -4  2 0 2  -2 0 2 ] "integer indices" [ 0 1 2 0 2 3 ]
  Shape "trianglemesh" "point3 P" [ -2 2.5 -4  -2 2.5 2  2 2.5 2  2 2.5 -4 ] "integer indices" [ 0 1 2 0 2 3 ]
  Shape "trianglemesh" "point3 P" [ -2 0 2  2 0 2  2 2.5 2  -2 2.5 2 ] "integer indices" [ 0 1 2 0 2 3 ]
  Shape "trianglemesh" "point3 P" [ -2 0 -4  -2 0 2  -2 2.5 2  -2 2.5 -4 ] "integer indices" [ 0 1 2 0 2 3 ]
  Shape "trianglemesh" "point3 P" [ 2 0 -4  2 2.5 -4  2 2.5 2  2 0 2 ] "integer indices" [ 0 1 2 0 2 3 ]
AttributeEnd
AttributeBegin
  AreaLightSource "diffuse" "rgb L" [ 10 10 10 ]
  Shape "trianglemesh" "point3 P" [ -0.5 2.49 0  -0.5 2.49 1  0.5 2.49 1  0.5 2.49 0 ] "integer indices" [ 0 1 2 0 2 3 ]
AttributeEnd
AttributeBegin
  Material "dielectric" "float eta" [ 1.5 ]
  Translate -0.7 0.5 0.5
  Shape "sphere" "float radius" [ 0.5 ]
AttributeEnd
AttributeBegin
  Material "conductor" "float roughness" [ 0 ]
  Translate 0.8 0.4 1
  Shape "sphere" "float radius" [ 0.4 ]
AttributeEnd
AttributeBegin
  Material "conductor" "float roughness" [ 0.3 ]
  Translate 0.2 0.3 -0.5
  Shape "sphere" "float radius" [ 0.3 ]
AttributeEnd
)";

/// The mixed scene filled with fog (camera and light in it, every surface with fog on both
/// sides): complete paths then have medium vertices, whose densities are the phase
/// function's with no cosine in the conversion to area densities.
std::string foggy_mixed_scene() {
    std::string s = kMixedScene;
    s = "MakeNamedMedium \"fog\" \"string type\" \"homogeneous\" \"spectrum sigma_a\" [ 300 0.05 "
        "900 0.05 ] \"spectrum sigma_s\" [ 300 0.4 900 0.4 ] \"float g\" [ 0.5 ]\n"
        "MediumInterface \"\" \"fog\"\n" +
        s;
    s.replace(s.find("WorldBegin"), 10, "WorldBegin\nMediumInterface \"fog\" \"fog\"");
    return s;
}

/// Checks the weights over random complete paths of 3 to 9 vertices; returns the number of
/// paths with a medium vertex.
int check_weights(const std::string& text) {
    Scene scene = build_scene(parse_pbrt_string(text, "<test>", "."));
    BidirContext ctx(scene);
    std::unique_ptr<Sampler> sampler = make_sampler("independent", 1 << 20, Vec2i(32, 32), 3);
    int paths = 0, with_specular = 0, with_medium = 0;
    for (int n = 3; n <= 9; ++n) {
        int found = 0;
        for (int i = 0; i < 400000 && found < 40; ++i) {
            sampler->start_pixel_sample(Vec2i(i % 32, (i / 32) % 32), i / 1024 + n * 1000);
            const Point2 up = sampler->get_pixel_2d();
            SampledWavelengths lambda = SampledWavelengths::sample_visible(sampler->get_pixel_1d());
            const Ray ray = scene.camera->generate_ray(
                Point2(Float(i % 32) + up.x, Float((i / 32) % 32) + up.y), Point2(0.5f, 0.5f));
            auto w = bdpt_test::mis_weights_of_camera_path(ctx, ray, lambda, *sampler, n);
            if (w.empty()) continue;
            ++found;
            double sum = 0, direct_sum = 0;
            for (const auto& c : w) {
                sum += c.recursive;
                direct_sum += c.direct;
                EXPECT_NEAR(c.recursive, c.direct, 2e-3 + 2e-3 * c.direct)
                    << "n " << n << " s " << c.s;
            }
            EXPECT_NEAR(sum, 1.0, 2e-3) << "path of " << n << " vertices";
            EXPECT_NEAR(direct_sum, 1.0, 1e-9);
            with_specular += int(w.size()) < n;  // some strategy impossible: a specular vertex
            with_medium += w[0].medium_vertices > 0;
        }
        EXPECT_GE(found, 10) << "too few complete paths of " << n << " vertices";
        paths += found;
    }
    EXPECT_GT(with_specular, 10);
    EXPECT_GT(paths, 100);
    return with_medium;
}

// Veach's recursion (sec. 10.2.1) gives each strategy's power-heuristic weight from ratios
// of neighbouring densities; the weights of all strategies that can make a path must sum to
// 1, and each must equal p_s^2 / sum_i p_i^2 computed directly from the path's densities
// (eq. 10.9 with exponent 2). Checked over random complete paths (camera paths that end on
// the light) through diffuse, glossy and specular vertices, of 3 to 9 vertices.
TEST(BdptMis, WeightsOfAllStrategiesSumToOneAndMatchTheDirectFormula) {
    EXPECT_EQ(check_weights(kMixedScene), 0);
}

// The same with medium vertices on the paths (scattering in fog between the surfaces).
TEST(BdptMis, WeightsSumToOneAndMatchTheDirectFormulaWithMediumVertices) {
    EXPECT_GT(check_weights(foggy_mixed_scene()), 50);
}

// The camera's importance is normalised so that its integral over the film (over the
// directions of one lens point) is 1: a sample of sample_wi() towards points spread over
// the scene weighs We cos / pdf; integrating We cos over directions, by uniform sampling of
// the directions in the camera's view, gives 1 (pinhole) for any film aspect.
TEST(CameraImportance, IntegratesToOneOverTheFilm) {
    for (const char* cam : {R"(Camera "perspective" "float fov" [ 40 ])",
                            R"(Camera "perspective" "float fov" [ 70 ] "float screenwindow" [ -1 1 -0.5 0.5 ])"}) {
        const std::string text = std::string("LookAt 0 0 0  0 0 1  0 1 0\n") + cam + R"(
Film "rgb" "integer xresolution" [ 64 ] "integer yresolution" [ 32 ] "string filename" "x.exr"
WorldBegin
Shape "sphere" "float radius" [ 100 ]
)";
        Scene scene = build_scene(parse_pbrt_string(text, "<test>", "."));
        // Uniform directions on the forward hemisphere: E[We cos / pdf] = integral of We cos.
        double sum = 0;
        const int n = 400000;
        Pcg32 rng(7, 12345);
        for (int i = 0; i < n; ++i) {
            const Float u1 = rng.next_float(), u2 = rng.next_float();
            const Float z = u1, r = std::sqrt(std::max(Float(0), 1 - z * z));
            const Vec3 d(r * std::cos(2 * kPi * u2), r * std::sin(2 * kPi * u2), z);
            Point2 pr;
            const Float we = scene.camera->we(Ray{Point3(0, 0, 0), d, kInfinity}, &pr);
            if (pr.x < 0 || pr.x >= 64 || pr.y < 0 || pr.y >= 32) continue;
            sum += double(we) * z * (2 * kPi);
        }
        const double est = sum / n;
        EXPECT_NEAR(est, 1.0, 0.02) << cam;
    }
}

}  // namespace
}  // namespace sr
