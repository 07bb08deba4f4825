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

}  // namespace

std::optional<Bsdf> make_bsdf(const Material& m, const MaterialContext& ctx, const SurfaceHit& h,
                              const SampledWavelengths& lambda) {
    return std::visit(
        [&](const auto& mat) -> std::optional<Bsdf> {
            using T = std::decay_t<decltype(mat)>;
            if constexpr (std::is_same_v<T, InterfaceMaterial>) {
                return std::nullopt;
            } else {
                SampledSpectrum r = evaluate((*ctx.spectrum_textures)[mat.reflectance], h, lambda);
                for (auto& v : r.v) v = clamp(v, Float(0), Float(1));
                return Bsdf(shading_frame(h), h.ng, LambertLobe{r});
            }
        },
        m);
}

}  // namespace sr
