#include "steradian/material/subsurface.h"

namespace sr {

Float subsurface_albedo(Float reflectance, Float internal_r) {
    double a = reflectance;
    if (internal_r > 0 && a > 0 && a < 1) a = a / (1 - internal_r + internal_r * a);
    if (!(a > 0)) return 0;
    if (a >= 1) return 1;
    const double r = 4.09712 + 4.20863 * a - std::sqrt(9.59217 + 41.6808 * a + 17.7126 * a * a);
    return Float(std::clamp(1 - r * r, 0.0, 1.0));
}

SubsurfaceCoefficients subsurface_coefficients(const SubsurfaceMaterial& m,
                                               const MaterialContext& ctx, const SurfaceHit& h,
                                               const SampledWavelengths& lambda) {
    const auto& tex = *ctx.spectrum_textures;
    SubsurfaceCoefficients c;
    if (m.sigma_a >= 0) {
        c.sigma_a = evaluate(tex[m.sigma_a], h, lambda) * m.scale;
        c.sigma_s = evaluate(tex[m.sigma_s], h, lambda) * m.scale;
        // Clamped to >= 0 as pbrt-v4 does (a NaN, too, becomes 0) and below 1e30.
        for (int i = 0; i < kSpectrumSamples; ++i) {
            c.sigma_a[i] = c.sigma_a[i] > 0 ? std::min(c.sigma_a[i], Float(1e30)) : 0;
            c.sigma_s[i] = c.sigma_s[i] > 0 ? std::min(c.sigma_s[i], Float(1e30)) : 0;
        }
        return c;
    }
    const SampledSpectrum r = evaluate(tex[m.reflectance], h, lambda);
    const SampledSpectrum mfp = evaluate(tex[m.mfp], h, lambda) * m.scale;
    for (int i = 0; i < kSpectrumSamples; ++i) {
        const Float alpha = subsurface_albedo(clamp(r[i], Float(0), Float(1)), m.internal_r);
        const Float sigma_t = 1 / (mfp[i] > Float(1e-30) ? mfp[i] : Float(1e-30));
        c.sigma_s[i] = alpha * sigma_t;
        c.sigma_a[i] = (1 - alpha) * sigma_t;
    }
    return c;
}

}  // namespace sr
