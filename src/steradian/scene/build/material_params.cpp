/// Material parameters: roughness, indices of refraction, reflectances, lobes and layers.
#include "steradian/bsdf/normalized_fresnel.h"
#include "steradian/media/medium.h"
#include "steradian/scene/build/builder.h"

namespace sr::build_detail {

/// "roughness", or "uroughness"/"vroughness" (pbrt-v4: each defaults to roughness), and
/// "remaproughness".
Roughness Builder::roughness_params(const ParamSet& ps) {
    Roughness r;
    bool has_u = ps.find("uroughness") != nullptr, has_v = ps.find("vroughness") != nullptr;
    int both = (!has_u || !has_v) ? float_texture_param(ps, "roughness", 0) : -1;
    r.u = has_u ? float_texture_param(ps, "uroughness", 0) : both;
    r.v = has_v ? float_texture_param(ps, "vroughness", 0) : both;
    r.remap = ps.get_bool("remaproughness", true);
    return r;
}

/// An index of refraction: "float eta" or "spectrum eta" (named glasses disperse).
std::pair<Spectrum, bool> Builder::eta_param(const ParamSet& ps, Float def) {
    if (const Param* p = ps.find("eta")) {
        if (p->type == ParamType::Float) return {ConstantSpectrum{ps.get_float("eta", def)}, false};
        Spectrum s =
            spectrum_from_param(*ps.find_spectrum("eta"), SpectrumKind::Unbounded, m_d.base_dir);
        if (const auto* c = s.get_if<ConstantSpectrum>()) return {*c, false};
        return {densely_sampled(s), true};
    }
    return {ConstantSpectrum{def}, false};
}

Spectrum Builder::unbounded_param(const ParamSet& ps, std::string_view name,
                                  const char* def_named) {
    if (const Param* p = ps.find_spectrum(name))
        return densely_sampled(spectrum_from_param(*p, SpectrumKind::Unbounded, m_d.base_dir));
    return *named_spectrum(def_named);
}

// ---- parameters of steradian's extension materials (phong, lafortune, ward) ---------
/// A reflectance parameter that may also be a plain "float" (a grey constant in [0, 1]);
/// otherwise as spectrum_texture_param.
int Builder::albedo_param(const ParamSet& ps, std::string_view name, Float def) {
    const Param* p = ps.find(name);
    if (!p || p->type != ParamType::Float) return spectrum_texture_param(ps, name, def);
    Float v = ps.get_float(name, def);
    if (!(v >= 0 && v <= 1))
        throw_error(p->loc, "\"float {}\" is a reflectance and must be in [0, 1], got {}", name, v);
    m_s.spectrum_textures.push_back(ConstantSpectrumTexture{ConstantSpectrum{v}});
    return int(m_s.spectrum_textures.size()) - 1;
}

/// max over the tabulated wavelengths of clamp(a) + clamp(b) (clamped to [0, 1] as the
/// materials do) when both spectrum textures are constant; empty otherwise.
std::optional<Float> Builder::constant_albedo_sum(int a, int b) const {
    const auto* ca = std::get_if<ConstantSpectrumTexture>(&m_s.spectrum_textures[a]);
    const auto* cb = std::get_if<ConstantSpectrumTexture>(&m_s.spectrum_textures[b]);
    if (!ca || !cb) return std::nullopt;
    Float mx = 0;
    for (int l = int(kLambdaMin); l <= int(kLambdaMax); ++l) {
        Float sum = clamp(ca->value(Float(l)), Float(0), Float(1)) +
                    clamp(cb->value(Float(l)), Float(0), Float(1));
        mx = std::max(mx, sum);
    }
    return mx;
}

/// The factor that makes Kd + Ks <= 1 at every wavelength when both are constant, with a
/// located warning when it is below 1. Textured inputs are normalised per lookup instead.
Float Builder::energy_scale(int kd, int ks, const SourceLoc& loc, const std::string& what) {
    std::optional<Float> sum = constant_albedo_sum(kd, ks);
    if (!sum || *sum <= 1) return 1;
    warning(loc, fmt::format("{}: Kd + Ks reaches {:.4g} > 1, which would create energy; both "
                             "are scaled by {:.4g}",
                             what, *sum, 1 / *sum));
    return 1 / *sum;
}

/// A float-texture parameter whose constant value must be >= 0 (or > 0 if `positive`);
/// a violation is an error at the parameter.
int Builder::bounded_float_param(const ParamSet& ps, std::string_view name, Float def,
                                 bool positive) {
    int idx = float_texture_param(ps, name, def);
    if (const auto* c = std::get_if<ConstantFloatTexture>(&m_s.float_textures[idx])) {
        if (positive ? !(c->value > 0) : !(c->value >= 0)) {
            const Param* p = ps.find(name);
            throw_error(p ? p->loc : SourceLoc{}, "\"{}\" must be {}, got {}", name,
                        positive ? "positive" : "non-negative", c->value);
        }
    }
    return idx;
}

/// "lafortune": "diffuse" (reflectance), and per lobe one value each of "Cx", "Cy", "Cz",
/// "n" and optionally "rhos" (default 1). Warns when the albedo can exceed 1.
LafortuneMaterial Builder::lafortune_params(const ParamSet& ps, const SourceLoc& loc,
                                            const std::string& what) {
    LafortuneMaterial l;
    l.diffuse = albedo_param(ps, "diffuse", 0.5f);
    const char* names[5] = {"Cx", "Cy", "Cz", "n", "rhos"};
    std::vector<Float> v[5];
    const Param* given = nullptr;  // a lobe parameter that is present, for locations
    for (int k = 0; k < 5; ++k) {
        v[k] = ps.get_floats(names[k]);
        if (!given) given = ps.find(names[k]);
    }
    size_t count = std::max({v[0].size(), v[1].size(), v[2].size(), v[3].size()});
    for (int k = 0; k < 5; ++k) {
        if (v[k].size() == count || (k == 4 && v[k].empty())) continue;
        const Param* p = ps.find(names[k]);
        throw_error(p ? p->loc : given->loc,
                    "{}: \"Cx\", \"Cy\", \"Cz\", \"n\" (and \"rhos\" if given) need one "
                    "value per lobe: {} lobes, but \"{}\" has {} values",
                    what, count, names[k], v[k].size());
    }
    if (count > size_t(LafortuneLobe::kMaxLobes))
        throw_error(given->loc, "{}: at most {} lobes, got {}", what, LafortuneLobe::kMaxLobes,
                    count);
    l.count = int(count);
    for (size_t i = 0; i < count; ++i) {
        LafortuneCosine c{v[0][i], v[1][i], v[2][i], v[3][i], v[4].empty() ? 1 : v[4][i]};
        Float cmax = std::max({std::abs(c.cx), std::abs(c.cy), std::abs(c.cz)});
        bool finite = std::isfinite(cmax) && std::isfinite(c.n) && std::isfinite(c.rho);
        if (!finite || c.n < 0 || c.rho < 0)
            throw_error(ps.find(c.rho < 0 ? "rhos" : "n")->loc,
                        "{}: lobe {}: \"n\" and \"rhos\" must be finite and >= 0, C finite", what,
                        i + 1);
        // The lobe's peak rhos (Cmax cos)^n must stay far inside float range.
        if (double(c.rho) * std::pow(double(cmax), double(c.n)) > 1e30)
            throw_error(ps.find("n")->loc, "{}: lobe {}: rhos * max|C|^n = {:.3g} overflows", what,
                        i + 1, double(c.rho) * std::pow(double(cmax), double(c.n)));
        l.lobes[i] = c;
    }
    // Energy: the model can reflect more than it receives. Unless the sufficient condition
    // of lafortune.h holds, estimate the largest albedo.
    Float rho_d = 0, bound = 0;
    const SpectrumTexture& diffuse = m_s.spectrum_textures[l.diffuse];
    if (const auto* cd = std::get_if<ConstantSpectrumTexture>(&diffuse))
        rho_d = std::min(Float(1), cd->value.max_value());
    for (size_t i = 0; i < count; ++i) {
        const LafortuneCosine& c = l.lobes[i];
        Float cmax = std::max({std::abs(c.cx), std::abs(c.cy), std::abs(c.cz)});
        bound += c.rho * std::pow(cmax, c.n) * 2 * kPi / (c.n + 1);
    }
    if (rho_d + bound > 1) {
        LafortuneLobe lobe;
        lobe.rho_d = SampledSpectrum(rho_d);
        lobe.lobes = l.lobes;
        lobe.count = l.count;
        LafortuneAlbedo a = lafortune_max_albedo(lobe, 2048);
        if (a.albedo - 3 * a.std_error > 1)
            warning(loc, fmt::format("{}: not energy conserving: the directional albedo "
                                     "reaches about {:.3g} at {} degrees incidence",
                                     what, a.albedo, a.theta_deg));
    }
    return l;
}

// ---- parameters of the coated materials (coateddiffuse, coatedconductor) ---------
/// "<prefix>roughness", or "<prefix>uroughness"/"<prefix>vroughness" (each defaulting to
/// the former), and the unprefixed "remaproughness" (one per material, as in pbrt-v4).
Roughness Builder::prefixed_roughness_params(const ParamSet& ps, const std::string& prefix) {
    const std::string u = prefix + "uroughness", v = prefix + "vroughness";
    Roughness r;
    bool has_u = ps.find(u) != nullptr, has_v = ps.find(v) != nullptr;
    int both = (!has_u || !has_v) ? float_texture_param(ps, prefix + "roughness", 0) : -1;
    r.u = has_u ? float_texture_param(ps, u, 0) : both;
    r.v = has_v ? float_texture_param(ps, v, 0) : both;
    r.remap = ps.get_bool("remaproughness", true);
    return r;
}

/// An index of refraction called `name`: a float, or a spectrum (a tabulated one
/// disperses), as eta_param.
std::pair<Spectrum, bool> Builder::named_eta_param(const ParamSet& ps, const std::string& name,
                                                   Float def) {
    const Param* p = ps.find(name);
    if (!p) return {ConstantSpectrum{def}, false};
    if (p->type == ParamType::Float) return {ConstantSpectrum{ps.get_float(name, def)}, false};
    Spectrum s =
        spectrum_from_param(*ps.find_spectrum(name), SpectrumKind::Unbounded, m_d.base_dir);
    if (const auto* c = s.get_if<ConstantSpectrum>()) return {*c, false};
    return {densely_sampled(s), true};
}

/// The slab between coating and base and the random-walk settings: "thickness" (0.01),
/// "albedo" (0), "g" (0), "maxdepth" (10), "nsamples" (1), pbrt-v4's defaults.
LayerParams Builder::layer_params(const ParamSet& ps, const std::string& what) {
    LayerParams l;
    l.thickness = float_texture_param(ps, "thickness", 0.01f);
    l.albedo = spectrum_texture_param(ps, "albedo", 0);
    l.g = float_texture_param(ps, "g", 0);
    auto count = [&](const char* name, int def, int lo) {
        int v = ps.get_int(name, def);
        if (v < lo || v > 65535) {
            const Param* p = ps.find(name);
            throw_error(p ? p->loc : SourceLoc{}, "{}: \"{}\" must be in [{}, 65535], got {}", what,
                        name, lo, v);
        }
        return uint16_t(v);
    };
    l.max_depth = count("maxdepth", 10, 0);
    l.n_samples = count("nsamples", 1, 1);
    return l;
}

// ---- subsurface --------------------------------------------------------------------
/// pbrt-v4's SubsurfaceMaterial::Create. The interior from the first of: "name" (a measured
/// medium of pbrt-v4's table, sigma_s' and sigma_a per mm as sRGB; "g" is then 0, with a
/// warning if given, since the table holds reduced scattering coefficients), "sigma_a" with
/// "sigma_s" (unbounded spectrum textures; one without the other is an error), "reflectance"
/// (a spectrum texture) with "mfp" (unbounded, default 1), else pbrt-v4's defaults sigma_a =
/// RGB(.0011, .0024, .014), sigma_s = RGB(2.55, 3.21, 3.77) (whole milk). "scale" (1), "eta"
/// (1.33, a float as in pbrt-v4), "g" (0); the boundary's roughness as the dielectric's.
SubsurfaceMaterial Builder::subsurface_params(const ParamSet& ps, const std::string& what) {
    SubsurfaceMaterial s;
    auto constant = [&](Rgb c) {
        m_s.spectrum_textures.push_back(ConstantSpectrumTexture{rgb_unbounded_spectrum(c)});
        return int(m_s.spectrum_textures.size()) - 1;
    };
    auto check = [&](const char* name, bool ok, const char* must) {
        if (const Param* p = ps.find(name); p && !ok)
            throw_error(p->loc, "{}: \"{}\" must be {}", what, name, must);
    };
    s.g = ps.get_float("g", 0);
    check("g", std::abs(s.g) < 1, "in (-1, 1)");
    const std::string name = ps.get_string("name", "");
    const Param* sigma_a = ps.find("sigma_a");
    const Param* sigma_s = ps.find("sigma_s");
    if (!name.empty()) {
        Rgb sig_s, sig_a;
        if (!measured_medium(name, sig_s, sig_a))
            throw_error(ps.find("name")->loc,
                        "{}: no measured medium is called \"{}\" (the names are pbrt-v4's, "
                        "e.g. \"Skin1\", \"Wholemilk\", \"Ketchup\")",
                        what, name);
        if (s.g != 0)
            warning(ps.find("g")->loc,
                    fmt::format("{}: \"g\" is ignored with the named medium \"{}\" (its "
                                "coefficients are reduced ones, for g = 0), as pbrt-v4 does",
                                what, name));
        s.g = 0;
        s.sigma_a = constant(sig_a);
        s.sigma_s = constant(sig_s);
    } else if (sigma_a || sigma_s) {
        if (!sigma_s)
            throw_error(sigma_a->loc,
                        "{}: \"sigma_a\" is given without \"sigma_s\" (give both "
                        "or neither)",
                        what);
        if (!sigma_a)
            throw_error(sigma_s->loc,
                        "{}: \"sigma_s\" is given without \"sigma_a\" (give both "
                        "or neither)",
                        what);
        s.sigma_a = spectrum_texture_param(ps, "sigma_a", 0, SpectrumKind::Unbounded);
        s.sigma_s = spectrum_texture_param(ps, "sigma_s", 0, SpectrumKind::Unbounded);
    } else if (ps.find("reflectance")) {
        s.reflectance = spectrum_texture_param(ps, "reflectance", 0.5f);
        s.mfp = spectrum_texture_param(ps, "mfp", 1, SpectrumKind::Unbounded);
        if (const auto* c = std::get_if<ConstantSpectrumTexture>(&m_s.spectrum_textures[s.mfp])) {
            bool positive = true;
            for (int l = int(kLambdaMin); l <= int(kLambdaMax); ++l)
                positive = positive && c->value(Float(l)) > 0;
            check("mfp", positive, "positive");
        }
    } else {
        s.sigma_a = constant(Rgb{.0011f, .0024f, .014f});
        s.sigma_s = constant(Rgb{2.55f, 3.21f, 3.77f});
    }
    s.scale = ps.get_float("scale", 1);
    check("scale", s.scale >= 0 && std::isfinite(s.scale), "finite and >= 0");
    s.eta = ps.get_float("eta", 1.33f);
    check("eta", s.eta > 0 && std::isfinite(s.eta), "finite and positive");
    s.exit_c = normalized_fresnel_c(s.eta);
    s.internal_r = diffuse_internal_reflectance(s.eta);
    s.roughness = roughness_params(ps);
    return s;
}

}  // namespace sr::build_detail
