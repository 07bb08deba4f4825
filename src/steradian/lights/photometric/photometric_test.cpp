#include "steradian/lights/photometric/photometric.h"

#include <gtest/gtest.h>

#include <cmath>
#include <functional>
#include <numbers>

namespace sr {
namespace {

constexpr double kPi = std::numbers::pi;
constexpr double kDeg = kPi / 180.0;

std::vector<double> range(double first, double last, double step) {
    std::vector<double> out;
    const int n = static_cast<int>(std::lround((last - first) / step));
    for (int i = 0; i <= n; ++i) out.push_back(first + step * i);
    return out;
}

/// A table in the file's own angles: candela[h][v] = f(h, v).
PhotometricData make_table(PhotometricType type, std::vector<double> v, std::vector<double> h,
                           const std::function<double(double, double)>& f) {
    PhotometricData d;
    d.type = type;
    d.vertical_angles = std::move(v);
    d.horizontal_angles = std::move(h);
    for (double hh : d.horizontal_angles) {
        std::vector<double> row;
        for (double vv : d.vertical_angles) row.push_back(f(hh, vv));
        d.candela.push_back(row);
    }
    return d;
}

/// Direction of Type C angles in the luminaire frame (see photometric.h).
void dir_c(double gamma, double c, double& x, double& y, double& z) {
    x = std::sin(gamma * kDeg) * std::cos(c * kDeg);
    y = std::sin(gamma * kDeg) * std::sin(c * kDeg);
    z = -std::cos(gamma * kDeg);
}

// ---- flux oracles -------------------------------------------------------------------------

TEST(PhotometricFlux, IsotropicIsFourPiI) {
    const double I = 123.0;
    // Rotationally symmetric single plane, a quadrant table and a full table: all 4 pi I.
    auto iso = [&](double, double) { return I; };
    for (const auto& d :
         {make_table(PhotometricType::C, range(0, 180, 10), {0}, iso),
          make_table(PhotometricType::C, range(0, 180, 7.5), range(0, 90, 22.5), iso),
          make_table(PhotometricType::C, range(0, 180, 5), range(0, 180, 30), iso),
          make_table(PhotometricType::C, range(0, 180, 5), range(90, 270, 45), iso),
          make_table(PhotometricType::C, range(0, 180, 5), range(0, 360, 15), iso),
          make_table(PhotometricType::C, range(0, 180, 5), range(0, 345, 15), iso)}) {
        EXPECT_NEAR(d.total_flux(), 4 * kPi * I, 1e-4 * 4 * kPi * I);
    }
    // Lower and upper halves only: 2 pi I each.
    EXPECT_NEAR(make_table(PhotometricType::C, range(0, 90, 5), {0}, iso).total_flux(), 2 * kPi * I,
                1e-9 * I);
    EXPECT_NEAR(make_table(PhotometricType::C, range(90, 180, 5), {0}, iso).total_flux(),
                2 * kPi * I, 1e-9 * I);
}

TEST(PhotometricFlux, CosineLobeIsPiI0) {
    const double I0 = 1000.0;
    auto lobe = [&](double, double g) { return I0 * std::cos(g * kDeg); };
    // 1 deg grid: the interpolation error of cos is at most h^2/8 = 3.8e-5 relative.
    auto d = make_table(PhotometricType::C, range(0, 90, 1), {0}, lobe);
    EXPECT_NEAR(d.total_flux(), kPi * I0, 1e-4 * kPi * I0);
    // A coarse 10 deg grid: the chordal interpolant of the concave cos lies below it, by at
    // most h^2/8 relative.
    auto coarse = make_table(PhotometricType::C, range(0, 90, 10), range(0, 90, 30), lobe);
    const double h = 10 * kDeg;
    EXPECT_LT(coarse.total_flux(), kPi * I0);
    EXPECT_GT(coarse.total_flux(), kPi * I0 * (1 - h * h / 8));
}

TEST(PhotometricFlux, TypeBAndTypeAHemispheres) {
    const double I = 10.0;
    auto iso = [&](double, double) { return I; };
    // Type A/B data cover the front hemisphere only.
    EXPECT_NEAR(
        make_table(PhotometricType::B, range(-90, 90, 5), range(-90, 90, 5), iso).total_flux(),
        2 * kPi * I, 1e-9 * I);
    EXPECT_NEAR(make_table(PhotometricType::B, range(0, 90, 5), range(0, 90, 10), iso).total_flux(),
                2 * kPi * I, 1e-9 * I);
    EXPECT_NEAR(
        make_table(PhotometricType::A, range(-90, 90, 5), range(-90, 90, 5), iso).total_flux(),
        2 * kPi * I, 1e-9 * I);
    EXPECT_NEAR(
        make_table(PhotometricType::A, range(-90, 90, 5), range(0, 90, 5), iso).total_flux(),
        2 * kPi * I, 1e-9 * I);

    // Cosine lobes about the front axis: pi I0.
    const double I0 = 500.0;
    // Type B: nadir is (H, V) = (0, 0); cos of the angle to nadir = cos H cos V.
    auto lobe_b = make_table(
        PhotometricType::B, range(-90, 90, 1), range(-90, 90, 1),
        [&](double hh, double vv) { return I0 * std::cos(hh * kDeg) * std::cos(vv * kDeg); });
    EXPECT_NEAR(lobe_b.total_flux(), kPi * I0, 1e-4 * kPi * I0);
    // Type A: photometric horizontal +x is (0, 0); cos of the angle to +x = cos V cos H.
    auto lobe_a = make_table(
        PhotometricType::A, range(0, 90, 1), range(0, 90, 1),
        [&](double hh, double vv) { return I0 * std::cos(hh * kDeg) * std::cos(vv * kDeg); });
    EXPECT_NEAR(lobe_a.total_flux(), kPi * I0, 1e-4 * kPi * I0);
}

TEST(PhotometricFlux, SymmetricTableEqualsItsExpansion) {
    // A quadrant-symmetric distribution written as a 0-90 table and as a full 0-360 table.
    auto f = [](double c, double g) {
        return (100 + 40 * std::cos(2 * c * kDeg)) * std::cos(g * kDeg / 2);
    };
    auto quad = make_table(PhotometricType::C, range(0, 180, 5), range(0, 90, 15), f);
    auto full = make_table(PhotometricType::C, range(0, 180, 5), range(0, 360, 15), f);
    auto half = make_table(PhotometricType::C, range(0, 180, 5), range(0, 180, 15), f);
    EXPECT_NEAR(quad.total_flux(), full.total_flux(), 1e-9 * full.total_flux());
    EXPECT_NEAR(half.total_flux(), full.total_flux(), 1e-9 * full.total_flux());
    // A distribution symmetric about the 90-270 plane, as 90-270 and as a full table.
    auto g = [](double c, double gm) { return (100 + 40 * std::sin(c * kDeg)) + gm; };
    auto side = make_table(PhotometricType::C, range(0, 180, 5), range(90, 270, 15), g);
    auto side_full = make_table(PhotometricType::C, range(0, 180, 5), range(0, 360, 15), g);
    EXPECT_NEAR(side.total_flux(), side_full.total_flux(), 1e-9 * side_full.total_flux());
}

TEST(PhotometricFlux, FluxOfTheInterpolantIsExact) {
    // A table linear in gamma between two samples: flux = 2 pi (w0 I0 + w1 I1) with the
    // closed-form weights; check against a fine midpoint rule of intensity() itself.
    auto d = make_table(PhotometricType::C, {0, 60, 180}, {0, 90, 180, 270, 360},
                        [](double c, double g) { return 50 + g + (c == 90 ? 30 : 0); });
    double sum = 0;
    const int n = 720;
    for (int i = 0; i < n; ++i) {
        for (int j = 0; j < n; ++j) {
            double u = -1 + 2 * (i + 0.5) / n;  // cos gamma' where gamma' from zenith
            double c = 360.0 * (j + 0.5) / n;
            double gamma = std::acos(-u) / kDeg;
            sum += d.intensity(gamma, c);
        }
    }
    sum *= (2.0 / n) * (2 * kPi / n);
    EXPECT_NEAR(d.total_flux(), sum, 1e-5 * sum);
}

// ---- interpolation and symmetry -----------------------------------------------------------

TEST(PhotometricIntensity, GridPointsAndBilinearMidpoints) {
    // Periodic in C (the 360 plane repeats the 0 plane, as it must).
    auto d = make_table(PhotometricType::C, {0, 30, 90, 180}, {0, 45, 90, 180, 360},
                        [](double c, double g) { return 1 + 10 * std::min(c, 360 - c) + g * g; });
    for (size_t i = 0; i < d.horizontal_angles.size(); ++i) {
        for (size_t j = 0; j < d.vertical_angles.size(); ++j) {
            EXPECT_DOUBLE_EQ(d.intensity(d.vertical_angles[j], d.horizontal_angles[i]),
                             d.candela[i][j]);
        }
    }
    // Midpoints in gamma, in C, and cell centres.
    EXPECT_DOUBLE_EQ(d.intensity(15, 45), 0.5 * (d.candela[1][0] + d.candela[1][1]));
    EXPECT_DOUBLE_EQ(d.intensity(30, 67.5), 0.5 * (d.candela[1][1] + d.candela[2][1]));
    EXPECT_DOUBLE_EQ(d.intensity(60, 135), 0.25 * (d.candela[2][1] + d.candela[2][2] +
                                                   d.candela[3][1] + d.candela[3][2]));
    // Bilinear at a quarter point.
    double a = 0.75 * d.candela[0][2] + 0.25 * d.candela[0][3];
    double b = 0.75 * d.candela[1][2] + 0.25 * d.candela[1][3];
    EXPECT_NEAR(d.intensity(112.5, 11.25), 0.75 * a + 0.25 * b, 1e-9);
}

TEST(PhotometricIntensity, RotationalSymmetry) {
    auto d = make_table(PhotometricType::C, range(0, 180, 10), {0},
                        [](double, double g) { return 10 + g; });
    for (double c : {0.0, 17.0, 90.0, 200.0, 359.0, -45.0, 725.0}) {
        EXPECT_DOUBLE_EQ(d.intensity(25, c), 35);
    }
}

TEST(PhotometricIntensity, QuadrantSymmetry) {
    auto d = make_table(PhotometricType::C, range(0, 180, 10), range(0, 90, 30),
                        [](double c, double g) { return 10 + g + 3 * c; });
    for (double g : {0.0, 35.0, 90.0, 155.0}) {
        for (double c : {0.0, 10.0, 30.0, 47.0, 90.0}) {
            const double i = d.intensity(g, c);
            EXPECT_NEAR(d.intensity(g, -c), i, 1e-9);
            EXPECT_NEAR(d.intensity(g, 180 - c), i, 1e-9);
            EXPECT_NEAR(d.intensity(g, 180 + c), i, 1e-9);
            EXPECT_NEAR(d.intensity(g, 360 - c), i, 1e-9);
        }
    }
    EXPECT_DOUBLE_EQ(d.intensity(20, 150), d.candela[1][2]);  // mirrors C = 30
}

TEST(PhotometricIntensity, BilateralSymmetryAboutC0C180) {
    auto d = make_table(PhotometricType::C, range(0, 180, 10), range(0, 180, 30),
                        [](double c, double g) { return 10 + g + 3 * c; });
    for (double c : {0.0, 15.0, 60.0, 100.0, 180.0}) {
        EXPECT_NEAR(d.intensity(40, -c), d.intensity(40, c), 1e-9);
        EXPECT_NEAR(d.intensity(40, 360 - c), d.intensity(40, c), 1e-9);
    }
    // Not symmetric about the 90-270 plane.
    EXPECT_NE(d.intensity(40, 30), d.intensity(40, 150));
    EXPECT_DOUBLE_EQ(d.intensity(40, 300), d.candela[2][4]);  // mirrors C = 60
}

TEST(PhotometricIntensity, BilateralSymmetryAboutC90C270) {
    auto d = make_table(PhotometricType::C, range(0, 180, 10), range(90, 270, 30),
                        [](double c, double g) { return 10 + g + 3 * c; });
    for (double c : {0.0, 20.0, 60.0, 90.0, 100.0, 300.0}) {
        EXPECT_NEAR(d.intensity(70, 180 - c), d.intensity(70, c), 1e-9);
    }
    EXPECT_DOUBLE_EQ(d.intensity(70, 0), d.candela[3][7]);    // C0 mirrors C180
    EXPECT_DOUBLE_EQ(d.intensity(70, 300), d.candela[5][7]);  // C300 mirrors C240
    EXPECT_NE(d.intensity(70, 30), d.intensity(70, -30));
}

TEST(PhotometricIntensity, FullAndWrappedFull) {
    auto f = [](double c, double g) { return 10 + g + 3 * c; };
    auto full = make_table(PhotometricType::C, range(0, 180, 10), range(0, 360, 30), f);
    EXPECT_NE(full.intensity(30, 30), full.intensity(30, -30));
    EXPECT_DOUBLE_EQ(full.intensity(30, -30), full.candela[11][3]);
    // Last plane 330 < 360: between 330 and 360 the data wrap to the 0 plane.
    auto wrapped = make_table(PhotometricType::C, range(0, 180, 10), range(0, 330, 30), f);
    EXPECT_DOUBLE_EQ(wrapped.intensity(30, 345),
                     0.5 * (wrapped.candela[11][3] + wrapped.candela[0][3]));
    EXPECT_DOUBLE_EQ(wrapped.intensity(30, 360), wrapped.candela[0][3]);
}

TEST(PhotometricIntensity, VerticalRanges) {
    auto f = [](double, double g) { return 1 + g; };
    auto down = make_table(PhotometricType::C, range(0, 90, 10), {0}, f);
    EXPECT_DOUBLE_EQ(down.intensity(90, 0), 91);
    EXPECT_EQ(down.intensity(90.5, 0), 0);
    EXPECT_EQ(down.intensity(180, 0), 0);
    auto up = make_table(PhotometricType::C, range(90, 180, 10), {0}, f);
    EXPECT_EQ(up.intensity(45, 0), 0);
    EXPECT_DOUBLE_EQ(up.intensity(135, 0), 136);
    EXPECT_DOUBLE_EQ(up.intensity(180, 0), 181);
    // Angles outside [0, 180] are the same directions.
    auto both = make_table(PhotometricType::C, range(0, 180, 10), range(0, 360, 90),
                           [](double c, double g) { return 1 + g + c; });
    EXPECT_NEAR(both.intensity(-30, 0), both.intensity(30, 180), 1e-9);
    EXPECT_NEAR(both.intensity(200, 90), both.intensity(160, 270), 1e-9);
}

TEST(PhotometricIntensity, DirectionMatchesAngles) {
    auto d = make_table(PhotometricType::C, range(0, 180, 10), range(0, 360, 30),
                        [](double c, double g) { return 1 + g + 0.5 * c; });
    for (double g : {5.0, 45.0, 90.0, 133.0, 175.0}) {
        for (double c : {0.0, 29.0, 100.0, 250.0, 359.0}) {
            double x, y, z;
            dir_c(g, c, x, y, z);
            EXPECT_NEAR(d.intensity_direction(3 * x, 3 * y, 3 * z), d.intensity(g, c), 1e-9);
        }
    }
    EXPECT_EQ(d.intensity_direction(0, 0, 0), 0);
    EXPECT_EQ(d.intensity(std::nan(""), 0), 0);
}

TEST(PhotometricIntensity, TypeBMapping) {
    // f records (H, V) so that every lookup says where it landed; at the poles of the
    // polar axis (H = +-90) it does not depend on V, as a function on the sphere must not.
    auto at = [](double h, double v) { return 1000 + 10 * h + v * std::cos(h * kDeg); };
    auto d = make_table(PhotometricType::B, range(-90, 90, 15), range(-90, 90, 15), at);
    EXPECT_NEAR(d.intensity(0, 0), at(0, 0), 1e-9);       // nadir = photometric zero
    EXPECT_NEAR(d.intensity(90, 0), at(0, 90), 1e-9);     // +x = photometric horizontal
    EXPECT_NEAR(d.intensity(90, 270), at(90, 0), 1e-9);   // -y: H = +90 (clockwise)
    EXPECT_NEAR(d.intensity(90, 90), at(-90, 0), 1e-9);   // +y: H = -90
    EXPECT_NEAR(d.intensity(45, 180), at(0, -45), 1e-9);  // towards -x: V = -45
    EXPECT_EQ(d.intensity(180, 0), 0);                    // zenith: behind the floodlight
    // A general grid point: d(H, V) = (cos H sin V, -sin H, -cos H cos V).
    const double h = 30 * kDeg, v = 45 * kDeg;
    EXPECT_NEAR(
        d.intensity_direction(std::cos(h) * std::sin(v), -std::sin(h), -std::cos(h) * std::cos(v)),
        at(30, 45), 1e-9);
    // Symmetric ranges starting at 0 mirror H and V.
    auto s = make_table(PhotometricType::B, range(0, 90, 15), range(0, 90, 15), at);
    EXPECT_NEAR(
        s.intensity_direction(std::cos(h) * std::sin(-v), std::sin(h), -std::cos(h) * std::cos(v)),
        at(30, 45), 1e-9);
}

TEST(PhotometricIntensity, TypeAMapping) {
    // Independent of H at the poles V = +-90 of the vertical polar axis.
    auto at = [](double h, double v) { return 1000 + 10 * h * std::cos(v * kDeg) + v; };
    auto d = make_table(PhotometricType::A, range(-90, 90, 15), range(-90, 90, 15), at);
    EXPECT_NEAR(d.intensity(90, 0), at(0, 0), 1e-9);     // +x = photometric horizontal
    EXPECT_NEAR(d.intensity(0, 0), at(0, -90), 1e-9);    // nadir = V -90
    EXPECT_NEAR(d.intensity(180, 0), at(0, 90), 1e-9);   // zenith = V +90
    EXPECT_NEAR(d.intensity(90, 270), at(90, 0), 1e-9);  // -y: H = +90 (clockwise)
    EXPECT_NEAR(d.intensity(90, 90), at(-90, 0), 1e-9);  // +y: H = -90
    EXPECT_NEAR(d.intensity(60, 30), at(-30, -30), 1e-9);
    EXPECT_EQ(d.intensity(90, 180), 0);  // -x: behind
}

TEST(PhotometricIntensity, MalformedTablesDoNotCrash) {
    PhotometricData d;
    EXPECT_EQ(d.intensity(10, 10), 0);
    EXPECT_EQ(d.total_flux(), 0);
    d.vertical_angles = {0, 90};
    d.horizontal_angles = {0};
    d.candela = {{1.0}};  // row too short
    EXPECT_EQ(d.intensity(10, 10), 0);
    d.candela = {};
    EXPECT_EQ(d.intensity(10, 10), 0);
}

// ---- small pieces -------------------------------------------------------------------------

TEST(Photometric, NominalFlux) {
    PhotometricData d;
    d.lamp_lumens = 1500;
    d.num_lamps = 2;
    EXPECT_EQ(d.nominal_flux(), 3000);
    d.lamp_lumens = -1;
    EXPECT_EQ(d.nominal_flux(), -1);
}

TEST(Photometric, TiltFactor) {
    TiltData t;
    EXPECT_EQ(t.factor(30), 1);
    t.angles = {0, 30, 90};
    t.factors = {1.0, 0.9, 0.6};
    EXPECT_DOUBLE_EQ(t.factor(0), 1.0);
    EXPECT_DOUBLE_EQ(t.factor(15), 0.95);
    EXPECT_DOUBLE_EQ(t.factor(60), 0.75);
    EXPECT_DOUBLE_EQ(t.factor(-5), 1.0);
    EXPECT_DOUBLE_EQ(t.factor(120), 0.6);
}

TEST(Photometric, LuminousShapes) {
    using S = LuminousShape;
    EXPECT_EQ(classify_luminous_shape(0, 0, 0), S::Point);
    EXPECT_EQ(classify_luminous_shape(1, 2, 0), S::Rectangular);
    EXPECT_EQ(classify_luminous_shape(1, 2, 3), S::RectangularWithLuminousSides);
    EXPECT_EQ(classify_luminous_shape(-1, -1, 0), S::Circular);
    EXPECT_EQ(classify_luminous_shape(-1, -2, 0), S::Elliptical);
    EXPECT_EQ(classify_luminous_shape(-1, -1, 2), S::VerticalCylinder);
    EXPECT_EQ(classify_luminous_shape(-1, -2, 2), S::VerticalEllipticalCylinder);
    EXPECT_EQ(classify_luminous_shape(-1, -1, -1), S::Sphere);
    EXPECT_EQ(classify_luminous_shape(-1, -2, -1), S::Ellipsoid);
    EXPECT_EQ(classify_luminous_shape(-1, 2, -1), S::HorizontalCylinderAlong);
    EXPECT_EQ(classify_luminous_shape(-1, 2, -3), S::HorizontalEllipticalCylinderAlong);
    EXPECT_EQ(classify_luminous_shape(2, -1, -1), S::HorizontalCylinderPerpendicular);
    EXPECT_EQ(classify_luminous_shape(2, -1, -3), S::HorizontalEllipticalCylinderPerpendicular);
    EXPECT_EQ(classify_luminous_shape(-1, 0, -1), S::VerticalCircleFacingHorizontal);
    EXPECT_EQ(classify_luminous_shape(-1, 0, -2), S::VerticalEllipseFacingHorizontal);
    EXPECT_EQ(classify_luminous_shape(0, -1, -1), S::VerticalCirclePerpendicular);
    EXPECT_EQ(classify_luminous_shape(0, -1, -2), S::VerticalEllipsePerpendicular);
    EXPECT_EQ(classify_luminous_shape(1, 0, 0), S::Unknown);
    EXPECT_STREQ(to_string(S::Sphere), "sphere");
    EXPECT_STREQ(to_string(PhotometricType::B), "B");
}

}  // namespace
}  // namespace sr
