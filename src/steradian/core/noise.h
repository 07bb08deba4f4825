#pragma once
/// Gradient noise for procedural textures: Perlin's improved noise (K. Perlin, "Improving
/// Noise", SIGGRAPH 2002: the quintic fade 6t^5 - 15t^4 + 10t^3 and gradients picked from
/// the cube's 12 edge directions by a permutation of 0..255), and the fractional Brownian
/// motion and turbulence sums pbrt-v4's "fbm", "wrinkled" and "windy" textures use. The
/// noise is 0 at every lattice point and lies in [-1, 1]; it repeats every 256 units.
#include "steradian/core/math.h"

namespace sr {

Float perlin_noise(Float x, Float y = Float(0.5), Float z = Float(0.5));
inline Float perlin_noise(Point3 p) { return perlin_noise(p.x, p.y, p.z); }

/// The forward differences (noise(p + 0.01 e_i) - noise(p)) / 0.01 along x, y and z: an
/// estimate of the noise's gradient, pbrt-v4's DNoise (which "cloud" media use).
Vec3 perlin_noise_differences(Point3 p);

/// sum over i < n of omega^i noise(1.99^i p), band-limited by the footprint (dpdx, dpdy) as
/// pbrt-v4's FBm: n = clamp(-1 - log2(max(|dpdx|^2, |dpdy|^2)) / 2, 0, max_octaves) octaves
/// (an octave of period finer than about two footprints is left out), the fractional one
/// faded in by smoothstep(frac(n), 0.3, 0.7). A zero footprint keeps every octave.
Float fbm(Point3 p, Vec3 dpdx, Vec3 dpdy, Float omega, int max_octaves);
inline Float fbm(Point3 p, Float omega, int octaves) {
    return fbm(p, Vec3(0, 0, 0), Vec3(0, 0, 0), omega, octaves);
}
/// sum over the same octaves of omega^i |noise(1.99^i p)|, each octave left out replaced by
/// 0.2 omega^i (about the mean of |noise|), and the one past the last by 0.2 omega^n when
/// all are kept: pbrt-v4's Turbulence.
Float turbulence(Point3 p, Vec3 dpdx, Vec3 dpdy, Float omega, int max_octaves);
inline Float turbulence(Point3 p, Float omega, int octaves) {
    return turbulence(p, Vec3(0, 0, 0), Vec3(0, 0, 0), omega, octaves);
}

}  // namespace sr
