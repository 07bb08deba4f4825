#include "steradian/core/noise.h"

#include <cmath>

namespace sr {

namespace {

/// Perlin's permutation of 0..255 (the table of his reference implementation of "Improving
/// Noise", SIGGRAPH 2002, also pbrt-v4's NoisePerm), indexed modulo 256.
constexpr int kPerm[256] = {
    151, 160, 137, 91,  90,  15,  131, 13,  201, 95,  96,  53,  194, 233, 7,   225, 140, 36,  103,
    30,  69,  142, 8,   99,  37,  240, 21,  10,  23,  190, 6,   148, 247, 120, 234, 75,  0,   26,
    197, 62,  94,  252, 219, 203, 117, 35,  11,  32,  57,  177, 33,  88,  237, 149, 56,  87,  174,
    20,  125, 136, 171, 168, 68,  175, 74,  165, 71,  134, 139, 48,  27,  166, 77,  146, 158, 231,
    83,  111, 229, 122, 60,  211, 133, 230, 220, 105, 92,  41,  55,  46,  245, 40,  244, 102, 143,
    54,  65,  25,  63,  161, 1,   216, 80,  73,  209, 76,  132, 187, 208, 89,  18,  169, 200, 196,
    135, 130, 116, 188, 159, 86,  164, 100, 109, 198, 173, 186, 3,   64,  52,  217, 226, 250, 124,
    123, 5,   202, 38,  147, 118, 126, 255, 82,  85,  212, 207, 206, 59,  227, 47,  16,  58,  17,
    182, 189, 28,  42,  223, 183, 170, 213, 119, 248, 152, 2,   44,  154, 163, 70,  221, 153, 101,
    155, 167, 43,  172, 9,   129, 22,  39,  253, 19,  98,  108, 110, 79,  113, 224, 232, 178, 185,
    112, 104, 218, 246, 97,  228, 251, 34,  242, 193, 238, 210, 144, 12,  191, 179, 162, 241, 81,
    51,  145, 235, 249, 14,  239, 107, 49,  192, 214, 31,  181, 199, 106, 157, 184, 84,  204, 176,
    115, 121, 50,  45,  127, 4,   150, 254, 138, 236, 205, 93,  222, 114, 67,  29,  24,  72,  243,
    141, 128, 195, 78,  66,  215, 61,  156, 180,
};

int perm(int i) { return kPerm[i & 255]; }

/// The dot product of the lattice point's gradient (one of the 12 directions to the cube's
/// edge midpoints, 4 of them twice: Perlin 2002) with the offset (dx, dy, dz) from it.
Float grad(int x, int y, int z, Float dx, Float dy, Float dz) {
    const int h = perm(perm(perm(x) + y) + z) & 15;
    const Float u = h < 8 || h == 12 || h == 13 ? dx : dy;
    const Float v = h < 4 || h == 12 || h == 13 ? dy : dz;
    return ((h & 1) ? -u : u) + ((h & 2) ? -v : v);
}

Float fade(Float t) { return t * t * t * (t * (t * 6 - 15) + 10); }

}  // namespace

Float perlin_noise(Float x, Float y, Float z) {
    // Beyond 2^30 the cell index would not fit an int; the noise repeats every 256 anyway.
    x = std::fmod(x, Float(1 << 30));
    y = std::fmod(y, Float(1 << 30));
    z = std::fmod(z, Float(1 << 30));
    const Float fx = std::floor(x), fy = std::floor(y), fz = std::floor(z);
    const Float dx = x - fx, dy = y - fy, dz = z - fz;
    const int ix = int(fx) & 255, iy = int(fy) & 255, iz = int(fz) & 255;
    const Float w000 = grad(ix, iy, iz, dx, dy, dz);
    const Float w100 = grad(ix + 1, iy, iz, dx - 1, dy, dz);
    const Float w010 = grad(ix, iy + 1, iz, dx, dy - 1, dz);
    const Float w110 = grad(ix + 1, iy + 1, iz, dx - 1, dy - 1, dz);
    const Float w001 = grad(ix, iy, iz + 1, dx, dy, dz - 1);
    const Float w101 = grad(ix + 1, iy, iz + 1, dx - 1, dy, dz - 1);
    const Float w011 = grad(ix, iy + 1, iz + 1, dx, dy - 1, dz - 1);
    const Float w111 = grad(ix + 1, iy + 1, iz + 1, dx - 1, dy - 1, dz - 1);
    const Float wx = fade(dx), wy = fade(dy), wz = fade(dz);
    const Float y0 = lerp(wy, lerp(wx, w000, w100), lerp(wx, w010, w110));
    const Float y1 = lerp(wy, lerp(wx, w001, w101), lerp(wx, w011, w111));
    return lerp(wz, y0, y1);
}

Vec3 perlin_noise_differences(Point3 p) {
    constexpr Float delta = Float(0.01);
    const Float n = perlin_noise(p);
    return Vec3(perlin_noise(p.x + delta, p.y, p.z) - n, perlin_noise(p.x, p.y + delta, p.z) - n,
                perlin_noise(p.x, p.y, p.z + delta) - n) /
           delta;
}

namespace {
/// The number of octaves a footprint allows (pbrt-v4's FBm / Turbulence).
Float octaves_for(Vec3 dpdx, Vec3 dpdy, int max_octaves) {
    const Float len2 = std::max(length_squared(dpdx), length_squared(dpdy));
    if (!(len2 > 0)) return Float(max_octaves);
    return std::clamp(-1 - std::log2(len2) / 2, Float(0), Float(max_octaves));
}
Float smoothstep(Float x, Float a, Float b) {
    const Float t = std::clamp((x - a) / (b - a), Float(0), Float(1));
    return t * t * (3 - 2 * t);
}
Point3 scaled(Point3 p, Float s) { return Point3(p.x * s, p.y * s, p.z * s); }
}  // namespace

Float fbm(Point3 p, Vec3 dpdx, Vec3 dpdy, Float omega, int max_octaves) {
    const Float n = octaves_for(dpdx, dpdy, max_octaves);
    const int n_int = int(std::floor(n));
    Float sum = 0, scale = 1, o = 1;
    for (int i = 0; i < n_int; ++i) {
        sum += o * perlin_noise(scaled(p, scale));
        scale *= Float(1.99);
        o *= omega;
    }
    const Float partial = n - Float(n_int);
    if (partial > 0) sum += o * smoothstep(partial, Float(0.3), Float(0.7)) * perlin_noise(scaled(p, scale));
    return sum;
}

Float turbulence(Point3 p, Vec3 dpdx, Vec3 dpdy, Float omega, int max_octaves) {
    const Float n = octaves_for(dpdx, dpdy, max_octaves);
    const int n_int = int(std::floor(n));
    Float sum = 0, scale = 1, o = 1;
    for (int i = 0; i < n_int; ++i) {
        sum += o * std::abs(perlin_noise(scaled(p, scale)));
        scale *= Float(1.99);
        o *= omega;
    }
    // The partial octave fades from 0.2 to |noise|; the octaves left out count 0.2 each.
    const Float fade = smoothstep(n - Float(n_int), Float(0.3), Float(0.7));
    sum += o * ((1 - fade) * Float(0.2) + fade * std::abs(perlin_noise(scaled(p, scale))));
    for (int i = n_int; i < max_octaves; ++i) {
        sum += o * Float(0.2);
        o *= omega;
    }
    return sum;
}

}  // namespace sr
