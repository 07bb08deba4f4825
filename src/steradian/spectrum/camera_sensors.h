#pragma once
/// Measured data of pbrt-v4's PixelSensor: the spectral sensitivities of the cameras its
/// Film "sensor" parameter names, and the 24 ColorChecker reflectances it fits a sensor's
/// XYZ-from-RGB matrix to (the fit itself is film/sensor.h). Sources are cited in the .cpp.
#include <array>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "steradian/spectrum/spectrum.h"

namespace sr {

/// The camera names pbrt-v4 accepts besides "cie1931" ("canon_eos_100d", ..., "sony_ilce_9").
std::vector<std::string> camera_sensor_names();
/// The relative spectral sensitivities r, g, b of a named camera (piecewise linear through
/// 10 nm samples over 380..720 nm, zero outside), or nullopt for an unknown name.
std::optional<std::array<PiecewiseLinearSpectrum, 3>> camera_sensor_curves(std::string_view name);

inline constexpr int kColorCheckerSwatches = 24;
/// The ColorChecker swatch reflectances (piecewise linear through 10 nm samples over
/// 380..730 nm, zero outside), in the chart's order (dark skin, light skin, ..., black).
const std::array<PiecewiseLinearSpectrum, kColorCheckerSwatches>& colorchecker_reflectances();

}  // namespace sr
