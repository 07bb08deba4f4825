#include "steradian/lights/photometric/photometric.h"

#include <algorithm>
#include <cmath>
#include <numbers>

namespace sr {
namespace {

constexpr double kDeg = std::numbers::pi / 180.0;
constexpr double kAngleEps = 1e-9;

bool near(double a, double b) { return std::abs(a - b) <= 1e-6; }

/// Locates x in the increasing array a: a[i] <= x <= a[i+1] with x = lerp(t, a[i], a[i+1]).
/// A single-entry array matches only its own value. False when x lies outside.
bool locate(const std::vector<double>& a, double x, size_t& i, double& t) {
    if (a.empty() || !(x >= a.front() - kAngleEps) || !(x <= a.back() + kAngleEps)) return false;
    if (a.size() == 1) {
        i = 0;
        t = 0;
        return true;
    }
    // Most files tabulate equal steps: guess the interval from the range, and search only
    // if the guess is wrong (the same interval upper_bound gives).
    size_t hi;
    const double span = a.back() - a.front();
    const double g = span > 0 ? (x - a.front()) / span * double(a.size() - 1) : 0.0;
    const size_t guess = g > 0 ? std::min(static_cast<size_t>(g) + 1, a.size() - 1) : 1;
    if (a[guess - 1] <= x && (x < a[guess] || guess == a.size() - 1)) {
        hi = guess;
    } else {
        auto it = std::upper_bound(a.begin(), a.end(), x);
        hi = static_cast<size_t>(it - a.begin());
    }
    hi = std::clamp<size_t>(hi, 1, a.size() - 1);
    i = hi - 1;
    double w = a[hi] - a[i];
    t = w > 0 ? std::clamp((x - a[i]) / w, 0.0, 1.0) : 0.0;
    return true;
}

double wrap360(double a) {
    double c = std::fmod(a, 360.0);
    if (c < 0) c += 360.0;
    if (c >= 360.0) c = 0.0;
    return c;
}

/// Polar-angle weights of the exact integral of a linear function over [a, b] (radians)
/// times sin(x) (use_sin) or cos(x): integral = w0 f(a) + w1 f(b).
void polar_weights(double a, double b, bool use_sin, double& w0, double& w1) {
    double h = b - a;
    if (h < 1e-4) {
        // Linear weight function approximation (relative error O(h^2), h < 1e-4 rad).
        double ga = use_sin ? std::sin(a) : std::cos(a);
        double gb = use_sin ? std::sin(b) : std::cos(b);
        w0 = h * (2 * ga + gb) / 6;
        w1 = h * (ga + 2 * gb) / 6;
        return;
    }
    if (use_sin) {
        w0 = (h * std::cos(a) - std::sin(b) + std::sin(a)) / h;
        w1 = (std::sin(b) - std::sin(a) - h * std::cos(b)) / h;
    } else {
        w0 = (std::cos(a) - std::cos(b) - h * std::sin(a)) / h;
        w1 = (h * std::sin(b) + std::cos(b) - std::cos(a)) / h;
    }
}

void sort_unique(std::vector<double>& v) {
    std::sort(v.begin(), v.end());
    std::vector<double> out;
    for (double x : v) {
        if (out.empty() || x - out.back() > kAngleEps) out.push_back(x);
    }
    v = std::move(out);
}

/// Mirrors a range that starts at 0 (A/B symmetry): {x} U {-x}.
std::vector<double> mirrored(const std::vector<double>& a) {
    std::vector<double> out = a;
    if (!a.empty() && near(a.front(), 0.0)) {
        for (double x : a) out.push_back(-x);
    }
    sort_unique(out);
    return out;
}

}  // namespace

const char* to_string(PhotometricType t) {
    switch (t) {
        case PhotometricType::C:
            return "C";
        case PhotometricType::B:
            return "B";
        case PhotometricType::A:
            return "A";
    }
    return "?";
}

const char* to_string(LuminousShape s) {
    switch (s) {
        case LuminousShape::Point:
            return "point";
        case LuminousShape::Rectangular:
            return "rectangular";
        case LuminousShape::RectangularWithLuminousSides:
            return "rectangular with luminous sides";
        case LuminousShape::Circular:
            return "circular";
        case LuminousShape::Elliptical:
            return "elliptical";
        case LuminousShape::VerticalCylinder:
            return "vertical cylinder";
        case LuminousShape::VerticalEllipticalCylinder:
            return "vertical elliptical cylinder";
        case LuminousShape::Sphere:
            return "sphere";
        case LuminousShape::Ellipsoid:
            return "ellipsoidal spheroid";
        case LuminousShape::HorizontalCylinderAlong:
            return "horizontal cylinder along photometric horizontal";
        case LuminousShape::HorizontalEllipticalCylinderAlong:
            return "horizontal elliptical cylinder along photometric horizontal";
        case LuminousShape::HorizontalCylinderPerpendicular:
            return "horizontal cylinder perpendicular to photometric horizontal";
        case LuminousShape::HorizontalEllipticalCylinderPerpendicular:
            return "horizontal elliptical cylinder perpendicular to photometric horizontal";
        case LuminousShape::VerticalCircleFacingHorizontal:
            return "vertical circle facing photometric horizontal";
        case LuminousShape::VerticalEllipseFacingHorizontal:
            return "vertical ellipse facing photometric horizontal";
        case LuminousShape::VerticalCirclePerpendicular:
            return "vertical circle facing perpendicular to photometric horizontal";
        case LuminousShape::VerticalEllipsePerpendicular:
            return "vertical ellipse facing perpendicular to photometric horizontal";
        case LuminousShape::Unknown:
            return "unknown";
    }
    return "?";
}

LuminousShape classify_luminous_shape(double w, double l, double h) {
    auto same = [](double a, double b) {
        return std::abs(a - b) <= 1e-9 * std::max(std::abs(a), std::abs(b));
    };
    auto sgn = [](double x) { return x > 0 ? 1 : (x < 0 ? -1 : 0); };
    const int sw = sgn(w), sl = sgn(l), sh = sgn(h);
    using S = LuminousShape;
    if (sw == 0 && sl == 0 && sh == 0) return S::Point;
    if (sw > 0 && sl > 0)
        return sh == 0 ? S::Rectangular : (sh > 0 ? S::RectangularWithLuminousSides : S::Unknown);
    if (sw < 0 && sl < 0) {
        if (sh == 0) return same(w, l) ? S::Circular : S::Elliptical;
        if (sh > 0) return same(w, l) ? S::VerticalCylinder : S::VerticalEllipticalCylinder;
        return same(w, l) && same(l, h) ? S::Sphere : S::Ellipsoid;
    }
    if (sw < 0 && sl > 0 && sh < 0)
        return same(w, h) ? S::HorizontalCylinderAlong : S::HorizontalEllipticalCylinderAlong;
    if (sw > 0 && sl < 0 && sh < 0)
        return same(l, h) ? S::HorizontalCylinderPerpendicular
                          : S::HorizontalEllipticalCylinderPerpendicular;
    if (sw < 0 && sl == 0 && sh < 0)
        return same(w, h) ? S::VerticalCircleFacingHorizontal : S::VerticalEllipseFacingHorizontal;
    if (sw == 0 && sl < 0 && sh < 0)
        return same(l, h) ? S::VerticalCirclePerpendicular : S::VerticalEllipsePerpendicular;
    return S::Unknown;
}

double TiltData::factor(double angle_deg) const {
    if (angles.empty() || angles.size() != factors.size()) return 1.0;
    if (angle_deg <= angles.front()) return factors.front();
    if (angle_deg >= angles.back()) return factors.back();
    size_t i = 0;
    double t = 0;
    if (!locate(angles, angle_deg, i, t)) return 1.0;
    if (i + 1 >= factors.size()) return factors[i];
    return (1 - t) * factors[i] + t * factors[i + 1];
}

double PhotometricData::table_intensity(double h, double v) const {
    const auto& H = horizontal_angles;
    const auto& V = vertical_angles;
    if (H.empty() || V.empty() || candela.size() != H.size()) return 0.0;
    if (!std::isfinite(h) || !std::isfinite(v)) return 0.0;

    // Horizontal fold: the row pair (i0, i1) and weight t, per the file's symmetry.
    size_t i0 = 0, i1 = 0;
    double th = 0;
    if (type == PhotometricType::C) {
        double c = wrap360(h);
        const double first = H.front(), last = H.back();
        if (H.size() == 1) {
            c = first;
        } else if (near(first, 0) && near(last, 90)) {
            if (c > 180) c = 360 - c;
            if (c > 90) c = 180 - c;
        } else if (near(first, 0) && near(last, 180)) {
            if (c > 180) c = 360 - c;
        } else if (near(first, 90) && near(last, 270)) {
            if (c < 90)
                c = 180 - c;
            else if (c > 270)
                c = 540 - c;
        }
        if (near(first, 0) && last > 180 && c > last) {
            // No lateral symmetry with the last plane below 360: wrap to the 0 plane.
            i0 = H.size() - 1;
            i1 = 0;
            th = std::clamp((c - last) / (360.0 - last), 0.0, 1.0);
        } else {
            size_t i = 0;
            if (!locate(H, c, i, th)) return 0.0;
            i0 = i;
            i1 = std::min(i + 1, H.size() - 1);
        }
    } else {
        if (near(H.front(), 0)) h = std::abs(h);
        if (near(V.front(), 0)) v = std::abs(v);
        size_t i = 0;
        if (!locate(H, h, i, th)) return 0.0;
        i0 = i;
        i1 = std::min(i + 1, H.size() - 1);
    }

    size_t j = 0;
    double tv = 0;
    if (!locate(V, v, j, tv)) return 0.0;
    const size_t j1 = std::min(j + 1, V.size() - 1);
    const auto& r0 = candela[i0];
    const auto& r1 = candela[i1];
    if (r0.size() != V.size() || r1.size() != V.size()) return 0.0;
    double a = (1 - tv) * r0[j] + tv * r0[j1];
    double b = (1 - tv) * r1[j] + tv * r1[j1];
    return (1 - th) * a + th * b;
}

double PhotometricData::intensity(double gamma_deg, double c_deg) const {
    if (!std::isfinite(gamma_deg) || !std::isfinite(c_deg)) return 0.0;
    if (type == PhotometricType::C) {
        double g = wrap360(gamma_deg);
        double c = c_deg;
        if (g > 180) {
            g = 360 - g;
            c += 180;
        }
        return table_intensity(c, g);
    }
    const double g = gamma_deg * kDeg, c = c_deg * kDeg;
    return intensity_direction(std::sin(g) * std::cos(c), std::sin(g) * std::sin(c), -std::cos(g));
}

double PhotometricData::intensity_direction(double x, double y, double z) const {
    if (!std::isfinite(x) || !std::isfinite(y) || !std::isfinite(z)) return 0.0;
    if (x == 0 && y == 0 && z == 0) return 0.0;
    switch (type) {
        // (sqrt rather than hypot: the arguments are directions, far from overflow, and
        // hypot's care costs as much as an atan2.)
        case PhotometricType::C: {
            const double gamma = std::atan2(std::sqrt(x * x + y * y), -z) / kDeg;
            // A rotationally symmetric file (one C plane) needs no C angle.
            const double c = horizontal_angles.size() == 1 ? 0.0 : std::atan2(y, x) / kDeg;
            return table_intensity(c, gamma);
        }
        case PhotometricType::B: {
            double hh = std::atan2(-y, std::sqrt(x * x + z * z)) / kDeg;
            double vv = std::atan2(x, -z) / kDeg;
            return table_intensity(hh, vv);
        }
        case PhotometricType::A: {
            double vv = std::atan2(z, std::sqrt(x * x + y * y)) / kDeg;
            double hh = std::atan2(-y, x) / kDeg;
            return table_intensity(hh, vv);
        }
    }
    return 0.0;
}

double PhotometricData::total_flux() const {
    const auto& H = horizontal_angles;
    const auto& V = vertical_angles;
    if (H.empty() || V.empty()) return 0.0;

    // Polar ("latitude") angles with their weight (sin from nadir for C, cos from the
    // equator for A/B) and azimuthal breakpoints of the symmetry-expanded interpolant.
    std::vector<double> polar, azimuth;
    bool use_sin = true;
    bool polar_is_vertical = true;
    if (type == PhotometricType::C) {
        polar = V;
        const double first = H.front(), last = H.back();
        for (double h : H) {
            if (H.size() == 1) break;
            azimuth.push_back(h);
            if (near(first, 0) && near(last, 90)) {
                azimuth.push_back(180 - h);
                azimuth.push_back(180 + h);
                azimuth.push_back(360 - h);
            } else if (near(first, 0) && near(last, 180)) {
                azimuth.push_back(360 - h);
            } else if (near(first, 90) && near(last, 270)) {
                azimuth.push_back(wrap360(180 - h));
            }
        }
        azimuth.push_back(0);
        azimuth.push_back(360);
        for (double& a : azimuth) a = std::clamp(a, 0.0, 360.0);
        sort_unique(azimuth);
    } else if (type == PhotometricType::B) {
        use_sin = false;
        polar_is_vertical = false;
        polar = mirrored(H);
        azimuth = mirrored(V);
    } else {
        use_sin = false;
        polar = mirrored(V);
        azimuth = mirrored(H);
    }

    auto f = [&](double p, double a) {
        return polar_is_vertical ? table_intensity(a, p) : table_intensity(p, a);
    };
    // P(a) = integral over the polar angle at azimuth a; linear in a between breakpoints.
    auto polar_integral = [&](double a) {
        if (polar.size() < 2) return 0.0;
        double sum = 0;
        for (size_t i = 0; i + 1 < polar.size(); ++i) {
            double w0 = 0, w1 = 0;
            polar_weights(polar[i] * kDeg, polar[i + 1] * kDeg, use_sin, w0, w1);
            sum += w0 * f(polar[i], a) + w1 * f(polar[i + 1], a);
        }
        return sum;
    };
    double flux = 0;
    double p_prev = polar_integral(azimuth.front());
    for (size_t j = 0; j + 1 < azimuth.size(); ++j) {
        double p_next = polar_integral(azimuth[j + 1]);
        flux += 0.5 * (azimuth[j + 1] - azimuth[j]) * kDeg * (p_prev + p_next);
        p_prev = p_next;
    }
    return flux;
}

double PhotometricData::nominal_flux() const {
    if (lamp_lumens < 0) return -1.0;
    return lamp_lumens * num_lamps;
}

double PhotometricData::max_intensity() const {
    double m = 0;
    for (const auto& row : candela)
        for (double v : row) m = std::max(m, v);
    return m;
}

}  // namespace sr
