#include "steradian/material/material.h"

namespace sr {

namespace {

Frame shading_frame(const SurfaceHit& h) {
    // Gram-Schmidt dpdu against the shading normal; fall back to an arbitrary tangent.
    Vec3 s = h.dpdu - h.ns * dot(h.ns, h.dpdu);
    Float l2 = length_squared(s);
    if (!(l2 > 1e-20f)) return Frame::from_z(h.ns);
    s = s / std::sqrt(l2);
    return Frame(s, cross(h.ns, s), h.ns);
}

SampledSpectrum clamped(SampledSpectrum s) {
    for (auto& v : s.v) v = clamp(v, Float(0), Float(1));
    return s;
}

TrowbridgeReitz microfacets(const Roughness& r, const MaterialContext& ctx, const SurfaceHit& h) {
    Float u = r.u >= 0 ? evaluate((*ctx.float_textures)[r.u], h) : 0;
    Float v = r.v >= 0 ? evaluate((*ctx.float_textures)[r.v], h) : u;
    if (r.remap) {
        u = TrowbridgeReitz::roughness_to_alpha(std::max(Float(0), u));
        v = TrowbridgeReitz::roughness_to_alpha(std::max(Float(0), v));
    }
    return TrowbridgeReitz{std::max(Float(0), u), std::max(Float(0), v)};
}

/// eta at the hero wavelength; a dispersive eta keeps only the hero (see dielectric.h).
Float hero_eta(const Spectrum& eta, bool dispersive, SampledWavelengths& lambda) {
    Float e = eta(lambda[0]);
    if (dispersive) lambda.terminate_secondary();
    return e > 0 ? e : 1;  // a tabulated spectrum is 0 outside its range
}

}  // namespace

std::optional<Bsdf> make_bsdf(const Material& m, const MaterialContext& ctx, const SurfaceHit& h,
                              SampledWavelengths& lambda) {
    const auto& tex = *ctx.spectrum_textures;
    return std::visit(
        [&](const auto& mat) -> std::optional<Bsdf> {
            using T = std::decay_t<decltype(mat)>;
            if constexpr (std::is_same_v<T, InterfaceMaterial>) {
                return std::nullopt;
            } else if constexpr (std::is_same_v<T, DiffuseMaterial>) {
                SampledSpectrum r = clamped(evaluate(tex[mat.reflectance], h, lambda));
                return Bsdf(shading_frame(h), h.ng, LambertLobe{r});
            } else if constexpr (std::is_same_v<T, DielectricMaterial>) {
                Float eta = hero_eta(mat.eta, mat.dispersive, lambda);
                return Bsdf(shading_frame(h), h.ng,
                            DielectricLobe{eta, microfacets(mat.roughness, ctx, h)});
            } else if constexpr (std::is_same_v<T, ThinDielectricMaterial>) {
                Float eta = hero_eta(mat.eta, mat.dispersive, lambda);
                return Bsdf(shading_frame(h), h.ng, ThinDielectricLobe{eta});
            } else if constexpr (std::is_same_v<T, ConductorMaterial>) {
                SampledSpectrum eta, k;
                if (mat.reflectance >= 0) {
                    // Normal-incidence reflectance r with eta = 1: r = k^2 / (4 + k^2).
                    SampledSpectrum r = clamped(evaluate(tex[mat.reflectance], h, lambda));
                    eta = SampledSpectrum(1);
                    for (int i = 0; i < kSpectrumSamples; ++i) {
                        Float ri = std::min(r[i], Float(0.9999));
                        k[i] = 2 * std::sqrt(ri) / std::sqrt(1 - ri);
                    }
                } else {
                    eta = mat.eta.sample(lambda);
                    k = mat.k.sample(lambda);
                }
                return Bsdf(shading_frame(h), h.ng,
                            ConductorLobe{eta, k, microfacets(mat.roughness, ctx, h)});
            } else {
                SampledSpectrum r = clamped(evaluate(tex[mat.reflectance], h, lambda) * mat.scale);
                SampledSpectrum t = clamped(evaluate(tex[mat.transmittance], h, lambda) * mat.scale);
                return Bsdf(shading_frame(h), h.ng, DiffuseTransmissionLobe{r, t});
            }
        },
        m);
}

}  // namespace sr
