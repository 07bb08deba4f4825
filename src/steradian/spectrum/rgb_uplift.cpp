/// RGB -> spectrum uplift for the sRGB colour space (Jakob & Hanika 2019, "A Low-Dimensional
/// Function Space for Efficient Spectral Upsampling", Computer Graphics Forum 38(2)).
///
/// pbrt-v4 precomputes a coefficient table; here each colour is solved when first asked
/// for: Gauss-Newton on the CIELAB (CIE 1976) difference between the target and the
/// colour of the sigmoid-polynomial reflectance under D65, with continuation from the
/// c = 0 spectrum (0.5 grey) towards the target, as the paper's optimiser walks its grid.
/// The fit is done in the normalised wavelength t = (l - 360) / 470 for conditioning and
/// converted to coefficients in nm at the end. Results are cached (thread-safe).
#include <array>
#include <bit>
#include <cmath>
#include <cstdint>
#include <map>
#include <mutex>

#include "steradian/core/error.h"
#include "steradian/spectrum/cie_data.h"
#include "steradian/spectrum/sigmoid.h"
#include "steradian/spectrum/spectrum.h"

namespace sr {

namespace {

constexpr int kN = cie::kCmfCount;  // integration at every nm of 360..830, as spectrum_to_xyz
constexpr double kLambda0 = kLambdaMin;
constexpr double kLambdaRange = kLambdaMax - kLambdaMin;

using Vec3 = std::array<double, 3>;
using Mat3 = std::array<Vec3, 3>;  // row-major

/// Per-wavelength weights cmf * D65 / sum(ybar * D65): the XYZ of a reflectance s under
/// D65 is sum_i s(l_i) w_i, with Y = 1 for s = 1.
struct UpliftTables {
    std::array<double, kN> t{}, wx{}, wy{}, wz{};
    Vec3 white{};  ///< XYZ of the perfect white reflector under D65
};

const UpliftTables& uplift_tables() {
    static const UpliftTables tables = [] {
        UpliftTables u;
        const DenselySampledSpectrum& d65 = srgb_illuminant();
        double yw = 0;
        for (int i = 0; i < kN; ++i) yw += cie::kY[i] * double((*d65.values)[i]);
        for (int i = 0; i < kN; ++i) {
            double e = double((*d65.values)[i]) / yw;
            u.t[i] = i / kLambdaRange;
            u.wx[i] = cie::kX[i] * e;
            u.wy[i] = cie::kY[i] * e;
            u.wz[i] = cie::kZ[i] * e;
            u.white[0] += u.wx[i];
            u.white[1] += u.wy[i];
            u.white[2] += u.wz[i];
        }
        return u;
    }();
    return tables;
}

/// CIE 1976 L*a*b* of xyz relative to the white point, and (optionally) its Jacobian.
Vec3 xyz_to_lab(const Vec3& xyz, const Vec3& white, Mat3* jac = nullptr) {
    constexpr double delta = 6.0 / 29.0;
    double f[3], df[3];
    for (int i = 0; i < 3; ++i) {
        double r = xyz[i] / white[i];
        if (r > delta * delta * delta) {
            f[i] = std::cbrt(r);
            df[i] = 1 / (3 * f[i] * f[i] * white[i]);
        } else {
            f[i] = r / (3 * delta * delta) + 4.0 / 29.0;
            df[i] = 1 / (3 * delta * delta * white[i]);
        }
    }
    if (jac) {
        *jac = Mat3{Vec3{0, 116 * df[1], 0}, Vec3{500 * df[0], -500 * df[1], 0},
                    Vec3{0, 200 * df[1], -200 * df[2]}};
    }
    return {116 * f[1] - 16, 500 * (f[0] - f[1]), 200 * (f[1] - f[2])};
}

/// XYZ under D65 of the sigmoid polynomial with normalised coefficients c, and dXYZ/dc.
Vec3 eval_xyz(const Vec3& c, Mat3* jac) {
    const UpliftTables& u = uplift_tables();
    Vec3 xyz{0, 0, 0};
    Mat3 j{};
    for (int i = 0; i < kN; ++i) {
        double t = u.t[i];
        double x = (c[0] * t + c[1]) * t + c[2];
        double q = 1 + x * x;
        double sq = std::sqrt(q);
        double s = 0.5 + x / (2 * sq);
        double ds = 0.5 / (q * sq);  // dS/dx
        xyz[0] += u.wx[i] * s;
        xyz[1] += u.wy[i] * s;
        xyz[2] += u.wz[i] * s;
        if (jac) {
            double g[3] = {ds * t * t, ds * t, ds};
            for (int k = 0; k < 3; ++k) {
                j[0][k] += u.wx[i] * g[k];
                j[1][k] += u.wy[i] * g[k];
                j[2][k] += u.wz[i] * g[k];
            }
        }
    }
    if (jac) *jac = j;
    return xyz;
}

/// Residual (Lab of the spectrum minus the target Lab) and its Jacobian w.r.t. c.
Vec3 residual(const Vec3& c, const Vec3& target_lab, Mat3* jac) {
    const UpliftTables& u = uplift_tables();
    Mat3 jxyz, jlab;
    Vec3 lab = xyz_to_lab(eval_xyz(c, jac ? &jxyz : nullptr), u.white, jac ? &jlab : nullptr);
    if (jac) {
        for (int r = 0; r < 3; ++r)
            for (int k = 0; k < 3; ++k)
                (*jac)[r][k] = jlab[r][0] * jxyz[0][k] + jlab[r][1] * jxyz[1][k] +
                               jlab[r][2] * jxyz[2][k];
    }
    return {lab[0] - target_lab[0], lab[1] - target_lab[1], lab[2] - target_lab[2]};
}

double norm(const Vec3& v) { return std::sqrt(v[0] * v[0] + v[1] * v[1] + v[2] * v[2]); }

/// Solves a x = b by Gaussian elimination with partial pivoting; false if singular.
bool solve3(Mat3 a, Vec3 b, Vec3& x) {
    for (int col = 0; col < 3; ++col) {
        int p = col;
        for (int r = col + 1; r < 3; ++r)
            if (std::abs(a[r][col]) > std::abs(a[p][col])) p = r;
        if (!(std::abs(a[p][col]) > 1e-300)) return false;
        std::swap(a[p], a[col]);
        std::swap(b[p], b[col]);
        for (int r = col + 1; r < 3; ++r) {
            double f = a[r][col] / a[col][col];
            for (int k = col; k < 3; ++k) a[r][k] -= f * a[col][k];
            b[r] -= f * b[col];
        }
    }
    for (int r = 2; r >= 0; --r) {
        double s = b[r];
        for (int k = r + 1; k < 3; ++k) s -= a[r][k] * x[k];
        x[r] = s / a[r][r];
    }
    return std::isfinite(x[0]) && std::isfinite(x[1]) && std::isfinite(x[2]);
}

/// Gauss-Newton with backtracking from c towards target_lab. Updates c to the best point
/// found and returns its residual norm (CIELAB Delta E 1976).
double gauss_newton(Vec3& c, const Vec3& target_lab, double tolerance, int max_iterations) {
    Mat3 jac;
    Vec3 r = residual(c, target_lab, &jac);
    double err = norm(r);
    for (int it = 0; it < max_iterations && err > tolerance; ++it) {
        Vec3 step;
        if (!solve3(jac, r, step)) break;
        // Backtracking: accept the first step length that reduces the residual.
        bool improved = false;
        for (double alpha = 1; alpha > 1.0 / 1024; alpha *= 0.5) {
            Vec3 cn{c[0] - alpha * step[0], c[1] - alpha * step[1], c[2] - alpha * step[2]};
            Mat3 jn;
            Vec3 rn = residual(cn, target_lab, &jn);
            double en = norm(rn);
            if (std::isfinite(en) && en < err) {
                c = cn;
                r = rn;
                jac = jn;
                err = en;
                improved = true;
                break;
            }
        }
        if (!improved) break;
    }
    return err;
}

Vec3 lerp3(double t, const Vec3& a, const Vec3& b) {
    return {a[0] + t * (b[0] - a[0]), a[1] + t * (b[1] - a[1]), a[2] + t * (b[2] - a[2])};
}

/// Normalised-wavelength coefficients for rgb in [0,1]^3 with r, g, b not all equal.
Vec3 fit_normalized(Rgb rgb) {
    const UpliftTables& u = uplift_tables();
    Xyz txyz = linear_srgb_to_xyz(rgb);
    Vec3 target_xyz{txyz.x, txyz.y, txyz.z};
    // Start: c = 0 is the constant 0.5 reflectance; walk its XYZ towards the target's.
    Vec3 c{0, 0, 0};
    Vec3 start_xyz = eval_xyz(c, nullptr);
    Vec3 target_lab = xyz_to_lab(target_xyz, u.white);
    double t = 0, dt = 0.25;
    constexpr double kStepTolerance = 1e-3;  // Delta E, intermediate targets
    while (t < 1 && dt > 1.0 / 4096) {
        double tn = std::min(1.0, t + dt);
        Vec3 ct = c;
        Vec3 lab = xyz_to_lab(lerp3(tn, start_xyz, target_xyz), u.white);
        if (gauss_newton(ct, lab, kStepTolerance, 12) <= kStepTolerance) {
            c = ct;
            t = tn;
            dt = std::min(1.0, 2 * dt);
        } else {
            dt *= 0.5;
        }
    }
    // Polish on the final target (also the best effort when continuation stalled, e.g. for
    // colours at the edge of what the function space can reach).
    gauss_newton(c, target_lab, 1e-7, 60);
    return c;
}

struct Coefficients {
    Float c0 = 0, c1 = 0, c2 = 0;
};

/// Coefficients in nm for rgb in [0,1]^3.
Coefficients solve_coefficients(Rgb rgb) {
    if (rgb.r == rgb.g && rgb.g == rgb.b) {
        // Constant spectrum: S(c2) = value, exactly (+-infinity at 1 and 0).
        return {0, 0, Float(inverse_sigmoid(rgb.r))};
    }
    Vec3 c = fit_normalized(rgb);
    // x(l) = c0 t^2 + c1 t + c2 with t = (l - a) / w, expanded in powers of l.
    double a = kLambda0, w = kLambdaRange;
    double c0 = c[0] / (w * w);
    double c1 = c[1] / w - 2 * c[0] * a / (w * w);
    double c2 = c[0] * a * a / (w * w) - c[1] * a / w + c[2];
    return {Float(c0), Float(c1), Float(c2)};
}

/// Thread-safe memo of solve_coefficients; scenes repeat colours.
Coefficients cached_coefficients(Rgb rgb) {
    using Key = std::array<std::uint32_t, 3>;
    static std::mutex mutex;
    static std::map<Key, Coefficients> cache;
    // +0 and -0 are the same colour.
    auto bits = [](Float v) { return std::bit_cast<std::uint32_t>(v == 0 ? Float(0) : v); };
    Key key{bits(rgb.r), bits(rgb.g), bits(rgb.b)};
    {
        std::lock_guard<std::mutex> lock(mutex);
        if (auto it = cache.find(key); it != cache.end()) return it->second;
    }
    Coefficients c = solve_coefficients(rgb);  // outside the lock: other colours proceed
    std::lock_guard<std::mutex> lock(mutex);
    cache.emplace(key, c);
    return c;
}

void check_finite_non_negative(Rgb rgb, const char* what) {
    for (int i = 0; i < 3; ++i)
        if (!std::isfinite(rgb[i]) || rgb[i] < 0)
            throw Error(fmt::format("{}: RGB ({}, {}, {}) must be finite and non-negative", what,
                                    rgb.r, rgb.g, rgb.b));
}

}  // namespace

RgbAlbedoSpectrum rgb_albedo_spectrum(Rgb rgb) {
    check_finite_non_negative(rgb, "reflectance");
    if (rgb.r > 1 || rgb.g > 1 || rgb.b > 1)
        throw Error(fmt::format("reflectance: RGB ({}, {}, {}) must lie in [0, 1]", rgb.r, rgb.g,
                                rgb.b));
    Coefficients c = cached_coefficients(rgb);
    return {c.c0, c.c1, c.c2};
}

RgbUnboundedSpectrum rgb_unbounded_spectrum(Rgb rgb) {
    check_finite_non_negative(rgb, "unbounded RGB");
    // pbrt-v4: scale = 2 max(r, g, b) and fit rgb / scale, whose largest component is 1/2.
    Float m = std::max({rgb.r, rgb.g, rgb.b});
    Float scale = 2 * m;
    Rgb fit = scale > 0 ? Rgb{rgb.r / scale, rgb.g / scale, rgb.b / scale} : Rgb{0, 0, 0};
    Coefficients c = cached_coefficients(fit);
    return {scale, c.c0, c.c1, c.c2};
}

RgbIlluminantSpectrum rgb_illuminant_spectrum(Rgb rgb) {
    check_finite_non_negative(rgb, "illuminant RGB");
    RgbUnboundedSpectrum u = rgb_unbounded_spectrum(rgb);
    return {u.scale, u.c0, u.c1, u.c2, srgb_illuminant()};
}

}  // namespace sr
