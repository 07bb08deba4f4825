#include "steradian/integrators/report.h"

#include <cmath>
#include <numbers>
#include <regex>

#include <fmt/format.h>

#include <gtest/gtest.h>

#include "steradian/integrators/measure.h"
#include "steradian/lights/photometric/photometric.h"
#include "steradian/scene/build.h"
#include "steradian/scene/pbrt/parser.h"
#include "steradian/scene/scene.h"

namespace sr {
namespace {

// A field linear in the lattice coordinates, f = 2 i + 3 j: its level line f = L is the
// straight line 2x + 3y = L, which linear interpolation along cell edges reproduces exactly.
TEST(Report, ContourOfALinearFieldLiesOnItsLevelLine) {
    const int nx = 11, ny = 9;
    std::vector<double> v(size_t(nx) * ny);
    for (int j = 0; j < ny; ++j)
        for (int i = 0; i < nx; ++i) v[size_t(j) * nx + i] = 2.0 * i + 3.0 * j;
    for (double level : {0.5, 7.3, 20.0 + 1.0 / 3, 37.9}) {
        std::vector<ContourSegment> segs = contour_segments(v, nx, ny, level);
        ASSERT_FALSE(segs.empty()) << level;
        double total = 0;
        for (const ContourSegment& g : segs) {
            EXPECT_NEAR(2 * g.x0 + 3 * g.y0, level, 1e-9);
            EXPECT_NEAR(2 * g.x1 + 3 * g.y1, level, 1e-9);
            total += std::hypot(g.x1 - g.x0, g.y1 - g.y0);
        }
        // The chord of the line 2x + 3y = L clipped to [0, 10] x [0, 8]: x runs over
        // [max(0, (L - 24) / 2), min(10, L / 2)], and the chord is that span times
        // sqrt(1 + (2/3)^2).
        const double xa = std::max(0.0, (level - 24) / 2), xb = std::min(10.0, level / 2);
        EXPECT_NEAR(total, (xb - xa) * std::sqrt(1 + 4.0 / 9), 1e-9) << level;
    }
    // No line outside the range of the values.
    EXPECT_TRUE(contour_segments(v, nx, ny, -1).empty());
    EXPECT_TRUE(contour_segments(v, nx, ny, 2.0 * 10 + 3.0 * 8 + 1).empty());
}

// A saddle f = (x - 1/2)(y - 1/2) on one cell: the corners (0,0) and (1,1) are above 0.01,
// the other two below; the centre's mean (0) is below, so the lines cut off the two high
// corners, each crossing the two edges that meet there.
TEST(Report, SaddleCellsJoinBySideOfTheCentre) {
    std::vector<double> v = {0.25, -0.25, -0.25, 0.25};  // (0,0) (1,0) (0,1) (1,1)
    std::vector<ContourSegment> segs = contour_segments(v, 2, 2, 0.01);
    ASSERT_EQ(segs.size(), 2u);
    for (const ContourSegment& g : segs) {
        const double mx = (g.x0 + g.x1) / 2, my = (g.y0 + g.y1) / 2;
        // Each segment sits in the quadrant of a high corner: (0,0) or (1,1).
        EXPECT_TRUE((mx < 0.5 && my < 0.5) || (mx > 0.5 && my > 0.5)) << mx << " " << my;
    }
    // At -0.01 the centre is above: the lines now cut off the low corners (1,0) and (0,1).
    segs = contour_segments(v, 2, 2, -0.01);
    ASSERT_EQ(segs.size(), 2u);
    for (const ContourSegment& g : segs) {
        const double mx = (g.x0 + g.x1) / 2, my = (g.y0 + g.y1) / 2;
        EXPECT_TRUE((mx > 0.5 && my < 0.5) || (mx < 0.5 && my > 0.5)) << mx << " " << my;
    }
}

TEST(Report, ContourLevelsAreNiceStepsInsideTheRange) {
    // 0..100 with at most 10 levels: steps 1, 2, 2.5 and 5 give 99, 49, 39 and 19 levels
    // strictly inside; 10 gives 9: 10, 20, ..., 90.
    std::vector<double> l = contour_levels(0, 100, 10);
    ASSERT_EQ(l.size(), 9u);
    for (size_t k = 0; k < l.size(); ++k) EXPECT_DOUBLE_EQ(l[k], 10.0 * (k + 1));
    // 312..498, at most 8: step 25 gives 325, 350, ..., 475 (7 levels); 20 would give 9.
    l = contour_levels(312, 498, 8);
    ASSERT_EQ(l.size(), 7u);
    EXPECT_DOUBLE_EQ(l.front(), 325);
    EXPECT_DOUBLE_EQ(l.back(), 475);
    EXPECT_TRUE(contour_levels(5, 5, 10).empty());
    EXPECT_TRUE(contour_levels(0, NAN, 10).empty());
}

PhotometricData isotropic(double cd, double lamp_lumens) {
    PhotometricData d;
    d.vertical_angles = {0, 90, 180};
    d.horizontal_angles = {0};
    d.candela = {{cd, cd, cd}};
    d.lamp_lumens = lamp_lumens;
    d.num_lamps = 1;
    return d;
}

// The polar diagram of an isotropic distribution is a circle about the centre whose radius
// is the intensity over the outer ring's value times the outer ring's radius.
TEST(Report, PolarPlotOfAnIsotropicSourceIsACircle) {
    const double four_pi = 4 * std::numbers::pi;
    for (auto [cd, lumens, factor, outer] :
         {std::tuple{100.0, -1.0, 1.0, 100.0},
          std::tuple{100.0, four_pi * 100, 1000 / (four_pi * 100), 100.0},
          std::tuple{37.0, -1.0, 1.0, 50.0}}) {
        PhotometricData d = isotropic(cd, lumens);
        PolarScale sc = polar_plot_scale(d);
        EXPECT_NEAR(sc.factor, factor, 1e-12);
        EXPECT_EQ(sc.unit, lumens > 0 ? "cd/klm" : "cd");
        // The nice outer value: 100 cd -> 100; 100 cd of a 4 pi 100 lm lamp = 79.58 cd/klm ->
        // 100; 37 -> 50.
        EXPECT_DOUBLE_EQ(sc.outer, outer);
        const int size = 320;
        const double c = size / 2.0, R = size / 2.0 - 24;
        const std::string svg = polar_plot_svg(d, size);
        // The first <path> is the C0-C180 line: every vertex at the circle's radius.
        const size_t a = svg.find("<path d=\""), b = svg.find('"', a + 9);
        ASSERT_NE(a, std::string::npos);
        const std::string path = svg.substr(a + 9, b - a - 9);
        std::regex vertex(R"([ML](-?[0-9.]+) (-?[0-9.]+))");
        int n = 0;
        for (auto it = std::sregex_iterator(path.begin(), path.end(), vertex);
             it != std::sregex_iterator(); ++it, ++n) {
            const double x = std::stod((*it)[1]), y = std::stod((*it)[2]);
            EXPECT_NEAR(std::hypot(x - c, y - c), R * cd * factor / outer, 0.02);
        }
        EXPECT_EQ(n, 361);  // gamma 180 .. 0 on the left, 1 .. 180 on the right
    }
}

TEST(Report, HtmlEscapesMarkup) {
    EXPECT_EQ(html_escape("a<b & \"c\" 'd'>"), "a&lt;b &amp; &quot;c&quot; &#39;d&#39;&gt;");
}

// A grid under one isotropic point source above a black floor: the report's table gives the
// measured figures (E_avg, E_min, E_max, U0 and E_min / E_max as the readings define them),
// and the page is self-contained (no external resource) with balanced SVG elements.
TEST(Report, PageCarriesTheGridFiguresAndNothingExternal) {
    const std::string text = R"(
LookAt 0 0 5  0 0 0  0 1 0
Camera "perspective"
Film "rgb" "integer xresolution" [8] "integer yresolution" [8]
WorldBegin
LightSource "point" "point3 from" [0 0 2] "blackbody I" [3000]
Material "diffuse" "rgb reflectance" [0 0 0]
Shape "bilinearmesh" "point3 P" [-5 -5 0  5 -5 0  -5 5 0  5 5 0]
Meter "illuminancegrid" "string name" "floor" "point3 corner" [-2 -2 0.001] "vector3 u" [4 0 0]
  "vector3 v" [0 4 0] "integer resolution" [6 5]
Meter "illuminance" "string name" "centre" "point3 p" [0 0 0.001] "normal n" [0 0 1]
)";
    Scene scene = build_scene(parse_pbrt_string(text, "<test>"));
    MeasureOptions mo;
    mo.rel_error = 1e-2;
    mo.threads = 1;
    MeasureResult r = measure(scene, mo);
    ReportOptions ro;
    ro.scene_path = "grid.pbrt";
    const std::string html = measure_report_html(scene, r, ro);
    const MeterReading& g = r.readings[0];
    ASSERT_EQ(g.meter.kind, MeterKind::Grid);
    // U0 and E_min / E_max from the readings' own definitions.
    double mn = 1e300, mx = 0, sum = 0;
    for (double v : g.values) mn = std::min(mn, v), mx = std::max(mx, v), sum += v;
    EXPECT_NEAR(g.uniformity, mn / (sum / g.values.size()), 1e-12);
    EXPECT_NE(html.find(fmt::format("<td>{:.3f}</td>", g.uniformity)), std::string::npos);
    EXPECT_NE(html.find(fmt::format("<td>{:.3f}</td>", mn / mx)), std::string::npos);
    EXPECT_NE(html.find(fmt::format("{:.4g} &plusmn;", g.avg)), std::string::npos);
    EXPECT_NE(html.find("lx"), std::string::npos);
    // Self-contained: no link, script, image source or URL other than the SVG namespace.
    EXPECT_EQ(html.find("<script"), std::string::npos);
    EXPECT_EQ(html.find("<link"), std::string::npos);
    EXPECT_EQ(html.find("src="), std::string::npos);
    std::string rest = html;
    for (size_t p; (p = rest.find("http")) != std::string::npos; rest = rest.substr(p + 4))
        EXPECT_EQ(rest.compare(p, 26, "http://www.w3.org/2000/svg"), 0);
    auto count = [&](const std::string& s) {
        size_t n = 0;
        for (size_t p = html.find(s); p != std::string::npos; p = html.find(s, p + 1)) ++n;
        return n;
    };
    EXPECT_EQ(count("<svg"), 2u);  // the grid's false-colour and isolux plans
    EXPECT_EQ(count("<svg"), count("</svg>"));
    EXPECT_EQ(count("<table"), count("</table>"));
    EXPECT_NE(html.find("no luminaire from a photometric file"), std::string::npos);
}

}  // namespace
}  // namespace sr
