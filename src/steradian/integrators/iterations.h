#pragma once
/// Pieces shared by the integrators that render in whole iterations, each with one set of
/// wavelengths for all its paths ("sppm", "vcm").
#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>

#include "steradian/core/math.h"
#include "steradian/integrators/integrator.h"
#include "steradian/sampling/hash.h"

namespace sr {

/// The wavelength sample of iteration i: the base-3 radical inverse of i (the van der Corput
/// sequence in base 3), as pbrt-v4's sppm takes it, so the iterations' wavelengths are
/// stratified; rotated (Cranley-Patterson) by an offset hashed from the seed and the
/// integrator's `salt`, so that renders with other seeds are independent estimates (pbrt-v4
/// does not rotate it).
inline Float pass_wavelength_sample(uint64_t i, uint64_t seed, uint64_t salt) {
    double inv = 1.0 / 3, f = inv, r = 0;
    while (i > 0) {
        r += double(i % 3) * f;
        i /= 3;
        f *= inv;
    }
    r += double(mix_bits(seed ^ salt) >> 11) * 0x1.0p-53;
    r -= std::floor(r);
    return Float(std::min(r, 1 - 1e-7));
}

inline bool finite3(const std::array<double, 3>& v) {
    return std::isfinite(v[0]) && std::isfinite(v[1]) && std::isfinite(v[2]);
}

/// After `done` of `iterations` iterations, the last of which took `iter_seconds`, `elapsed`
/// seconds into the render: whether to stop (RenderOptions::stop, or a time budget the next
/// whole iteration would not fit in; the first iteration always completes). Sets
/// stats.interrupted or stats.time_limited when it stops early.
inline bool stop_before_next_iteration(const RenderOptions& opt, int done, int iterations,
                                       double elapsed, double iter_seconds, RenderStats& stats) {
    if (done >= iterations) return false;
    if (opt.stop && opt.stop->load()) {
        stats.interrupted = true;
        return true;
    }
    if (opt.time_budget > 0 && elapsed + iter_seconds > opt.time_budget) {
        stats.time_limited = true;
        return true;
    }
    return false;
}

}  // namespace sr
