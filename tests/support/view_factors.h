#pragma once
/// Configuration (view) factors in closed form, for tests whose expected illuminance is
/// pi L times the factor of a uniformly bright rectangle.
#include <cmath>

namespace sr::test {

/// The configuration factor from a small upward-facing patch at the origin to the parallel
/// rectangle [0, a] x [0, b] at height h above it (a corner straight above the patch):
/// Howell's catalogue of configuration factors, B-2,
/// F = [X / sqrt(1 + X^2) atan(Y / sqrt(1 + X^2)) + Y / sqrt(1 + Y^2) atan(X / sqrt(1 + Y^2))]
/// / (2 pi), X = |a| / h, Y = |b| / h; extended as an odd function of a and b (negative when
/// exactly one of them is) so that rectangles add up by superposition.
inline double corner_factor(double a, double b, double h) {
    const double X = std::abs(a) / h, Y = std::abs(b) / h;
    const double sx = std::sqrt(1 + X * X), sy = std::sqrt(1 + Y * Y);
    const double f =
        (X / sx * std::atan(Y / sx) + Y / sy * std::atan(X / sy)) / (2 * 3.14159265358979323846);
    return (a < 0) != (b < 0) ? -f : f;
}

/// The factor of the rectangle [x1, x2] x [y1, y2] at height h seen from an upward patch at
/// (px, py, 0), by superposition of corner rectangles.
inline double rectangle_factor(double x1, double x2, double y1, double y2, double px, double py,
                               double h) {
    return corner_factor(x2 - px, y2 - py, h) - corner_factor(x1 - px, y2 - py, h) -
           corner_factor(x2 - px, y1 - py, h) + corner_factor(x1 - px, y1 - py, h);
}

}  // namespace sr::test
