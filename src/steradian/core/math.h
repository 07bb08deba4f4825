#pragma once
/// Core scalar and vector math: Float, Vec2/Vec3 templates, Frame, and helpers.
/// Points, vectors and normals share one type (Vec3); the name of a variable says which.
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>
#include <numbers>

namespace sr {

using Float = float;

inline constexpr Float kPi = std::numbers::pi_v<Float>;
inline constexpr Float kInvPi = std::numbers::inv_pi_v<Float>;
inline constexpr Float kInv2Pi = Float(0.5) * std::numbers::inv_pi_v<Float>;
inline constexpr Float kInv4Pi = Float(0.25) * std::numbers::inv_pi_v<Float>;
inline constexpr Float kPiOver2 = Float(0.5) * std::numbers::pi_v<Float>;
inline constexpr Float kPiOver4 = Float(0.25) * std::numbers::pi_v<Float>;
inline constexpr Float kInfinity = std::numeric_limits<Float>::infinity();
/// Largest float strictly below 1: the upper end of [0, 1) random numbers.
inline constexpr Float kOneMinusEpsilon = 0x1.fffffep-1f;

template <typename T>
constexpr T sqr(T x) { return x * x; }
template <typename T>
constexpr T clamp(T x, T lo, T hi) { return x < lo ? lo : (x > hi ? hi : x); }
template <typename T, typename U>
constexpr T lerp(U t, T a, T b) { return (1 - t) * a + t * b; }
inline Float safe_sqrt(Float x) { return std::sqrt(std::max(Float(0), x)); }
inline double safe_sqrt(double x) { return std::sqrt(std::max(0.0, x)); }
inline Float safe_asin(Float x) { return std::asin(clamp(x, Float(-1), Float(1))); }
inline Float safe_acos(Float x) { return std::acos(clamp(x, Float(-1), Float(1))); }
// ---- short polynomial sin, cos and atan2 for the sampling kernels ---------------------------
// Minimax-fitted here (iteratively reweighted least squares on Chebyshev nodes, numpy, double
// precision) and checked against the libm functions by math_test.cpp. They replace
// std::sin/cos/atan2 where a path calls them per sample (light and BSDF sampling), at a third
// of the instructions; their error is a few float ulps, far below anything a sample can show.

/// sin and cos of x for |x| <= pi/4 (no range reduction). Absolute error < 1e-7.
inline void sincos_pi4(Float x, Float& s, Float& c) {
    Float x2 = x * x;
    s = x + x * x2 * (Float(-0.166666647) + x2 * (Float(0.008332749) + x2 * Float(-0.000195880094)));
    c = 1 + x2 * (Float(-0.5) +
                  x2 * (Float(0.041666651) + x2 * (Float(-0.00138875996) + x2 * Float(2.44647709e-05))));
}

/// sin and cos of x for |x| <= 64: reduction by the nearest multiple k of pi/2, then
/// sincos_pi4 and the quadrant's symmetry. Absolute error < 2e-7 over that range.
/// The reduction is Cody and Waite's (as in Cephes' sinf): pi/2 split in three floats whose
/// first two have few significant bits, so that k times each is exact and the remainder
/// stays accurate with or without fused multiply-adds (a two-float split relied on the
/// compiler contracting x - k * hi into an FMA: without FMA, the error reached 2e-6).
inline void fast_sincos(Float x, Float& s, Float& c) {
    constexpr Float kPiOver2A = 1.5703125f;                // 8 significant bits
    constexpr Float kPiOver2B = 4.837512969970703125e-4f;  // 11 significant bits
    constexpr Float kPiOver2C = 7.5497899487686e-8f;       // pi/2 - A - B, rounded
    Float k = std::nearbyint(x * Float(0.636619772));  // x * 2/pi
    Float r = ((x - k * kPiOver2A) - k * kPiOver2B) - k * kPiOver2C;
    Float sr, cr;
    sincos_pi4(r, sr, cr);
    switch (int(k) & 3) {
        case 0: s = sr; c = cr; break;
        case 1: s = cr; c = -sr; break;
        case 2: s = -sr; c = -cr; break;
        default: s = -cr; c = sr; break;
    }
}

/// atan2(y, x) in [-pi, pi], with relative error < 3e-7 (atan on [0, 1] as z P(z^2), P of
/// degree 7 in z^2, then the octant's symmetry). atan2(0, 0) = 0.
inline Float fast_atan2(Float y, Float x) {
    Float ax = std::abs(x), ay = std::abs(y);
    Float hi = std::max(ax, ay), lo = std::min(ax, ay);
    if (hi == 0) return 0;
    Float z = lo / hi, z2 = z * z;
    Float p = Float(-0.00469314189);
    p = p * z2 + Float(0.0242519365);
    p = p * z2 + Float(-0.0594857562);
    p = p * z2 + Float(0.099142498);
    p = p * z2 + Float(-0.14019466);
    p = p * z2 + Float(0.199697215);
    p = p * z2 + Float(-0.333319906);
    p = p * z2 + Float(0.999999901);
    Float a = z * p;
    if (ay > ax) a = kPiOver2 - a;
    if (x < 0) a = kPi - a;
    return std::signbit(y) ? -a : a;
}

inline Float radians(Float deg) { return deg * (kPi / 180); }
inline Float degrees(Float rad) { return rad * (180 / kPi); }

template <typename T>
struct Vec2T {
    T x{}, y{};
    constexpr Vec2T() = default;
    constexpr Vec2T(T x_, T y_) : x(x_), y(y_) {}
    constexpr T operator[](int i) const { return i == 0 ? x : y; }
    constexpr T& operator[](int i) { return i == 0 ? x : y; }
    constexpr Vec2T operator+(Vec2T o) const { return {x + o.x, y + o.y}; }
    constexpr Vec2T operator-(Vec2T o) const { return {x - o.x, y - o.y}; }
    constexpr Vec2T operator*(T s) const { return {x * s, y * s}; }
    constexpr Vec2T operator/(T s) const { return {x / s, y / s}; }
    constexpr bool operator==(const Vec2T&) const = default;
};
using Vec2 = Vec2T<Float>;
using Vec2i = Vec2T<int>;
using Vec2d = Vec2T<double>;
using Point2 = Vec2;

template <typename T>
struct Vec3T {
    T x{}, y{}, z{};
    constexpr Vec3T() = default;
    constexpr Vec3T(T x_, T y_, T z_) : x(x_), y(y_), z(z_) {}
    template <typename U>
    constexpr explicit Vec3T(Vec3T<U> v) : x(T(v.x)), y(T(v.y)), z(T(v.z)) {}
    constexpr T operator[](int i) const { return i == 0 ? x : (i == 1 ? y : z); }
    constexpr T& operator[](int i) { return i == 0 ? x : (i == 1 ? y : z); }
    constexpr Vec3T operator-() const { return {-x, -y, -z}; }
    constexpr Vec3T operator+(Vec3T o) const { return {x + o.x, y + o.y, z + o.z}; }
    constexpr Vec3T operator-(Vec3T o) const { return {x - o.x, y - o.y, z - o.z}; }
    constexpr Vec3T operator*(Vec3T o) const { return {x * o.x, y * o.y, z * o.z}; }
    constexpr Vec3T operator*(T s) const { return {x * s, y * s, z * s}; }
    constexpr Vec3T operator/(T s) const {
        T inv = T(1) / s;
        return {x * inv, y * inv, z * inv};
    }
    constexpr Vec3T& operator+=(Vec3T o) { x += o.x; y += o.y; z += o.z; return *this; }
    constexpr Vec3T& operator-=(Vec3T o) { x -= o.x; y -= o.y; z -= o.z; return *this; }
    constexpr Vec3T& operator*=(T s) { x *= s; y *= s; z *= s; return *this; }
    constexpr bool operator==(const Vec3T&) const = default;
};
template <typename T>
constexpr Vec3T<T> operator*(T s, Vec3T<T> v) { return v * s; }
using Vec3 = Vec3T<Float>;
using Vec3d = Vec3T<double>;
using Point3 = Vec3;
using Normal3 = Vec3;

template <typename T>
constexpr T dot(Vec3T<T> a, Vec3T<T> b) { return a.x * b.x + a.y * b.y + a.z * b.z; }
template <typename T>
constexpr T absdot(Vec3T<T> a, Vec3T<T> b) { return std::abs(dot(a, b)); }
template <typename T>
constexpr Vec3T<T> cross(Vec3T<T> a, Vec3T<T> b) {
    return {a.y * b.z - a.z * b.y, a.z * b.x - a.x * b.z, a.x * b.y - a.y * b.x};
}
template <typename T>
constexpr T length_squared(Vec3T<T> v) { return dot(v, v); }
template <typename T>
T length(Vec3T<T> v) { return std::sqrt(dot(v, v)); }
template <typename T>
Vec3T<T> normalize(Vec3T<T> v) { return v / length(v); }
template <typename T>
T distance(Vec3T<T> a, Vec3T<T> b) { return length(a - b); }
template <typename T>
Vec3T<T> vmin(Vec3T<T> a, Vec3T<T> b) {
    return {std::min(a.x, b.x), std::min(a.y, b.y), std::min(a.z, b.z)};
}
template <typename T>
Vec3T<T> vmax(Vec3T<T> a, Vec3T<T> b) {
    return {std::max(a.x, b.x), std::max(a.y, b.y), std::max(a.z, b.z)};
}
template <typename T>
T max_component(Vec3T<T> v) { return std::max({v.x, v.y, v.z}); }
/// n flipped, if needed, into the hemisphere of v.
template <typename T>
Vec3T<T> face_forward(Vec3T<T> n, Vec3T<T> v) { return dot(n, v) < T(0) ? -n : n; }

/// Orthonormal basis from a unit vector (Duff et al. 2017, "Building an Orthonormal Basis,
/// Revisited", JCGT 6(1)).
inline void coordinate_system(Vec3 n, Vec3& s, Vec3& t) {
    Float sign = std::copysign(Float(1), n.z);
    Float a = -1 / (sign + n.z);
    Float b = n.x * n.y * a;
    s = Vec3(1 + sign * n.x * n.x * a, sign * b, -sign * n.x);
    t = Vec3(b, sign + n.y * n.y * a, -n.y);
}

/// Orthonormal frame; to_local/to_world map between world space and the frame (z = n).
struct Frame {
    Vec3 s{1, 0, 0}, t{0, 1, 0}, n{0, 0, 1};
    Frame() = default;
    Frame(Vec3 s_, Vec3 t_, Vec3 n_) : s(s_), t(t_), n(n_) {}
    static Frame from_z(Vec3 n) {
        Frame f;
        f.n = n;
        coordinate_system(n, f.s, f.t);
        return f;
    }
    Vec3 to_local(Vec3 v) const { return {dot(v, s), dot(v, t), dot(v, n)}; }
    Vec3 to_world(Vec3 v) const { return s * v.x + t * v.y + n * v.z; }
};

// Local shading-frame trigonometry (z is the normal).
inline Float cos_theta(Vec3 w) { return w.z; }
inline Float abs_cos_theta(Vec3 w) { return std::abs(w.z); }
inline Float cos2_theta(Vec3 w) { return w.z * w.z; }
inline Float sin2_theta(Vec3 w) { return std::max(Float(0), 1 - cos2_theta(w)); }
inline Float sin_theta(Vec3 w) { return std::sqrt(sin2_theta(w)); }
inline Float tan2_theta(Vec3 w) { return sin2_theta(w) / cos2_theta(w); }
inline Float cos_phi(Vec3 w) {
    Float st = sin_theta(w);
    return st == 0 ? 1 : clamp(w.x / st, Float(-1), Float(1));
}
inline Float sin_phi(Vec3 w) {
    Float st = sin_theta(w);
    return st == 0 ? 0 : clamp(w.y / st, Float(-1), Float(1));
}
inline bool same_hemisphere(Vec3 a, Vec3 b) { return a.z * b.z > 0; }

/// Direction from spherical coordinates (theta from +z, phi from +x).
inline Vec3 spherical_direction(Float sin_t, Float cos_t, Float phi) {
    return {clamp(sin_t, Float(-1), Float(1)) * std::cos(phi),
            clamp(sin_t, Float(-1), Float(1)) * std::sin(phi), clamp(cos_t, Float(-1), Float(1))};
}

/// Axis-aligned bounding box.
struct Bounds3 {
    Vec3 lo{kInfinity, kInfinity, kInfinity};
    Vec3 hi{-kInfinity, -kInfinity, -kInfinity};
    void expand(Vec3 p) { lo = vmin(lo, p); hi = vmax(hi, p); }
    void expand(const Bounds3& b) { lo = vmin(lo, b.lo); hi = vmax(hi, b.hi); }
    bool empty() const { return lo.x > hi.x || lo.y > hi.y || lo.z > hi.z; }
    Vec3 diagonal() const { return hi - lo; }
    Vec3 center() const { return (lo + hi) * Float(0.5); }
};

/// Ray with origin o and direction d; t in (0, t_max).
struct Ray {
    Point3 o;
    Vec3 d;
    Float t_max = kInfinity;
    Point3 at(Float t) const { return o + d * t; }
};

}  // namespace sr
