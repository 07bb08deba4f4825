#pragma once
/// Checks shared by the tests of the reflection-only extension lobes (Phong, Lafortune, Ward):
/// the directional albedo by deterministic cubature of f |cos|, the largest Helmholtz
/// reciprocity error, and the incident directions the tests sweep.
#include <cmath>
#include <vector>

#include "stat/chi2.h"
#include "stat/lobe_util.h"
#include "steradian/sampling/rng.h"
#include "steradian/sampling/warp.h"

namespace sr::testing {

/// Absolute accuracy goal of one cell of the albedo cubature (see sphere_cell_integral); with
/// kAlbedoCells cells the whole integral is good to about kAlbedoCells * kCellTolerance plus
/// the cubature's relative tolerance 1e-5.
inline constexpr double kCellTolerance = 1e-8;
inline constexpr int kAlbedoThetaCells = 9, kAlbedoPhiCells = 18;
inline constexpr int kAlbedoCells = kAlbedoThetaCells * kAlbedoPhiCells;
/// The error bound of albedo_by_cubature for an albedo of about a.
inline double cubature_error(double a) { return kAlbedoCells * kCellTolerance + 1e-5 * a; }

/// Directional albedo int f(wo, wi)[channel] |cos theta_i| dwi over wo's hemisphere, by the
/// adaptive cubature of the chi-square tests over a (theta, phi) grid.
template <typename L>
double albedo_by_cubature(const L& lobe, Vec3 wo, int channel) {
    const double pi = 3.141592653589793;
    const double dt = 0.5 * pi / kAlbedoThetaCells, dp = 2 * pi / kAlbedoPhiCells;
    const double side = wo.z < 0 ? -1 : 1;
    auto integrand = [&](Vec3 w) {
        Vec3 wi(w.x, w.y, Float(w.z * side));
        return Float(lobe.f(wo, wi, TransportMode::Radiance)[channel] * std::abs(wi.z));
    };
    double sum = 0;
    for (int i = 0; i < kAlbedoThetaCells; ++i)
        for (int j = 0; j < kAlbedoPhiCells; ++j)
            sum += sphere_cell_integral(integrand, i * dt, (i + 1) * dt, -pi + j * dp,
                                        -pi + (j + 1) * dp, kCellTolerance);
    return sum;
}

/// Largest relative difference |f(wo, wi) - f(wi, wo)| / max over n pairs of directions
/// drawn uniformly on the sphere; pairs on opposite sides must both give 0 (else returns 1).
template <typename L>
double max_reciprocity_error(const L& lobe, int n, uint64_t seed) {
    Pcg32 rng(seed);
    double worst = 0;
    for (int k = 0; k < n; ++k) {
        Vec3 wo = sample_uniform_sphere({rng.next_float(), rng.next_float()});
        Vec3 wi = sample_uniform_sphere({rng.next_float(), rng.next_float()});
        SampledSpectrum a = lobe.f(wo, wi, TransportMode::Radiance);
        SampledSpectrum b = lobe.f(wi, wo, TransportMode::Radiance);
        if (!same_hemisphere(wo, wi)) {
            if (!a.is_zero() || !b.is_zero()) return 1;
            continue;
        }
        for (int i = 0; i < kSpectrumSamples; ++i) worst = std::max(worst, rel_diff(a[i], b[i]));
    }
    return worst;
}

/// Polar angles (degrees) of wo for the albedo sweeps: normal to grazing, and one from below.
inline std::vector<double> albedo_thetas() {
    return {0, 10, 20, 30, 40, 50, 60, 70, 80, 85, 89, 89.9, 120};
}

}  // namespace sr::testing
