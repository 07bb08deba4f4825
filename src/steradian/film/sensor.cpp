#include "steradian/film/sensor.h"

#include <cmath>

#include "steradian/core/error.h"
#include "steradian/spectrum/camera_sensors.h"

namespace sr {

namespace {

/// sum over l = 360..830 nm of a(l) b(l) c(l).
double sum3(const Spectrum& a, const Spectrum& b, const Spectrum& c) {
    double s = 0;
    for (int l = int(kLambdaMin); l <= int(kLambdaMax); ++l)
        s += double(a(Float(l))) * double(b(Float(l))) * double(c(Float(l)));
    return s;
}

using Mat3d = std::array<std::array<double, 3>, 3>;

/// The inverse of m by its adjugate; nullopt-like failure as a false return when m is
/// singular relative to its scale.
bool invert(const Mat3d& m, Mat3d& inv) {
    const double c00 = m[1][1] * m[2][2] - m[1][2] * m[2][1];
    const double c01 = m[1][2] * m[2][0] - m[1][0] * m[2][2];
    const double c02 = m[1][0] * m[2][1] - m[1][1] * m[2][0];
    const double det = m[0][0] * c00 + m[0][1] * c01 + m[0][2] * c02;
    double scale = 0;
    for (const auto& row : m)
        for (double v : row) scale = std::max(scale, std::abs(v));
    if (!(std::abs(det) > 1e-12 * scale * scale * scale)) return false;
    const double k = 1 / det;
    inv = {{{c00 * k, (m[0][2] * m[2][1] - m[0][1] * m[2][2]) * k,
             (m[0][1] * m[1][2] - m[0][2] * m[1][1]) * k},
            {c01 * k, (m[0][0] * m[2][2] - m[0][2] * m[2][0]) * k,
             (m[0][2] * m[1][0] - m[0][0] * m[1][2]) * k},
            {c02 * k, (m[0][1] * m[2][0] - m[0][0] * m[2][1]) * k,
             (m[0][0] * m[1][1] - m[0][1] * m[1][0]) * k}}};
    return true;
}

}  // namespace

Matrix3 fit_xyz_from_sensor_rgb(const std::array<Spectrum, 3>& rgb, const Spectrum& sensor_illum,
                                const Spectrum& output_illum) {
    const Spectrum one = ConstantSpectrum{1};
    const std::array<Spectrum, 3> cmf = {cie_x(), cie_y(), cie_z()};
    const double g_white = sum3(rgb[1], sensor_illum, one);
    const double y_white_out = sum3(cmf[1], output_illum, one);
    const double y_white_sensor = sum3(cmf[1], sensor_illum, one);
    if (!(g_white > 0) || !(y_white_out > 0))
        throw Error("sensor fit: the sensor's green channel or the output white sees no light");
    // Normal equations of min |C M^T - T|^2 over the swatches (rows c_i, t_i):
    // (C^T C) M^T = C^T T.
    Mat3d ctc{}, ctt{};
    for (const PiecewiseLinearSpectrum& s : colorchecker_reflectances()) {
        double c[3], t[3];
        for (int k = 0; k < 3; ++k) {
            c[k] = sum3(rgb[size_t(k)], s, sensor_illum) / g_white;
            t[k] = sum3(cmf[size_t(k)], s, output_illum) / y_white_out * (y_white_sensor / g_white);
        }
        for (int i = 0; i < 3; ++i)
            for (int j = 0; j < 3; ++j) {
                ctc[size_t(i)][size_t(j)] += c[i] * c[j];
                ctt[size_t(i)][size_t(j)] += c[i] * t[j];
            }
    }
    Mat3d inv{};
    if (!invert(ctc, inv))
        throw Error("sensor fit: the swatches' sensor responses are linearly dependent");
    Matrix3 m{};  // M = (inv(C^T C) C^T T)^T
    for (int i = 0; i < 3; ++i)
        for (int j = 0; j < 3; ++j) {
            double s = 0;
            for (int k = 0; k < 3; ++k) s += inv[size_t(j)][size_t(k)] * ctt[size_t(k)][size_t(i)];
            m[size_t(i)][size_t(j)] = Float(s);
        }
    return m;
}

Matrix3 multiply(const Matrix3& a, const Matrix3& b) {
    Matrix3 r{};
    for (int i = 0; i < 3; ++i)
        for (int j = 0; j < 3; ++j) {
            double s = 0;
            for (int k = 0; k < 3; ++k)
                s += double(a[size_t(i)][size_t(k)]) * b[size_t(k)][size_t(j)];
            r[size_t(i)][size_t(j)] = Float(s);
        }
    return r;
}

}  // namespace sr
