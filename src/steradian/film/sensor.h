#pragma once
/// pbrt-v4's PixelSensor for camera sensitivities: the matrix from a camera's raw r, g, b
/// to CIE XYZ, fitted by linear least squares over the 24 ColorChecker swatches
/// (spectrum/camera_sensors.h) as pbrt-v4 fits it.
#include <array>

#include "steradian/spectrum/spectrum.h"

namespace sr {

using Matrix3 = std::array<std::array<Float, 3>, 3>;

/// The XYZ-from-sensor-RGB matrix M of a sensor of sensitivities `rgb` (r, g, b), with the
/// scene lit by `sensor_illum` and the output colour space's white `output_illum`
/// (pbrt-v4's PixelSensor constructor). For each swatch reflectance s_i, with sums over
/// the integer wavelengths 360..830 nm:
///   c_i = (sum r s_i E, sum g s_i E, sum b s_i E) / sum g E            (E = sensor_illum)
///   t_i = (sum xbar s_i W, sum ybar s_i W, sum zbar s_i W) / sum ybar W
///         * (sum ybar E / sum g E)                                     (W = output_illum)
/// and M minimises sum_i |M c_i - t_i|^2. So a sensor that sees white under E reports, after
/// M, about the output white, with the luminance the CIE observer sees of E. Throws
/// sr::Error if the swatches' sensor responses are linearly dependent (no unique fit).
Matrix3 fit_xyz_from_sensor_rgb(const std::array<Spectrum, 3>& rgb, const Spectrum& sensor_illum,
                                const Spectrum& output_illum);

/// a * b.
Matrix3 multiply(const Matrix3& a, const Matrix3& b);

}  // namespace sr
