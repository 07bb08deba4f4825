#pragma once
/// Checks shared by the IES and EULUMDAT harnesses: an accepted photometric file must give a
/// distribution whose every number the renderer uses is finite.
#include "fuzz_target.h"
#include "steradian/lights/photometric/photometric.h"

namespace sr::fuzz {

inline void check_photometric(const PhotometricData& d) {
    fuzz_check(!d.vertical_angles.empty() && !d.horizontal_angles.empty(), "empty angle list");
    fuzz_check(d.candela.size() == d.horizontal_angles.size(), "candela rows");
    for (const auto& row : d.candela) {
        fuzz_check(row.size() == d.vertical_angles.size(), "candela columns");
        for (double c : row) check_finite(c, "candela value");
    }
    for (double a : d.vertical_angles) check_finite(a, "vertical angle");
    for (double a : d.horizontal_angles) check_finite(a, "horizontal angle");
    check_finite(d.width, "width");
    check_finite(d.length, "length");
    check_finite(d.height, "height");
    check_finite(d.max_intensity(), "max_intensity()");
    check_finite(d.total_flux(), "total_flux()");
    check_finite(d.nominal_flux(), "nominal_flux()");
    for (double gamma : {0.0, 37.0, 90.0, 135.0, 180.0})
        for (double c : {0.0, 45.0, 200.0, 359.0})
            check_finite(d.intensity(gamma, c), "intensity()");
    for (double t : {-90.0, 0.0, 45.0, 90.0}) check_finite(d.tilt.factor(t), "tilt factor");
}

}  // namespace sr::fuzz
