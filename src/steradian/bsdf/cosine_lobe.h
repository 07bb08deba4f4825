#pragma once
/// Power-cosine lobes, the building block of the Phong-family models (phong.h, lafortune.h):
/// the solid-angle density (n + 1) / (2 pi) cos^n(beta) over the hemisphere of directions
/// within 90 degrees of a unit axis, beta the angle to the axis. It integrates to 1 over that
/// hemisphere: 2 pi * (n + 1) / (2 pi) * int_0^1 c^n dc = 1.
#include <cmath>

#include "steradian/core/math.h"

namespace sr {

/// Direction with density (n + 1) / (2 pi) cos^n(beta) about +z (n >= 0), from u in
/// [0, 1)^2: cos(beta) has the CDF c^(n+1), so cos(beta) = (1 - u.x)^(1 / (n + 1)); the
/// azimuth is 2 pi u.y. sin^2 is formed with expm1 so narrow lobes (large n) keep their
/// relative accuracy.
inline Vec3 sample_cosine_power(Point2 u, Float n) {
    Float log_cos = std::log1p(-u.x) / (n + 1);
    Float cos_b = std::exp(log_cos);
    Float sin_b = std::sqrt(std::max(Float(0), -std::expm1(2 * log_cos)));
    Float phi = 2 * kPi * u.y;
    return {sin_b * std::cos(phi), sin_b * std::sin(phi), cos_b};
}

/// Solid-angle density of sample_cosine_power at cos(beta) (1/sr); 0 for cos(beta) <= 0.
inline Float cosine_power_pdf(Float cos_b, Float n) {
    return cos_b > 0 ? (n + 1) * kInv2Pi * std::pow(cos_b, n) : 0;
}

}  // namespace sr
