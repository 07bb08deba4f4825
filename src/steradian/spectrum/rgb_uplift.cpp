/// RGB -> spectrum uplift for the sRGB colour space (Jakob & Hanika 2019, "A Low-Dimensional
/// Function Space for Efficient Spectral Upsampling", Computer Graphics Forum 38(2)).
///
/// Exact path (rgb_*_spectrum): each colour is solved when first asked for: Gauss-Newton on
/// the CIELAB (CIE 1976) difference between the target and the colour of the
/// sigmoid-polynomial reflectance under D65, with continuation from the c = 0 spectrum
/// (0.5 grey) towards the target, as the paper's optimiser walks its grid. The fit uses the
/// normalised wavelength t = (l - 360) / 470 for conditioning and is converted to
/// coefficients in nm at the end. Results are cached (thread-safe).
///
/// Fast path (rgb_*_spectrum_interpolated): the paper's coefficient table, built here by the
/// same solver on first use, trilinearly interpolated; for colours that vary per shading
/// point (image textures).
#include <array>
#include <bit>
#include <cmath>
#include <cstdint>
#include <map>
#include <mutex>
#include <thread>

#include "steradian/core/error.h"
#include "steradian/spectrum/cie_data.h"
#include "steradian/spectrum/sigmoid.h"
#include "steradian/spectrum/spectrum.h"

namespace sr {

namespace {

constexpr double kLambda0 = kLambdaMin;
constexpr double kLambdaRange = kLambdaMax - kLambdaMin;

using Vec3 = std::array<double, 3>;
using Mat3 = std::array<Vec3, 3>;  // row-major

/// Quadrature of a reflectance's colour under D65: XYZ = sum_i s(t_i) w_i, normalised so
/// that s = 1 has Y = 1.
struct Quadrature {
    std::vector<double> t, wx, wy, wz;
    Vec3 white{};  ///< XYZ of the perfect white reflector under D65
};

/// The 1 nm sums over 360..830 nm that spectrum_to_xyz and reflectance_to_xyz use: fits made
/// with it round-trip exactly through those functions.
Quadrature make_fine_quadrature() {
    const std::vector<Float>& d65 = *srgb_illuminant().values;
    Quadrature q;
    double yw = 0;
    for (int i = 0; i < cie::kCmfCount; ++i) yw += cie::kY[i] * double(d65[i]);
    for (int i = 0; i < cie::kCmfCount; ++i) {
        double e = double(d65[i]) / yw;
        q.t.push_back(i / kLambdaRange);
        q.wx.push_back(cie::kX[i] * e);
        q.wy.push_back(cie::kY[i] * e);
        q.wz.push_back(cie::kZ[i] * e);
    }
    for (size_t i = 0; i < q.t.size(); ++i) {
        q.white[0] += q.wx[i];
        q.white[1] += q.wy[i];
        q.white[2] += q.wz[i];
    }
    return q;
}

/// The fine weights lumped onto nodes every `step` nm with hat functions (exact for spectra
/// that are piecewise linear between the nodes): ~step times cheaper, for building tables.
Quadrature make_coarse_quadrature(const Quadrature& fine, int step) {
    Quadrature q;
    int nodes = int(kLambdaRange) / step + 1;
    q.t.resize(nodes);
    q.wx.assign(nodes, 0);
    q.wy.assign(nodes, 0);
    q.wz.assign(nodes, 0);
    for (int j = 0; j < nodes; ++j) q.t[j] = j * step / kLambdaRange;
    for (size_t i = 0; i < fine.t.size(); ++i) {
        int j = std::min(int(i) / step, nodes - 2);
        double f = (double(i) - j * step) / step;
        q.wx[j] += (1 - f) * fine.wx[i];
        q.wx[j + 1] += f * fine.wx[i];
        q.wy[j] += (1 - f) * fine.wy[i];
        q.wy[j + 1] += f * fine.wy[i];
        q.wz[j] += (1 - f) * fine.wz[i];
        q.wz[j + 1] += f * fine.wz[i];
    }
    q.white = fine.white;
    return q;
}

const Quadrature& fine_quadrature() {
    static const Quadrature q = make_fine_quadrature();
    return q;
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
Vec3 eval_xyz(const Quadrature& q, const Vec3& c, Mat3* jac) {
    Vec3 xyz{0, 0, 0};
    Mat3 j{};
    for (size_t i = 0; i < q.t.size(); ++i) {
        double t = q.t[i];
        double x = (c[0] * t + c[1]) * t + c[2];
        double q2 = 1 + x * x;
        double sq = std::sqrt(q2);
        double s = 0.5 + x / (2 * sq);
        xyz[0] += q.wx[i] * s;
        xyz[1] += q.wy[i] * s;
        xyz[2] += q.wz[i] * s;
        if (jac) {
            double ds = 0.5 / (q2 * sq);  // dS/dx
            double g[3] = {ds * t * t, ds * t, ds};
            for (int k = 0; k < 3; ++k) {
                j[0][k] += q.wx[i] * g[k];
                j[1][k] += q.wy[i] * g[k];
                j[2][k] += q.wz[i] * g[k];
            }
        }
    }
    if (jac) *jac = j;
    return xyz;
}

/// Residual (Lab of the spectrum minus the target Lab) and its Jacobian w.r.t. c.
Vec3 residual(const Quadrature& q, const Vec3& c, const Vec3& target_lab, Mat3* jac) {
    Mat3 jxyz, jlab;
    Vec3 lab = xyz_to_lab(eval_xyz(q, c, jac ? &jxyz : nullptr), q.white, jac ? &jlab : nullptr);
    if (jac) {
        for (int r = 0; r < 3; ++r)
            for (int k = 0; k < 3; ++k)
                (*jac)[r][k] =
                    jlab[r][0] * jxyz[0][k] + jlab[r][1] * jxyz[1][k] + jlab[r][2] * jxyz[2][k];
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
double gauss_newton(const Quadrature& q, Vec3& c, const Vec3& target_lab, double tolerance,
                    int max_iterations) {
    Mat3 jac;
    Vec3 r = residual(q, c, target_lab, &jac);
    double err = norm(r);
    for (int it = 0; it < max_iterations && err > tolerance; ++it) {
        Vec3 step;
        if (!solve3(jac, r, step)) break;
        // Backtracking: accept the first step length that reduces the residual.
        bool improved = false;
        for (double alpha = 1; alpha > 1.0 / 1024; alpha *= 0.5) {
            Vec3 cn{c[0] - alpha * step[0], c[1] - alpha * step[1], c[2] - alpha * step[2]};
            Mat3 jn;
            Vec3 rn = residual(q, cn, target_lab, &jn);
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

Vec3 rgb_to_xyz(Rgb rgb) {
    // IEC 61966-2-1 matrix in double (color.h has the same numbers in Float).
    double r = rgb.r, g = rgb.g, b = rgb.b;
    return {0.4124564 * r + 0.3575761 * g + 0.1804375 * b,
            0.2126729 * r + 0.7151522 * g + 0.0721750 * b,
            0.0193339 * r + 0.1191920 * g + 0.9503041 * b};
}

/// Continuation: walks the target from the colour of c (XYZ) to target_xyz in adaptive
/// steps, re-solving from the previous solution each time, then polishes on the final
/// target. Returns the final CIELAB residual; c holds the best point.
double continuation(const Quadrature& q, Vec3& c, const Vec3& target_xyz, double tolerance,
                    int polish_iterations) {
    Vec3 start_xyz = eval_xyz(q, c, nullptr);
    double t = 0, dt = 0.25;
    constexpr double kStepTolerance = 1e-3;  // Delta E, intermediate targets
    while (t < 1 && dt > 1.0 / 4096) {
        double tn = std::min(1.0, t + dt);
        Vec3 ct = c;
        Vec3 lab = xyz_to_lab(lerp3(tn, start_xyz, target_xyz), q.white);
        if (gauss_newton(q, ct, lab, kStepTolerance, 12) <= kStepTolerance) {
            c = ct;
            t = tn;
            dt = std::min(1.0, 2 * dt);
        } else {
            dt *= 0.5;
        }
    }
    // Polish on the final target (also the best effort when continuation stalled).
    return gauss_newton(q, c, xyz_to_lab(target_xyz, q.white), tolerance, polish_iterations);
}

/// Normalised coefficients -> coefficients in nm: x(l) = c0 t^2 + c1 t + c2 with
/// t = (l - a) / w, expanded in powers of l.
std::array<Float, 3> to_nm(const Vec3& c) {
    double a = kLambda0, w = kLambdaRange;
    double c0 = c[0] / (w * w);
    double c1 = c[1] / w - 2 * c[0] * a / (w * w);
    double c2 = c[0] * a * a / (w * w) - c[1] * a / w + c[2];
    return {Float(c0), Float(c1), Float(c2)};
}

using Coefficients = std::array<Float, 3>;  // c0, c1, c2 in nm

/// Exact coefficients in nm for rgb in [0,1]^3.
Coefficients solve_coefficients(Rgb rgb) {
    if (rgb.r == rgb.g && rgb.g == rgb.b) {
        // Constant spectrum: S(c2) = value, exactly (+-infinity at 1 and 0).
        return {0, 0, Float(inverse_sigmoid(rgb.r))};
    }
    Vec3 c{0, 0, 0};  // the constant 0.5 reflectance
    continuation(fine_quadrature(), c, rgb_to_xyz(rgb), 1e-7, 60);
    return to_nm(c);
}

/// Thread-safe memo of solve_coefficients; scenes repeat colours. Bounded so that a caller
/// that uplifts continuously varying colours cannot exhaust memory.
Coefficients cached_coefficients(Rgb rgb) {
    using Key = std::array<std::uint32_t, 3>;
    constexpr size_t kMaxEntries = size_t(1) << 16;
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
    if (cache.size() < kMaxEntries) cache.emplace(key, c);
    return c;
}

// ---- coefficient table (Jakob & Hanika 2019, section 4) --------------------------------------

/// Coefficients at rgb with rgb[l] = z the largest component and the other two
/// x z = rgb[(l + 1) % 3], y z = rgb[(l + 2) % 3], on a res^3 grid per l; z nodes are
/// denser near 0 and 1: z_k = smoothstep(smoothstep(k / (res - 1))).
class CoefficientTable {
  public:
    static constexpr int kRes = 64;

    CoefficientTable() : m_z(kRes), m_zf(kRes), m_c(size_t(3) * kRes * kRes * kRes) {
        for (int k = 0; k < kRes; ++k) {
            m_z[k] = smoothstep(smoothstep(double(k) / (kRes - 1)));
            m_zf[k] = Float(m_z[k]);
        }
        const Quadrature coarse = make_coarse_quadrature(fine_quadrature(), 5);
        // The three sub-tables are independent: one thread each (deterministic results).
        std::vector<std::thread> workers;
        for (int l = 0; l < 3; ++l) workers.emplace_back([this, l, &coarse] { build(l, coarse); });
        for (std::thread& w : workers) w.join();
    }

    Coefficients lookup(Rgb rgb) const {
        int l = (rgb.r >= rgb.g && rgb.r >= rgb.b) ? 0 : (rgb.g >= rgb.b ? 1 : 2);
        Float z = rgb[l];
        Float scale = Float(kRes - 1) / z;
        Float x = rgb[(l + 1) % 3] * scale, y = rgb[(l + 2) % 3] * scale;
        int xi = std::min(int(x), kRes - 2), yi = std::min(int(y), kRes - 2);
        int zi = int(std::upper_bound(m_zf.begin(), m_zf.end(), z) - m_zf.begin()) - 1;
        zi = std::clamp(zi, 0, kRes - 2);
        Float dx = x - Float(xi), dy = y - Float(yi);
        Float dz = (z - m_zf[zi]) / (m_zf[zi + 1] - m_zf[zi]);
        const Coefficients* c = &m_c[index(l, zi, yi, xi)];
        constexpr size_t sy = kRes, sz = size_t(kRes) * kRes;
        Coefficients out{};
        for (int k = 0; k < 3; ++k) {
            auto mix = [](Float a, Float b, Float t) { return a + t * (b - a); };
            Float c00 = mix(c[0][k], c[1][k], dx), c10 = mix(c[sy][k], c[sy + 1][k], dx);
            Float c01 = mix(c[sz][k], c[sz + 1][k], dx);
            Float c11 = mix(c[sz + sy][k], c[sz + sy + 1][k], dx);
            out[k] = mix(mix(c00, c10, dy), mix(c01, c11, dy), dz);
        }
        return out;
    }

  private:
    static double smoothstep(double x) { return x * x * (3 - 2 * x); }
    static size_t index(int l, int zi, int yi, int xi) {
        return ((size_t(l) * kRes + zi) * kRes + yi) * kRes + xi;
    }

    /// Fills sub-table l: per (x, y) column, a solve at a middle z (warm-started from the
    /// previous column), then a walk up and down z warm-started from the neighbour.
    void build(int l, const Quadrature& q) {
        constexpr double kTolerance = 1e-2;  // Delta E, well below visibility
        const int z_start = kRes / 5;
        Vec3 seed{0, 0, 0}, row_seed{0, 0, 0};
        for (int yi = 0; yi < kRes; ++yi) {
            for (int xi = 0; xi < kRes; ++xi) {
                auto target = [&](int zi) {
                    double rgb[3];
                    rgb[l] = m_z[zi];
                    rgb[(l + 1) % 3] = m_z[zi] * xi / (kRes - 1);
                    rgb[(l + 2) % 3] = m_z[zi] * yi / (kRes - 1);
                    return rgb_to_xyz({Float(rgb[0]), Float(rgb[1]), Float(rgb[2])});
                };
                auto solve_from = [&](Vec3 c, int zi) {
                    Vec3 txyz = target(zi);
                    Vec3 tried = c;
                    if (gauss_newton(q, tried, xyz_to_lab(txyz, q.white), kTolerance, 20) >
                        kTolerance)
                        continuation(q, c, txyz, kTolerance, 30);
                    else
                        c = tried;
                    m_c[index(l, zi, yi, xi)] = to_nm(c);
                    return c;
                };
                // Warm start from the previous column, or from the previous row's first.
                seed = solve_from(xi == 0 ? row_seed : seed, z_start);
                if (xi == 0) row_seed = seed;
                // Walk z from the seed both ways; the initial guess extrapolates linearly
                // from the last two solutions (a predictor-corrector continuation).
                for (int dir : {1, -1}) {
                    Vec3 c = seed, prev = seed;
                    for (int zi = z_start + dir, n = 0; zi >= 0 && zi < kRes; zi += dir, ++n) {
                        Vec3 guess = c;
                        if (n > 0) {
                            double f =
                                (m_z[zi] - m_z[zi - dir]) / (m_z[zi - dir] - m_z[zi - 2 * dir]);
                            guess = lerp3(1 + f, prev, c);
                        }
                        prev = c;
                        c = solve_from(guess, zi);
                    }
                }
            }
        }
    }

    std::vector<double> m_z;
    std::vector<Float> m_zf;
    std::vector<Coefficients> m_c;  ///< [l][z][y][x], coefficients in nm
};

const CoefficientTable& coefficient_table() {
    static const CoefficientTable table;
    return table;
}

void check_finite_non_negative(Rgb rgb, const char* what) {
    for (int i = 0; i < 3; ++i)
        if (!std::isfinite(rgb[i]) || rgb[i] < 0)
            throw Error(fmt::format("{}: RGB ({}, {}, {}) must be finite and non-negative", what,
                                    rgb.r, rgb.g, rgb.b));
}

void check_albedo(Rgb rgb) {
    check_finite_non_negative(rgb, "reflectance");
    if (rgb.r > 1 || rgb.g > 1 || rgb.b > 1)
        throw Error(
            fmt::format("reflectance: RGB ({}, {}, {}) must lie in [0, 1]", rgb.r, rgb.g, rgb.b));
}

/// pbrt-v4's unbounded convention: scale = 2 max(r, g, b); the fitted colour is rgb / scale,
/// whose largest component is 1/2.
Float unbounded_scale(Rgb rgb, Rgb& fit) {
    Float scale = 2 * std::max({rgb.r, rgb.g, rgb.b});
    fit = scale > 0 ? Rgb{rgb.r / scale, rgb.g / scale, rgb.b / scale} : Rgb{0, 0, 0};
    return scale;
}

Coefficients interpolated_coefficients(Rgb rgb) {
    if (rgb.r == rgb.g && rgb.g == rgb.b) return {0, 0, Float(inverse_sigmoid(rgb.r))};
    return coefficient_table().lookup(rgb);
}

}  // namespace

RgbAlbedoSpectrum rgb_albedo_spectrum(Rgb rgb) {
    check_albedo(rgb);
    Coefficients c = cached_coefficients(rgb);
    return {c[0], c[1], c[2]};
}

RgbUnboundedSpectrum rgb_unbounded_spectrum(Rgb rgb) {
    check_finite_non_negative(rgb, "unbounded RGB");
    Rgb fit;
    Float scale = unbounded_scale(rgb, fit);
    Coefficients c = cached_coefficients(fit);
    return {scale, c[0], c[1], c[2]};
}

RgbIlluminantSpectrum rgb_illuminant_spectrum(Rgb rgb) {
    check_finite_non_negative(rgb, "illuminant RGB");
    RgbUnboundedSpectrum u = rgb_unbounded_spectrum(rgb);
    return {u.scale, u.c0, u.c1, u.c2, srgb_illuminant()};
}

void build_rgb_uplift_table() { (void)coefficient_table(); }

RgbAlbedoSpectrum rgb_albedo_spectrum_interpolated(Rgb rgb) {
    // Clamped rather than rejected: texture filtering may overshoot [0, 1] slightly.
    for (int i = 0; i < 3; ++i)
        if (std::isnan(rgb[i])) return {0, 0, -kInfinity};
    rgb = {clamp(rgb.r, Float(0), Float(1)), clamp(rgb.g, Float(0), Float(1)),
           clamp(rgb.b, Float(0), Float(1))};
    Coefficients c = interpolated_coefficients(rgb);
    return {c[0], c[1], c[2]};
}

RgbUnboundedSpectrum rgb_unbounded_spectrum_interpolated(Rgb rgb) {
    for (int i = 0; i < 3; ++i)
        if (std::isnan(rgb[i])) return {0, 0, 0, -kInfinity};
    rgb = {std::max(rgb.r, Float(0)), std::max(rgb.g, Float(0)), std::max(rgb.b, Float(0))};
    Rgb fit;
    Float scale = unbounded_scale(rgb, fit);
    if (!std::isfinite(scale)) return {0, 0, 0, -kInfinity};
    Coefficients c = interpolated_coefficients(fit);
    return {scale, c[0], c[1], c[2]};
}

RgbIlluminantSpectrum rgb_illuminant_spectrum_interpolated(Rgb rgb) {
    RgbUnboundedSpectrum u = rgb_unbounded_spectrum_interpolated(rgb);
    return {u.scale, u.c0, u.c1, u.c2, srgb_illuminant()};
}

}  // namespace sr
