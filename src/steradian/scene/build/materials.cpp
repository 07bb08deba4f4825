/// Materials: every reflection model from its parameters, "mix" and material references.
#include <tuple>

#include "steradian/film/image_io.h"
#include "steradian/scene/build/builder.h"

namespace sr::build_detail {

/// Maps the description indices that make_material stored in "mix" materials to scene
/// material indices, and rejects a mix that contains itself (it would never resolve).
void Builder::resolve_mixes() {
    for (size_t i = 0; i < m_d.materials.size(); ++i)
        if (auto* mix = std::get_if<MixMaterial>(&m_s.materials[m_material_index[i]]))
            for (int& k : mix->materials) k = m_material_index[k];
    // Depth-first search over the mix graph: 1 = on the current path, 2 = done.
    std::vector<uint8_t> state(m_s.materials.size(), 0);
    auto visit = [&](auto&& self, int mi) -> bool {
        if (state[mi] == 1) return false;
        if (state[mi] == 2) return true;
        state[mi] = 1;
        if (const auto* mix = std::get_if<MixMaterial>(&m_s.materials[mi]))
            for (int k : mix->materials)
                if (!self(self, k)) return false;
        state[mi] = 2;
        return true;
    };
    for (size_t i = 0; i < m_d.materials.size(); ++i)
        if (!visit(visit, m_material_index[i]))
            throw_error(m_d.materials[i].loc, "material \"{}\": a \"mix\" material contains itself",
                        m_d.materials[i].name);
}

/// A material with pbrt-v4's shading-normal parameters ("normalmap", "displacement")
/// read for every reflection model (interface and mix have none, as in pbrt-v4).
Material Builder::make_material(const MaterialDesc& m) {
    const ParamSet& ps = m.params;
    MaterialCommon common;
    bool has_perturbation = false;
    // pbrt-v4's hair material has no normal or bump map either.
    if (m.type != "interface" && m.type != "none" && !m.type.empty() && m.type != "mix" &&
        m.type != "hair") {
        if (auto file = ps.find_string("normalmap")) {
            const Param* p = ps.find("normalmap");
            auto img = std::make_shared<TextureImage>();
            try {
                img->image = read_image(resolve_path(m_d.base_dir, *file), false);  // linear
            } catch (const Error& err) {
                throw_error(p->loc, "\"normalmap\": {}", err.what());
            }
            if (img->image.channels < 3)
                throw_error(p->loc, "\"normalmap\" \"{}\" needs RGB channels", *file);
            img->wrap = WrapMode::Repeat;
            common.normal_map = std::move(img);
            has_perturbation = true;
        }
        if (ps.find("displacement")) {
            common.displacement = float_texture_param(ps, "displacement", 0);
            has_perturbation = true;
        }
    }
    Material mt = make_material_model(m);
    if (has_perturbation)
        std::visit([&](auto& x) { static_cast<MaterialCommon&>(x) = common; }, mt);
    return mt;
}

Material Builder::make_material_model(const MaterialDesc& m) {
    const ParamSet& ps = m.params;
    std::string what = m.name.empty() ? fmt::format("Material \"{}\"", m.type)
                                      : fmt::format("material \"{}\"", m.name);
    if (m.type == "diffuse") {
        DiffuseMaterial d;
        d.reflectance = spectrum_texture_param(ps, "reflectance", 0.5f);
        ps.check_unused(what);
        return d;
    }
    if (m.type == "interface" || m.type == "none" || m.type.empty()) {
        ps.check_unused(what);
        return InterfaceMaterial{};
    }
    if (m.type == "dielectric") {
        DielectricMaterial d;
        std::tie(d.eta, d.dispersive) = eta_param(ps, 1.5f);
        d.roughness = roughness_params(ps);
        ps.check_unused(what);
        return d;
    }
    if (m.type == "thindielectric") {
        ThinDielectricMaterial d;
        std::tie(d.eta, d.dispersive) = eta_param(ps, 1.5f);
        ps.check_unused(what);
        return d;
    }
    if (m.type == "conductor") {
        ConductorMaterial c;
        if (ps.find("reflectance")) {
            if (ps.find("eta") || ps.find("k"))
                throw_error(m.loc, "{}: give either \"reflectance\" or \"eta\" and \"k\"", what);
            c.reflectance = spectrum_texture_param(ps, "reflectance", 1);
        } else {
            c.eta = unbounded_param(ps, "eta", "metal-Cu-eta");
            c.k = unbounded_param(ps, "k", "metal-Cu-k");
        }
        c.roughness = roughness_params(ps);
        ps.check_unused(what);
        return c;
    }
    if (m.type == "diffusetransmission") {
        DiffuseTransmissionMaterial d;
        d.reflectance = spectrum_texture_param(ps, "reflectance", 0.25f);
        d.transmittance = spectrum_texture_param(ps, "transmittance", 0.25f);
        d.scale = ps.get_float("scale", 1);
        ps.check_unused(what);
        return d;
    }
    if (m.type == "coateddiffuse") {
        CoatedDiffuseMaterial c;
        c.reflectance = spectrum_texture_param(ps, "reflectance", 0.5f);
        c.roughness = roughness_params(ps);
        std::tie(c.eta, c.dispersive) = eta_param(ps, 1.5f);
        c.layer = layer_params(ps, what);
        ps.check_unused(what);
        return c;
    }
    if (m.type == "coatedconductor") {
        CoatedConductorMaterial c;
        c.interface_roughness = prefixed_roughness_params(ps, "interface.");
        std::tie(c.interface_eta, c.dispersive) = named_eta_param(ps, "interface.eta", 1.5f);
        if (ps.find("reflectance")) {
            if (ps.find("conductor.eta") || ps.find("conductor.k"))
                throw_error(m.loc,
                            "{}: give either \"reflectance\" or \"conductor.eta\" and "
                            "\"conductor.k\"",
                            what);
            c.reflectance = spectrum_texture_param(ps, "reflectance", 1);
        } else {
            c.conductor_eta = unbounded_param(ps, "conductor.eta", "metal-Cu-eta");
            c.conductor_k = unbounded_param(ps, "conductor.k", "metal-Cu-k");
        }
        c.conductor_roughness = prefixed_roughness_params(ps, "conductor.");
        c.layer = layer_params(ps, what);
        ps.check_unused(what);
        return c;
    }
    if (m.type == "mix") {
        MixMaterial mix;
        std::vector<std::string> names = ps.get_strings("materials");
        const Param* p = ps.find("materials");
        SourceLoc loc = p ? p->loc : m.loc;
        if (names.size() != 2)
            throw_error(loc, "{}: \"materials\" must name two materials, got {}", what,
                        names.size());
        for (int k = 0; k < 2; ++k) {
            auto it = m_d.named_materials.find(names[k]);
            if (it == m_d.named_materials.end())
                throw_error(loc, "{}: named material \"{}\" is not defined", what, names[k]);
            mix.materials[k] = it->second;  // a description index until resolve_mixes()
        }
        mix.amount = float_texture_param(ps, "amount", 0.5f);
        ps.check_unused(what);
        return mix;
    }
    if (m.type == "hair") {
        HairMaterial h = hair_params(ps, what);
        ps.check_unused(what);
        return h;
    }
    if (m.type == "phong" || m.type == "modifiedphong") {  // steradian extensions
        PhongMaterial p;
        p.kd = albedo_param(ps, "Kd", 0.5f);
        p.ks = albedo_param(ps, "Ks", 0.25f);
        p.exponent = bounded_float_param(ps, "exponent", 20, false);
        p.absorb = m.type == "modifiedphong";
        ps.check_unused(what);
        p.energy_scale = energy_scale(p.kd, p.ks, m.loc, what);
        return p;
    }
    if (m.type == "lafortune") {  // steradian extension
        LafortuneMaterial l = lafortune_params(ps, m.loc, what);
        ps.check_unused(what);
        return l;
    }
    if (m.type == "ward") {  // steradian extension
        WardMaterial w;
        w.kd = albedo_param(ps, "Kd", 0.5f);
        w.ks = albedo_param(ps, "Ks", 0.25f);
        w.alpha_x = bounded_float_param(ps, "alpha_x", 0.1f, true);
        w.alpha_y = ps.find("alpha_y") ? bounded_float_param(ps, "alpha_y", 0.1f, true) : w.alpha_x;
        ps.check_unused(what);
        w.energy_scale = energy_scale(w.kd, w.ks, m.loc, what);
        return w;
    }
    if (m.type == "subsurface") {
        SubsurfaceMaterial s = subsurface_params(ps, what);
        ps.check_unused(what);
        return s;
    }
    if (m.type == "measured") {
        MeasuredMaterial mm;
        mm.brdf = measured_brdf(ps, m, what);
        ps.check_unused(what);
        return mm;
    }
    throw_unsupported(m.loc, "material type \"{}\" is not supported yet (see docs/pbrt-support.md)",
                      m.type);
}

/// pbrt-v4's HairMaterial::Create: the absorption from "sigma_a" (unbounded spectrum), else
/// "reflectance" (or its older name "color"), else "eumelanin"/"pheomelanin", else
/// eumelanin 1.3; the others given are ignored with a warning. "eta" (1.55), "beta_m" (0.3),
/// "beta_n" (0.3), "alpha" (2 degrees), all float textures.
HairMaterial Builder::hair_params(const ParamSet& ps, const std::string& what) {
    HairMaterial h;
    const char* refl = ps.find("reflectance") ? "reflectance" : "color";
    const bool has_sigma = ps.find("sigma_a"), has_refl = ps.find(refl);
    const bool has_melanin = ps.find("eumelanin") || ps.find("pheomelanin");
    auto ignored = [&](const char* name, const char* because) {
        if (const Param* p = ps.find(name)) {
            p->used = true;
            warning(p->loc, fmt::format("{}: \"{}\" is ignored since \"{}\" is given (as in "
                                        "pbrt-v4)",
                                        what, name, because));
        }
    };
    if (has_sigma) {
        h.sigma_a = spectrum_texture_param(ps, "sigma_a", 0, SpectrumKind::Unbounded);
        ignored(refl, "sigma_a");
        ignored("eumelanin", "sigma_a");
        ignored("pheomelanin", "sigma_a");
    } else if (has_refl) {
        h.reflectance = spectrum_texture_param(ps, refl, 0.5f);
        ignored("eumelanin", refl);
        ignored("pheomelanin", refl);
    } else if (has_melanin && (ps.find_texture("eumelanin") || ps.find_texture("pheomelanin"))) {
        h.eumelanin = float_texture_param(ps, "eumelanin", 0);
        h.pheomelanin = float_texture_param(ps, "pheomelanin", 0);
        build_rgb_uplift_table();  // per-hit concentrations are uplifted by table
    } else {
        // Constant concentrations (pbrt-v4's default: eumelanin 1.3) as a constant sigma_a.
        const Float ce = has_melanin ? ps.get_float("eumelanin", 0) : Float(1.3);
        const Float cp = has_melanin ? ps.get_float("pheomelanin", 0) : Float(0);
        for (const char* name : {"eumelanin", "pheomelanin"})
            if (const Param* p = ps.find(name); p && !(ps.get_float(name, 0) >= 0))
                throw_error(p->loc, "{}: \"{}\" must be a concentration >= 0", what, name);
        const auto rgb = HairLobe::sigma_a_from_concentration(ce, cp);
        m_s.spectrum_textures.push_back(ConstantSpectrumTexture{
            densely_sampled(rgb_unbounded_spectrum(Rgb{rgb[0], rgb[1], rgb[2]}))});
        h.sigma_a = int(m_s.spectrum_textures.size()) - 1;
    }
    h.eta = float_texture_param(ps, "eta", 1.55f);
    if (const Param* p = ps.find("eta", ParamType::Float); p && !(ps.get_float("eta", 1) > 0))
        throw_error(p->loc, "{}: \"eta\" must be positive", what);
    h.beta_m = float_texture_param(ps, "beta_m", 0.3f);
    h.beta_n = float_texture_param(ps, "beta_n", 0.3f);
    h.alpha = float_texture_param(ps, "alpha", 2);
    return h;
}

std::shared_ptr<const MeasuredBrdf> Builder::measured_brdf(const ParamSet& ps,
                                                           const MaterialDesc& m,
                                                           const std::string& what) {
    std::string file = ps.get_string("filename", "");
    const Param* p = ps.find("filename");
    if (file.empty())
        throw_error(p ? p->loc : m.loc, "{}: \"filename\" must name a .bsdf file", what);
    std::string path = resolve_path(m_d.base_dir, file);
    auto it = m_measured.find(path);
    if (it != m_measured.end()) return it->second;
    try {
        auto brdf = std::make_shared<const MeasuredBrdf>(read_measured_brdf(path));
        return m_measured.emplace(path, std::move(brdf)).first->second;
    } catch (const Error& err) {
        throw_error(p->loc, "{}: \"filename\": {}", what, err.what());
    }
}

void Builder::build_materials() {
    m_material_index.resize(m_d.materials.size(), -1);
    for (size_t i = 0; i < m_d.materials.size(); ++i) {
        Material m;
        if (recorded([&] { m = make_material(m_d.materials[i]); })) {
            m_material_index[i] = int(m_s.materials.size());
            m_s.materials.push_back(std::move(m));
        } else {
            m_material_index[i] = resolve_material({});  // recorded; the default stands in
        }
    }
    resolve_mixes();
    // A subsurface material's interior is a medium of the path (integrators/path/volpath.cpp):
    // the scene takes the volumetric kernel even if it has no "medium".
    for (const Material& m : m_s.materials)
        if (std::holds_alternative<SubsurfaceMaterial>(m)) {
            use_volumetric_kernel("subsurface materials",
                                  "renders them as plain dielectrics (no subsurface scattering)");
            break;
        }
}

int Builder::resolve_material(const MaterialRef& r) {
    if (r.index >= 0) {
        int mi = m_material_index[r.index];
        return std::holds_alternative<InterfaceMaterial>(m_s.materials[mi]) ? -1 : mi;
    }
    if (!r.name.empty()) {
        auto it = m_d.named_materials.find(r.name);
        if (it == m_d.named_materials.end())
            throw_error(r.loc, "named material \"{}\" is not defined", r.name);
        int mi = m_material_index[it->second];
        return std::holds_alternative<InterfaceMaterial>(m_s.materials[mi]) ? -1 : mi;
    }
    // pbrt-v4's default: diffuse with reflectance 0.5.
    if (m_default_material < 0) {
        DiffuseMaterial d;
        m_s.spectrum_textures.push_back(
            ConstantSpectrumTexture{densely_sampled(ConstantSpectrum{0.5f})});
        d.reflectance = int(m_s.spectrum_textures.size()) - 1;
        m_default_material = int(m_s.materials.size());
        m_s.materials.push_back(d);
    }
    return m_default_material;
}

}  // namespace sr::build_detail
