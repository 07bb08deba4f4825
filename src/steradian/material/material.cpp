#include "steradian/material/material.h"

#include "steradian/sampling/hash.h"

namespace sr {

namespace {

Frame shading_frame(const SurfaceHit& h) {
    // The shape's own tangent where it has one (flat triangles: computed once per triangle),
    // else dpdu against the shading normal; an arbitrary tangent if that degenerates.
    Vec3 s = is_nonzero(h.ss) ? h.ss : shading_tangent(h.dpdu, h.ns);
    if (!is_nonzero(s)) return Frame::from_z(h.ns);
    return Frame(s, cross(h.ns, s), h.ns);
}

SampledSpectrum clamped(SampledSpectrum s) {
    for (int i = 0; i < kSpectrumSamples; ++i) s[i] = clamp(s[i], Float(0), Float(1));
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

/// Complex IOR (eta, k) of a conductor: from its normal-incidence reflectance texture if it has
/// one (reflectance >= 0: eta = 1 and r = k^2 / (4 + k^2), r capped at 0.9999), else its
/// eta and k spectra.
std::pair<SampledSpectrum, SampledSpectrum> conductor_ior(int reflectance, const Spectrum& eta,
                                                          const Spectrum& k,
                                                          const MaterialContext& ctx,
                                                          const SurfaceHit& h,
                                                          const SampledWavelengths& lambda) {
    if (reflectance < 0) return {eta.sample(lambda), k.sample(lambda)};
    SampledSpectrum r = clamped(evaluate((*ctx.spectrum_textures)[reflectance], h, lambda));
    SampledSpectrum kr;
    for (int i = 0; i < kSpectrumSamples; ++i) {
        Float ri = std::min(r[i], Float(0.9999));
        kr[i] = 2 * std::sqrt(ri) / std::sqrt(1 - ri);
    }
    return {SampledSpectrum(1), kr};
}

/// Diffuse and specular albedos of the Phong and Ward materials: each clamped to [0, 1] and
/// multiplied by the builder's energy scale; where their sum still exceeds 1 (a texture can
/// make it so), both are divided by the sum, per wavelength, so that kd + ks <= 1.
std::pair<SampledSpectrum, SampledSpectrum> bounded_pair(SampledSpectrum kd, SampledSpectrum ks,
                                                         Float scale) {
    kd = clamped(kd) * scale;
    ks = clamped(ks) * scale;
    for (int i = 0; i < kSpectrumSamples; ++i) {
        Float sum = kd[i] + ks[i];
        if (sum > 1) {
            kd[i] /= sum;
            ks[i] /= sum;
        }
    }
    return {kd, ks};
}

/// The coated materials' lobe: interface `top` over `bottom`, the slab from lp at h.
template <typename Bottom>
LayeredLobe<Bottom> layered_lobe(const DielectricLobe& top, const Bottom& bottom,
                                 const LayerParams& lp, const MaterialContext& ctx,
                                 const SurfaceHit& h, const SampledWavelengths& lambda) {
    const auto& ftex = *ctx.float_textures;
    LayeredLobe<Bottom> l;
    l.top = top;
    l.bottom = bottom;
    l.albedo = clamped(evaluate((*ctx.spectrum_textures)[lp.albedo], h, lambda));
    l.thickness = std::max(Float(0), evaluate(ftex[lp.thickness], h));
    // |g| = 1 is a delta phase function, which the walk's next-event terms cannot evaluate.
    l.g = clamp(evaluate(ftex[lp.g], h), Float(-0.999), Float(0.999));
    l.max_depth = lp.max_depth;
    l.n_samples = lp.n_samples;
    return l;
}

/// pbrt-v4's MixMaterial::ChooseMaterial: materials[1] with probability `amount`, decided by a
/// hash of (p, wo, the two material ids) rather than by a sampler dimension, so that the choice
/// is a pure function of the shading point and direction.
int mix_choice(const MixMaterial& m, const MaterialContext& ctx, const SurfaceHit& h) {
    Float amount = evaluate((*ctx.float_textures)[m.amount], h);
    if (amount <= 0) return m.materials[0];
    if (amount >= 1) return m.materials[1];
    uint64_t bits =
        hash(h.p.x, h.p.y, h.p.z, h.wo.x, h.wo.y, h.wo.z, m.materials[0], m.materials[1]);
    Float u = Float(bits >> 40) * 0x1p-24f;  // 24 uniform bits in [0, 1)
    return amount < u ? m.materials[0] : m.materials[1];
}

/// pbrt-v4's HairMaterial::GetBxDF: roughnesses clamped to [0.01, 1], sigma_a from the
/// first given of sigma_a, reflectance and the melanin concentrations (each clamped to >= 0).
HairLobe hair_lobe(const HairMaterial& m, const MaterialContext& ctx, const SurfaceHit& h,
                   const SampledWavelengths& lambda) {
    const auto& ftex = *ctx.float_textures;
    const Float beta_m = clamp(evaluate(ftex[m.beta_m], h), Float(0.01), Float(1));
    const Float beta_n = clamp(evaluate(ftex[m.beta_n], h), Float(0.01), Float(1));
    SampledSpectrum sigma_a;
    if (m.sigma_a >= 0) {
        sigma_a = evaluate((*ctx.spectrum_textures)[m.sigma_a], h, lambda);
        for (int i = 0; i < kSpectrumSamples; ++i) sigma_a[i] = std::max(Float(0), sigma_a[i]);
    } else if (m.reflectance >= 0) {
        sigma_a = HairLobe::sigma_a_from_reflectance(
            clamped(evaluate((*ctx.spectrum_textures)[m.reflectance], h, lambda)), beta_n);
    } else {
        auto conc = [&](int t) { return t >= 0 ? std::max(Float(0), evaluate(ftex[t], h)) : 0; };
        const auto rgb = HairLobe::sigma_a_from_concentration(conc(m.eumelanin), conc(m.pheomelanin));
        const RgbUnboundedSpectrum spec =
            rgb_unbounded_spectrum_interpolated(Rgb{rgb[0], rgb[1], rgb[2]});
        for (int i = 0; i < kSpectrumSamples; ++i) sigma_a[i] = spec(lambda[i]);
    }
    // An infinite absorption (a black reflectance) would meet a zero chord length at h = +-1.
    for (int i = 0; i < kSpectrumSamples; ++i)
        sigma_a[i] = std::isnan(sigma_a[i]) ? 0 : std::min(sigma_a[i], Float(1e30));
    return HairLobe(2 * h.uv.y - 1, evaluate(ftex[m.eta], h), sigma_a, beta_m, beta_n,
                    evaluate(ftex[m.alpha], h));
}

}  // namespace

void perturb_shading(const MaterialCommon& c, const MaterialContext& ctx, SurfaceHit& h) {
    Normal3 ns = h.ns;
    Vec3 dpdu = h.dpdu, dpdv = h.dpdv;
    if (c.displacement >= 0) {
        const FloatTexture& d = (*ctx.float_textures)[c.displacement];
        // The finite-difference steps: half the footprint's extent in u and v, or 0.0005
        // without a footprint (pbrt-v4's BumpMap).
        Float step_u = Float(0.5) * (std::abs(h.dudx) + std::abs(h.dudy));
        Float step_v = Float(0.5) * (std::abs(h.dvdx) + std::abs(h.dvdy));
        if (step_u == 0) step_u = Float(0.0005);
        if (step_v == 0) step_v = Float(0.0005);
        Float d0 = evaluate(d, h);
        SurfaceHit sh = h;
        sh.p = h.p + h.dpdu * step_u;
        sh.uv = Point2(h.uv.x + step_u, h.uv.y);
        Float du = evaluate(d, sh);
        sh.p = h.p + h.dpdv * step_v;
        sh.uv = Point2(h.uv.x, h.uv.y + step_v);
        Float dv = evaluate(d, sh);
        dpdu = h.dpdu + ns * ((du - d0) / step_u) + h.dndu * d0;
        dpdv = h.dpdv + ns * ((dv - d0) / step_v) + h.dndv * d0;
        Vec3 n = cross(dpdu, dpdv);
        if (!(length_squared(n) > 0)) return;
        n = normalize(n);
        ns = dot(n, h.ns) < 0 ? -n : n;
    } else if (c.normal_map) {
        Rgb v = c.normal_map->bilerp(h.uv);
        Vec3 nt(2 * v.r - 1, 2 * v.g - 1, 2 * v.b - 1);
        if (!(length_squared(nt) > 0)) return;
        Vec3 t = h.dpdu - h.ns * dot(h.ns, h.dpdu);
        Frame f = length_squared(t) > 0 ? Frame(normalize(t), cross(h.ns, normalize(t)), h.ns)
                                        : Frame::from_z(h.ns);
        ns = normalize(f.to_world(normalize(nt)));
    } else {
        return;
    }
    if (dot(ns, h.ng) < 0) ns = -ns;
    // Tangents that go with the new normal (pbrt-v4: Gram-Schmidt, lengths kept).
    Float ul = length(dpdu), vl = length(dpdv);
    Vec3 u = dpdu - ns * dot(ns, dpdu);
    if (length_squared(u) > 0) {
        u = normalize(u) * ul;
        h.dpdu = u;
        h.dpdv = normalize(cross(ns, u)) * vl;
    }
    h.ns = ns;
    h.ss = Vec3(0, 0, 0);  // the shape's tangent was for the unperturbed normal
}

namespace {

/// The BSDF of material m at the (possibly perturbed) hit h.
std::optional<Bsdf> bsdf_at(const Material& m, const MaterialContext& ctx, const SurfaceHit& h,
                            SampledWavelengths& lambda) {
    const auto& tex = *ctx.spectrum_textures;
    // One result, its lobe built in place (Bsdf's lobe constructor) and returned by name:
    // returning Bsdf temporaries copied the 112-byte lobe variant twice and the 160-byte
    // Bsdf once more on every vertex.
    std::optional<Bsdf> out;
    std::visit(
        [&](const auto& mat) {
            using T = std::decay_t<decltype(mat)>;
            if constexpr (std::is_same_v<T, InterfaceMaterial>) {
                return;
            } else if constexpr (std::is_same_v<T, DiffuseMaterial>) {
                SampledSpectrum r = clamped(evaluate(tex[mat.reflectance], h, lambda));
                out.emplace(shading_frame(h), h.ng, LambertLobe{r});
            } else if constexpr (std::is_same_v<T, DielectricMaterial>) {
                Float eta = hero_eta(mat.eta, mat.dispersive, lambda);
                out.emplace(shading_frame(h), h.ng,
                            DielectricLobe{eta, microfacets(mat.roughness, ctx, h)});
            } else if constexpr (std::is_same_v<T, ThinDielectricMaterial>) {
                Float eta = hero_eta(mat.eta, mat.dispersive, lambda);
                out.emplace(shading_frame(h), h.ng, ThinDielectricLobe{eta});
            } else if constexpr (std::is_same_v<T, ConductorMaterial>) {
                auto [eta, k] = conductor_ior(mat.reflectance, mat.eta, mat.k, ctx, h, lambda);
                out.emplace(shading_frame(h), h.ng,
                            ConductorLobe{eta, k, microfacets(mat.roughness, ctx, h)});
            } else if constexpr (std::is_same_v<T, PhongMaterial>) {
                auto [kd, ks] = bounded_pair(evaluate(tex[mat.kd], h, lambda),
                                             evaluate(tex[mat.ks], h, lambda), mat.energy_scale);
                Float n = std::max(Float(0), evaluate((*ctx.float_textures)[mat.exponent], h));
                out.emplace(shading_frame(h), h.ng, PhongLobe{kd, ks, n, mat.absorb});
            } else if constexpr (std::is_same_v<T, LafortuneMaterial>) {
                LafortuneLobe l;
                l.rho_d = clamped(evaluate(tex[mat.diffuse], h, lambda));
                l.lobes = mat.lobes;
                l.count = mat.count;
                out.emplace(shading_frame(h), h.ng, l);
            } else if constexpr (std::is_same_v<T, WardMaterial>) {
                auto [kd, ks] = bounded_pair(evaluate(tex[mat.kd], h, lambda),
                                             evaluate(tex[mat.ks], h, lambda), mat.energy_scale);
                const auto& ftex = *ctx.float_textures;
                Float ax = std::max(WardMaterial::kMinAlpha, evaluate(ftex[mat.alpha_x], h));
                Float ay = std::max(WardMaterial::kMinAlpha, evaluate(ftex[mat.alpha_y], h));
                out.emplace(shading_frame(h), h.ng, WardLobe{kd, ks, ax, ay});
            } else if constexpr (std::is_same_v<T, CoatedDiffuseMaterial>) {
                Float eta = hero_eta(mat.eta, mat.dispersive, lambda);
                DielectricLobe top{eta, microfacets(mat.roughness, ctx, h)};
                LambertLobe base{clamped(evaluate(tex[mat.reflectance], h, lambda))};
                out.emplace(shading_frame(h), h.ng,
                            layered_lobe(top, base, mat.layer, ctx, h, lambda));
            } else if constexpr (std::is_same_v<T, CoatedConductorMaterial>) {
                Float eta = hero_eta(mat.interface_eta, mat.dispersive, lambda);
                DielectricLobe top{eta, microfacets(mat.interface_roughness, ctx, h)};
                auto [ce, ck] = conductor_ior(mat.reflectance, mat.conductor_eta, mat.conductor_k,
                                              ctx, h, lambda);
                // The base sits under the coating: its IOR relative to the coating's.
                ConductorLobe base{ce / eta, ck / eta, microfacets(mat.conductor_roughness, ctx, h)};
                out.emplace(shading_frame(h), h.ng,
                            layered_lobe(top, base, mat.layer, ctx, h, lambda));
            } else if constexpr (std::is_same_v<T, HairMaterial>) {
                out.emplace(shading_frame(h), h.ng, hair_lobe(mat, ctx, h, lambda));
            } else if constexpr (std::is_same_v<T, MeasuredMaterial>) {
                out.emplace(shading_frame(h), h.ng, MeasuredLobe{mat.brdf.get(), lambda});
            } else if constexpr (std::is_same_v<T, MixMaterial>) {
                out = make_bsdf((*ctx.materials)[mix_choice(mat, ctx, h)], ctx, h, lambda);
            } else if constexpr (std::is_same_v<T, SubsurfaceMaterial>) {
                // pbrt-v4's SubsurfaceMaterial::GetBxDF: the boundary is a dielectric; what
                // it transmits inside, the integrator's random walk carries (volpath.cpp).
                out.emplace(shading_frame(h), h.ng,
                            DielectricLobe{mat.eta, microfacets(mat.roughness, ctx, h)});
            } else {
                static_assert(std::is_same_v<T, DiffuseTransmissionMaterial>);
                SampledSpectrum r = clamped(evaluate(tex[mat.reflectance], h, lambda) * mat.scale);
                SampledSpectrum t = clamped(evaluate(tex[mat.transmittance], h, lambda) * mat.scale);
                out.emplace(shading_frame(h), h.ng, DiffuseTransmissionLobe{r, t});
            }
        },
        m);
    return out;
}

}  // namespace

const SubsurfaceMaterial* subsurface_at(const Material& m, const MaterialContext& ctx,
                                        const SurfaceHit& h) {
    const Material* cur = &m;
    // A mix of mixes resolves in a few steps (the builder rejects cycles).
    while (const auto* mix = std::get_if<MixMaterial>(cur))
        cur = &(*ctx.materials)[mix_choice(*mix, ctx, h)];
    return std::get_if<SubsurfaceMaterial>(cur);
}

std::optional<Bsdf> make_bsdf(const Material& m, const MaterialContext& ctx, const SurfaceHit& h,
                              SampledWavelengths& lambda) {
    const MaterialCommon& common =
        std::visit([](const auto& x) -> const MaterialCommon& { return x; }, m);
    // Only a perturbed hit is copied, in its own branch: a std::optional<SurfaceHit> for it
    // was zero-filled (140 bytes) on every call.
    if (common.normal_map || common.displacement >= 0) [[unlikely]] {
        SurfaceHit perturbed = h;
        perturb_shading(common, ctx, perturbed);
        return bsdf_at(m, ctx, perturbed, lambda);
    }
    return bsdf_at(m, ctx, h, lambda);
}

}  // namespace sr
