#pragma once
/// Checks shared by the BSDF lobe tests: the chi-square test of a lobe's sample() against its
/// pdf(), consistency of sample() with f() and pdf(), and the directional albedo.
#include <algorithm>
#include <cmath>
#include <optional>
#include <string>

#include "stat/chi2.h"
#include "steradian/bsdf/bsdf.h"
#include "steradian/sampling/rng.h"

namespace sr::testing {

/// Unit direction at polar angle theta_deg from +z (negative cos for theta > 90) and azimuth
/// phi (radians).
inline Vec3 direction_deg(double theta_deg, double phi = 0.3) {
    double t = theta_deg * 3.141592653589793 / 180;
    return Vec3(Float(std::sin(t) * std::cos(phi)), Float(std::sin(t) * std::sin(phi)),
                Float(std::cos(t)));
}

/// Chi-square test of lobe.sample(wo, ...) against lobe.pdf(wo, ., mode).
template <typename L>
SphereChi2Outcome lobe_chi2(const L& lobe, Vec3 wo, TransportMode mode,
                            const SphereChi2Config& cfg = {}) {
    return sphere_chi2(
        [&](Pcg32& rng) -> std::optional<Vec3> {
            Float uc = rng.next_float();
            Point2 u{rng.next_float(), rng.next_float()};
            std::optional<BsdfSample> s = lobe.sample(wo, uc, u, mode);
            if (!s || s->pdf_sa == 0) return std::nullopt;
            return s->wi;
        },
        [&](Vec3 wi) { return lobe.pdf(wo, wi, mode); }, cfg);
}

/// Largest relative differences between what sample() returns and what f() and pdf() give at
/// the returned wi (non-specular lobes), over n calls of sample().
struct ConsistencyResult {
    double max_rel_f = 0;
    double max_rel_pdf = 0;
    int samples = 0;
    std::string worst;  ///< description of the worst case
};

inline double rel_diff(double a, double b) {
    double m = std::max(std::abs(a), std::abs(b));
    return m == 0 ? 0 : std::abs(a - b) / m;
}

/// |a - b| <= rel max(|a|, |b|) + abs: a relative comparison with a floor for values that are
/// tiny compared with the function's scale, where float rounding of ill-conditioned inputs
/// (grazing microfacet cosines) dominates.
inline bool near_rel(double a, double b, double rel, double abs) {
    return std::abs(a - b) <= rel * std::max(std::abs(a), std::abs(b)) + abs;
}

template <typename L>
ConsistencyResult check_sample_consistency(const L& lobe, Vec3 wo, TransportMode mode, int n,
                                           uint64_t seed = 3) {
    ConsistencyResult res;
    Pcg32 rng(seed);
    for (int k = 0; k < n; ++k) {
        Float uc = rng.next_float();
        Point2 u{rng.next_float(), rng.next_float()};
        std::optional<BsdfSample> s = lobe.sample(wo, uc, u, mode);
        if (!s || s->pdf_sa == 0) continue;
        ++res.samples;
        SampledSpectrum f = lobe.f(wo, s->wi, mode);
        Float pdf = lobe.pdf(wo, s->wi, mode);
        double dp = rel_diff(s->pdf_sa, pdf);
        double df = 0;
        for (int i = 0; i < kSpectrumSamples; ++i) df = std::max(df, rel_diff(s->f[i], f[i]));
        if (dp > res.max_rel_pdf || df > res.max_rel_f) {
            char buf[256];
            std::snprintf(buf, sizeof buf,
                          "wi = (%.6g, %.6g, %.6g): sample f %.6g pdf %.6g, f() %.6g pdf() %.6g",
                          s->wi.x, s->wi.y, s->wi.z, s->f[0], s->pdf_sa, f[0], pdf);
            res.worst = buf;
        }
        res.max_rel_pdf = std::max(res.max_rel_pdf, dp);
        res.max_rel_f = std::max(res.max_rel_f, df);
    }
    return res;
}

/// Monte Carlo estimate of the directional albedo integral of f(wo, wi) |cos wi| dwi per
/// wavelength from sample() weights (failed samples count as 0), with its standard error.
/// In Radiance mode refraction weights are multiplied by sample.eta^2, undoing the radiance
/// scaling 1/etap^2, so that the result is the energy albedo in both modes.
struct Albedo {
    SampledSpectrum mean, std_error;
};
template <typename L>
Albedo directional_albedo(const L& lobe, Vec3 wo, TransportMode mode, int n, uint64_t seed = 5) {
    double sum[kSpectrumSamples] = {}, sum2[kSpectrumSamples] = {};
    Pcg32 rng(seed);
    for (int k = 0; k < n; ++k) {
        Float uc = rng.next_float();
        Point2 u{rng.next_float(), rng.next_float()};
        std::optional<BsdfSample> s = lobe.sample(wo, uc, u, mode);
        if (!s || s->pdf_sa == 0) continue;
        double scale = std::abs(s->wi.z) / s->pdf_sa;
        if (mode == TransportMode::Radiance && s->is_transmission()) scale *= sqr(s->eta);
        for (int i = 0; i < kSpectrumSamples; ++i) {
            double w = s->f[i] * scale;
            sum[i] += w;
            sum2[i] += w * w;
        }
    }
    Albedo a;
    for (int i = 0; i < kSpectrumSamples; ++i) {
        double m = sum[i] / n;
        double var = std::max(sum2[i] / n - m * m, 0.0);
        a.mean[i] = Float(m);
        a.std_error[i] = Float(std::sqrt(var / n));
    }
    return a;
}

}  // namespace sr::testing
