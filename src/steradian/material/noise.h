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

/// sum over i < octaves of omega^i noise(1.99^i p): pbrt-v4's FBm with every octave (no ray
/// differentials to band-limit it).
Float fbm(Point3 p, Float omega, int octaves);
/// sum over i < octaves of omega^i |noise(1.99^i p)| + 0.2 omega^octaves: pbrt-v4's
/// Turbulence with every octave (its last term stands for the octaves left out).
Float turbulence(Point3 p, Float omega, int octaves);

}  // namespace sr
