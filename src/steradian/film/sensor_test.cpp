#include "steradian/film/sensor.h"

#include <gtest/gtest.h>

#include <cmath>
#include <functional>

#include "steradian/film/film.h"
#include "steradian/spectrum/camera_sensors.h"

namespace sr {
namespace {

/// The integral over wavelength of the piecewise-linear curve through (lambdas, values)
/// times f, by Simpson's rule on each 10 nm segment split into 100 steps: independent of the
/// film's 1 nm tables.
double curve_integral(const PiecewiseLinearSpectrum& c, const std::function<double(double)>& f) {
    const auto &l = *c.lambdas, &v = *c.values;
    double sum = 0;
    for (size_t i = 0; i + 1 < l.size(); ++i) {
        const double a = l[i], b = l[i + 1];
        const int n = 100;
        const double h = (b - a) / n;
        auto g = [&](double x) { return (v[i] + (v[i + 1] - v[i]) * (x - a) / (b - a)) * f(x); };
        double s = g(a) + g(b);
        for (int k = 1; k < n; ++k) s += (k % 2 ? 4 : 2) * g(a + k * h);
        sum += s * h / 3;
    }
    return sum;
}

TEST(CameraSensors, EveryNameOfPbrtV4HasThreeCurvesAndNamedSpectra) {
    // pbrt-v4's list (src/pbrt/util/spectrum.cpp, the camera tables).
    const char* const expected[] = {
        "canon_eos_100d", "canon_eos_1dx_mkii", "canon_eos_200d",     "canon_eos_200d_mkii",
        "canon_eos_5d",   "canon_eos_5d_mkii",  "canon_eos_5d_mkiii", "canon_eos_5d_mkiv",
        "canon_eos_5ds",  "canon_eos_m",        "hasselblad_l1d_20c", "nikon_d810",
        "nikon_d850",     "sony_ilce_6400",     "sony_ilce_7m3",      "sony_ilce_7rm3",
        "sony_ilce_9"};
    EXPECT_EQ(camera_sensor_names().size(), std::size(expected));
    for (const char* name : expected) {
        auto c = camera_sensor_curves(name);
        ASSERT_TRUE(c) << name;
        double peak = 0;
        for (const auto& s : *c) {
            EXPECT_EQ(s.lambdas->front(), 380);
            EXPECT_EQ(s.lambdas->back(), 720);
            for (Float v : *s.values) {
                EXPECT_GE(v, 0) << name;
                peak = std::max(peak, double(v));
            }
        }
        EXPECT_NEAR(peak, 1, 1e-6) << name;  // relative sensitivities, normalised to a peak of 1
        for (const char* ch : {"_r", "_g", "_b"})
            EXPECT_TRUE(named_spectrum(std::string(name) + ch)) << name << ch;
    }
    EXPECT_FALSE(camera_sensor_curves("cie1931"));
    EXPECT_FALSE(camera_sensor_curves("canon_eos"));
}

TEST(CameraSensors, ColorCheckerReflectancesAreReflectances) {
    for (const auto& s : colorchecker_reflectances()) {
        EXPECT_EQ(s.lambdas->size(), 36u);
        for (Float v : *s.values) {
            EXPECT_GT(v, 0);
            EXPECT_LT(v, 1);
        }
    }
}

// The film's sensor response to a radiance L is imaging ratio times the integral of each
// sensitivity times L. Estimated with stratified wavelengths (a midpoint rule in primary
// sample space over 4 x 8192 nodes), it converges to the integral computed here by Simpson's
// rule on the raw 10 nm table; the film's 1 nm table adds a ramp of 1 nm below 380 nm and
// above 720 nm where the curves are ~1e-3 (relative 1e-5).
TEST(CameraSensors, FilmResponseIsTheIntegralOfTheCurveTimesTheSpectrum) {
    for (const char* name : {"nikon_d850", "canon_eos_5d", "sony_ilce_7m3"}) {
        const auto curves = *camera_sensor_curves(name);
        FilmParams p;
        p.resolution = {1, 1};
        p.x1 = p.y1 = 1;
        p.imaging_ratio = 2.5f;
        p.sensor_rgb = std::array<Spectrum, 3>{curves[0], curves[1], curves[2]};
        Film film(p);
        // A smooth, far from flat radiance (Planck's law at 3000 K, scaled to order 1).
        auto L = [](double l) { return planck(l, 3000) / planck(966, 3000); };
        const int n = 8192;
        std::array<double, 3> est{0, 0, 0};
        for (int k = 0; k < n; ++k) {
            SampledWavelengths lambda = SampledWavelengths::sample_visible((k + 0.5f) / n);
            SampledSpectrum s;
            for (int i = 0; i < kSpectrumSamples; ++i) s[i] = Float(L(lambda.lambda[i]));
            auto v = film.to_sensor(s, lambda);
            for (int c = 0; c < 3; ++c) est[c] += v[c] / n;
        }
        for (int c = 0; c < 3; ++c) {
            const double exact = 2.5 * curve_integral(curves[c], L);
            EXPECT_NEAR(est[c] / exact, 1, 3e-4) << name << " channel " << c;
        }
    }
}

using Mat3d = std::array<std::array<double, 3>, 3>;

Mat3d inverse(const Mat3d& m) {
    const double det = m[0][0] * (m[1][1] * m[2][2] - m[1][2] * m[2][1]) -
                       m[0][1] * (m[1][0] * m[2][2] - m[1][2] * m[2][0]) +
                       m[0][2] * (m[1][0] * m[2][1] - m[1][1] * m[2][0]);
    Mat3d r{};
    for (int i = 0; i < 3; ++i)
        for (int j = 0; j < 3; ++j) {
            // cofactor of m[j][i]
            const int r0 = (j + 1) % 3, r1 = (j + 2) % 3, c0 = (i + 1) % 3, c1 = (i + 2) % 3;
            r[i][j] = (m[r0][c0] * m[r1][c1] - m[r0][c1] * m[r1][c0]) / det;
        }
    return r;
}

// A sensor whose sensitivities are a linear mix C of the CIE matching functions meets the
// Luther-Ives condition: its responses are C times XYZ for every spectrum. Lit by the output
// white itself, the fit's targets are then exactly C^-1 times its inputs, the least-squares
// residual is zero, and the fitted matrix is C^-1.
TEST(SensorFit, IsExactForASensorThatIsALinearMixOfTheCmfs) {
    const Mat3d C = {{{0.6, 0.35, 0.05}, {0.15, 0.8, 0.05}, {0.0, 0.1, 0.9}}};
    std::array<Spectrum, 3> rgb;
    for (int k = 0; k < 3; ++k) {
        auto v = std::make_shared<std::vector<Float>>();
        for (int l = int(kLambdaMin); l <= int(kLambdaMax); ++l)
            v->push_back(Float(C[k][0] * cie_x()(Float(l)) + C[k][1] * cie_y()(Float(l)) +
                               C[k][2] * cie_z()(Float(l))));
        rgb[size_t(k)] = DenselySampledSpectrum{v};
    }
    const Matrix3 m = fit_xyz_from_sensor_rgb(rgb, srgb_illuminant(), srgb_illuminant());
    const Mat3d expected = inverse(C);
    for (int i = 0; i < 3; ++i)
        for (int j = 0; j < 3; ++j) EXPECT_NEAR(m[i][j], expected[i][j], 2e-5) << i << j;
}

/// c_i and t_i of pbrt-v4's construction (fit_xyz_from_sensor_rgb's documentation), for
/// the swatches (and a perfect white reflector last).
struct FitData {
    std::vector<std::array<double, 3>> c, t;
};
FitData fit_data(const std::array<Spectrum, 3>& rgb, const Spectrum& e, const Spectrum& w) {
    auto sum = [](const Spectrum& a, const Spectrum& b, const Spectrum& s) {
        double r = 0;
        for (int l = 360; l <= 830; ++l) r += double(a(Float(l))) * b(Float(l)) * s(Float(l));
        return r;
    };
    const std::array<Spectrum, 3> cmf = {cie_x(), cie_y(), cie_z()};
    const Spectrum one = ConstantSpectrum{1};
    const double g = sum(rgb[1], e, one), yw = sum(cmf[1], w, one), ye = sum(cmf[1], e, one);
    FitData d;
    std::vector<Spectrum> refl(colorchecker_reflectances().begin(),
                               colorchecker_reflectances().end());
    refl.push_back(one);
    for (const Spectrum& s : refl) {
        std::array<double, 3> c{}, t{};
        for (int k = 0; k < 3; ++k) {
            c[k] = sum(rgb[k], s, e) / g;
            t[k] = sum(cmf[k], s, w) / yw * ye / g;
        }
        d.c.push_back(c);
        d.t.push_back(t);
    }
    return d;
}

// For the real cameras the fit is not exact: it is the least-squares solution, so its
// residuals over the 24 swatches are orthogonal to each sensor channel (the normal equations,
// sum_i c_i[k] (M c_i - t_i)[j] = 0). A perfect white reflector is not among the swatches,
// but the neutral ones are near-multiples of it: its relative error must not exceed the
// worst relative residual of the swatches.
TEST(SensorFit, IsTheLeastSquaresSolutionForEveryCamera) {
    for (const std::string& name : camera_sensor_names()) {
        const auto cv = *camera_sensor_curves(name);
        const std::array<Spectrum, 3> rgb = {cv[0], cv[1], cv[2]};
        const Spectrum e = cie_d_illuminant(6500);
        const Matrix3 m = fit_xyz_from_sensor_rgb(rgb, e, srgb_illuminant());
        const FitData d = fit_data(rgb, e, srgb_illuminant());
        auto apply = [&](const std::array<double, 3>& c) {
            std::array<double, 3> r{};
            for (int i = 0; i < 3; ++i) r[i] = m[i][0] * c[0] + m[i][1] * c[1] + m[i][2] * c[2];
            return r;
        };
        double normal[3][3] = {}, scale[3][3] = {}, worst = 0;
        for (int s = 0; s < kColorCheckerSwatches; ++s) {
            const auto fit = apply(d.c[s]);
            double err = 0, len = 0;
            for (int j = 0; j < 3; ++j) {
                err += (fit[j] - d.t[s][j]) * (fit[j] - d.t[s][j]);
                len += d.t[s][j] * d.t[s][j];
                for (int k = 0; k < 3; ++k) {
                    normal[k][j] += d.c[s][k] * (fit[j] - d.t[s][j]);
                    scale[k][j] += std::abs(d.c[s][k] * d.t[s][j]);
                }
            }
            worst = std::max(worst, std::sqrt(err / len));
        }
        for (int k = 0; k < 3; ++k)
            for (int j = 0; j < 3; ++j)
                EXPECT_LT(std::abs(normal[k][j]), 1e-5 * scale[k][j]) << name << k << j;
        const auto white = apply(d.c.back());
        double err = 0, len = 0;
        for (int j = 0; j < 3; ++j) {
            err += (white[j] - d.t.back()[j]) * (white[j] - d.t.back()[j]);
            len += d.t.back()[j] * d.t.back()[j];
        }
        EXPECT_LE(std::sqrt(err / len), worst) << name;
        EXPECT_GT(worst, 1e-4) << name;  // a real camera is not a Luther sensor
    }
}

}  // namespace
}  // namespace sr
