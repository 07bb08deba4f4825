// The bundled scenes parse, build and render without NaN/Inf samples (small and fast: the
// images themselves are checked elsewhere, e.g. the Cornell box against pbrt-v4).
#include <numbers>

#include <gtest/gtest.h>

#include "steradian/film/film.h"
#include "steradian/integrators/integrator.h"
#include "steradian/integrators/measure.h"
#include "steradian/integrators/radiosity/form_factor.h"
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

// The office's direct illuminance on the desk tops is Lambert's: each of its four panels
// (scenes/panel-600.ies: I(gamma) = I0 cos(gamma) from a 0.6 m x 0.6 m opening, i.e. a
// uniformly luminous square of radiance L = I0 / A) gives E = pi L F, F the form factor from
// the point to the square (the contour integral of form_factor.h, itself tested against
// closed forms), nothing being in between.
TEST(BundledScenes, OfficeDirectIlluminanceIsLambertsPolygonFormula) {
    MeasureResult r = measure_scene(
        build_scene(parse_pbrt_file(std::string(STERADIAN_SOURCE_DIR) + "/scenes/office.pbrt"), {}),
        1e-2);
    const MeterReading* direct = nullptr;
    for (const MeterReading& m : r.readings)
        if (m.meter.name == "desk-direct") direct = &m;
    ASSERT_NE(direct, nullptr);
    const double panels[4][2] = {{1.5, 1}, {4.5, 1}, {1.5, 3}, {4.5, 3}};
    const double z = 2.995, a = 0.3, I0 = 1145.916, L = I0 / (4 * a * a);
    ASSERT_EQ(direct->values.size(), 3u);
    for (size_t i = 0; i < 3; ++i) {
        SCOPED_TRACE(i);
        const Point3 p = direct->meter.points[i];
        double e = 0;
        for (const auto& c : panels) {
            const radiosity::DVec3 sq[4] = {{c[0] - a, c[1] - a, z}, {c[0] + a, c[1] - a, z},
                                            {c[0] + a, c[1] + a, z}, {c[0] - a, c[1] + a, z}};
            e += std::numbers::pi * L * radiosity::point_to_polygon(radiosity::DVec3(p.x, p.y, p.z),
                                                       radiosity::DVec3(0, 0, 1), sq, 4);
        }
        // The file tabulates cos(gamma) every degree, interpolated linearly: low by at most
        // h^2/8 = 3.8e-5 of the value (h = 1 deg); the quadrature reports its own error.
        EXPECT_NEAR(direct->values[i], e, 4 * direct->stderrs[i] + 1e-4 * e);
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
