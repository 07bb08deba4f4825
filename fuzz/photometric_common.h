#pragma once
/// Checks shared by the IES and EULUMDAT harnesses: an accepted photometric file must give a
/// distribution whose every number the renderer uses is finite, and whose intensities and
/// flux fit the renderer's 32-bit floats.
#include <limits>

#include "fuzz_target.h"
#include "steradian/lights/photometric/photometric.h"

namespace sr::fuzz {

inline void check_float_range(double x, const char* what) {
    fuzz_check(std::abs(x) <= double(std::numeric_limits<float>::max()), what);
}

inline void check_photometric(const PhotometricData& d) {
    fuzz_check(!d.vertical_angles.empty() && !d.horizontal_angles.empty(), "empty angle list");
    fuzz_check(d.candela.size() == d.horizontal_angles.size(), "candela rows");
    for (const auto& row : d.candela) {
        fuzz_check(row.size() == d.vertical_angles.size(), "candela columns");
        for (double c : row) check_float_range(c, "candela value beyond float range");
    }
    for (double a : d.vertical_angles) check_finite(a, "vertical angle");
    for (double a : d.horizontal_angles) check_finite(a, "horizontal angle");
    check_finite(d.width, "width");
    check_finite(d.length, "length");
    check_finite(d.height, "height");
    check_float_range(d.max_intensity(), "max_intensity() beyond float range");
    check_float_range(d.total_flux(), "total_flux() beyond float range");
    check_finite(d.nominal_flux(), "nominal_flux()");
    for (double gamma : {0.0, 37.0, 90.0, 135.0, 180.0})
        for (double c : {0.0, 45.0, 200.0, 359.0})
            check_finite(d.intensity(gamma, c), "intensity()");
    for (double t : {-90.0, 0.0, 45.0, 90.0}) check_finite(d.tilt.factor(t), "tilt factor");
}

}  // namespace sr::fuzz
