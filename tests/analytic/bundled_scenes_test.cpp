// The bundled scenes parse, build and render without NaN/Inf samples (small and fast: the
// images themselves are checked elsewhere, e.g. the Cornell box against pbrt-v4).
#include <gtest/gtest.h>

#include "steradian/film/film.h"
#include "steradian/integrators/integrator.h"
#include "steradian/integrators/measure.h"
#include "steradian/scene/build.h"
#include "steradian/scene/pbrt/parser.h"
#include "support/render_util.h"

namespace sr::test {
namespace {

TEST(BundledScenes, MaterialsGalleryRendersCleanly) {
    SceneDesc d = parse_pbrt_file(std::string(STERADIAN_SOURCE_DIR) + "/scenes/materials.pbrt");
    Scene s = build_scene(d, {});
    Film film(s.film);
    RenderOptions ro;
    ro.spp = 2;
    ro.threads = 2;
    RenderStats st = render(s, film, ro);
    EXPECT_EQ(st.nonfinite, 0u);
    EXPECT_EQ(st.spp, 2);
    double sum = 0;
    for (double y : film.luminance()) sum += y;
    EXPECT_GT(sum, 0);
}

// The office's direct illuminance on the desk top is the inverse-square and cosine law summed
// over its four downlights (I(gamma) = 1000 cos(gamma) cd, 2.2 m above the desk, nothing in
// between): E = sum 1000 cos(gamma) cos(theta) / d^2 = sum 1000 h^2 / d^4, as CIE 171:2006
// case 5.2 derives for one of them.
TEST(BundledScenes, OfficeDirectIlluminanceIsTheInverseSquareSum) {
    MeasureResult r = measure_scene(
        build_scene(parse_pbrt_file(std::string(STERADIAN_SOURCE_DIR) + "/scenes/office.pbrt"), {}),
        1e-2);
    const MeterReading* direct = nullptr;
    for (const MeterReading& m : r.readings)
        if (m.meter.name == "desk-direct") direct = &m;
    ASSERT_NE(direct, nullptr);
    const double lights[4][2] = {{1.25, 1}, {3.75, 1}, {1.25, 3}, {3.75, 3}};
    const double h = 2.95 - 0.75;
    ASSERT_EQ(direct->values.size(), 3u);
    for (size_t i = 0; i < 3; ++i) {
        SCOPED_TRACE(i);
        const Point3 p = direct->meter.points[i];
        double e = 0;
        for (const auto& l : lights) {
            double d2 = (p.x - l[0]) * (p.x - l[0]) + (p.y - l[1]) * (p.y - l[1]) + h * h;
            e += 1000 * h * h / (d2 * d2);
        }
        // cos1000.ies tabulates cos(gamma) every 0.5 deg, interpolated linearly: low by at
        // most h^2/8 = 9.5e-6 of the value (h = 0.5 deg), which the exact point-source
        // reading (standard error 0) shows.
        EXPECT_NEAR(direct->values[i], e, 4 * direct->stderrs[i] + 1e-5 * e);
    }
    // Interreflections only add light: the desk's total exceeds its direct part.
    for (const MeterReading& m : r.readings) {
        if (m.meter.name == "desk") {
            EXPECT_GT(m.values[0], direct->values[0]);
        }
    }
}

}  // namespace
}  // namespace sr::test
