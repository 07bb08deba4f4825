/// Textures: image loading, uv mappings, float and spectrum textures and texture parameters.
#include "steradian/film/image_io.h"
#include "steradian/scene/build/builder.h"

namespace sr::build_detail {

std::shared_ptr<const TextureImage> Builder::load_image(const TextureDesc& t, const ParamSet& ps) {
    std::string file = ps.get_string("filename", "");
    if (file.empty()) throw_error(t.loc, "imagemap texture \"{}\" needs a \"filename\"", t.name);
    std::string path = resolve_path(m_d.base_dir, file);
    std::string encoding = ps.get_string("encoding", "sRGB");
    std::string wrap = ps.get_string("wrap", "repeat");
    std::string key = path + "|" + encoding + "|" + wrap;
    if (auto it = m_images.find(key); it != m_images.end()) return it->second;
    auto img = std::make_shared<TextureImage>();
    try {
        img->image = read_image(path, encoding == "sRGB");
    } catch (const Error& err) {
        throw_error(t.loc, "{}", err.what());
    }
    if (encoding != "sRGB" && encoding != "linear") {
        Float gamma = 0;
        if (std::sscanf(encoding.c_str(), "gamma %f", &gamma) != 1 || gamma <= 0)
            throw_error(t.loc, "unknown encoding \"{}\" (sRGB, linear, or \"gamma g\")", encoding);
        for (auto& v : img->image.data) v = std::pow(std::max(0.f, v), gamma);
    }
    if (wrap == "repeat")
        img->wrap = WrapMode::Repeat;
    else if (wrap == "clamp")
        img->wrap = WrapMode::Clamp;
    else if (wrap == "black")
        img->wrap = WrapMode::Black;
    else
        throw_error(t.loc, "unknown wrap mode \"{}\"", wrap);
    img->build_pyramid();
    m_images[key] = img;
    return img;
}

/// An imagemap's "filter" (pbrt-v4's names; default "bilinear") and "maxanisotropy" (8).
void Builder::read_filter(const TextureDesc& t, const ParamSet& ps, TextureFilter& f,
                          Float& max_aniso) {
    const std::string name = ps.get_string("filter", "bilinear");
    if (name == "point")
        f = TextureFilter::Point;
    else if (name == "bilinear")
        f = TextureFilter::Bilinear;
    else if (name == "trilinear")
        f = TextureFilter::Trilinear;
    else if (name == "ewa" || name == "EWA")
        f = TextureFilter::Ewa;
    else
        throw_error(ps.find("filter")->loc,
                    "Texture \"{}\": unknown filter \"{}\" (point, bilinear, trilinear or ewa)",
                    t.name, name);
    max_aniso = ps.get_float("maxanisotropy", 8);
    if (!(max_aniso >= 1) || !std::isfinite(max_aniso))
        throw_error(ps.find("maxanisotropy")->loc,
                    "Texture \"{}\": \"maxanisotropy\" must be a finite number >= 1", t.name);
    m_s.texture_footprints = true;
}

/// "directionmix"'s "dir" (default (0, 1, 0)) in the texture's space, as a unit world vector.
Vec3 Builder::mix_direction(const TextureDesc& t, const ParamSet& ps) {
    const Vec3 d = t.world_from_texture.vector(ps.find_vector3("dir").value_or(Vec3(0, 1, 0)));
    if (!(length(d) > 0) || !std::isfinite(length(d)))
        throw_error(t.loc, "Texture \"{}\": \"dir\" must be a non-zero vector", t.name);
    return normalize(d);
}

UvMapping Builder::read_mapping(const TextureDesc& t, const ParamSet& ps) {
    // pbrt-v4's TextureMapping2D::Create: uscale and vscale belong to "uv" only, udelta and
    // vdelta to "uv" and "planar".
    const std::string mapping = ps.get_string("mapping", "uv");
    UvMapping m;
    if (mapping == "uv") {
        m.su = ps.get_float("uscale", 1);
        m.sv = ps.get_float("vscale", 1);
        m.du = ps.get_float("udelta", 0);
        m.dv = ps.get_float("vdelta", 0);
        return m;
    }
    if (mapping == "spherical")
        m.kind = UvMapping::Kind::Spherical;
    else if (mapping == "cylindrical")
        m.kind = UvMapping::Kind::Cylindrical;
    else if (mapping == "planar")
        m.kind = UvMapping::Kind::Planar;
    else
        throw_error(t.loc, "unknown texture mapping \"{}\" (pbrt-v4 has \"uv\", \"spherical\", "
                           "\"cylindrical\" and \"planar\")", mapping);
    check_transform(t.world_from_texture, t.loc, "the texture's mapping");
    m.texture_from_world = t.world_from_texture.inverse();
    if (m.kind == UvMapping::Kind::Planar) {
        m.v1 = ps.find_vector3("v1").value_or(Vec3(1, 0, 0));
        m.v2 = ps.find_vector3("v2").value_or(Vec3(0, 1, 0));
        m.du = ps.get_float("udelta", 0);
        m.dv = ps.get_float("vdelta", 0);
    }
    return m;
}

void Builder::build_textures() {
    // A texture that cannot be built is recorded, and a constant 1 stands in under its name.
    for (const TextureDesc& t : m_d.float_textures)
        if (!recorded([&] { build_float_texture(t); })) {
            m_float_tex[t.name] = int(m_s.float_textures.size());
            m_s.float_textures.push_back(ConstantFloatTexture{1});
        }
    for (const TextureDesc& t : m_d.spectrum_textures)
        if (!recorded([&] { build_spectrum_texture(t); })) {
            m_spec_tex[t.name] = int(m_s.spectrum_textures.size());
            m_s.spectrum_textures.push_back(
                ConstantSpectrumTexture{densely_sampled(ConstantSpectrum{1})});
        }
}

void Builder::build_float_texture(const TextureDesc& t) {
    const ParamSet& ps = t.params;
    FloatTexture tex;
    if (t.type == "constant") {
        tex = ConstantFloatTexture{ps.get_float("value", 1)};
    } else if (t.type == "imagemap") {
        ImageFloatTexture it;
        it.mapping = read_mapping(t, ps);
        it.image = load_image(t, ps);
        it.scale = ps.get_float("scale", 1);
        it.invert = ps.get_bool("invert", false);
        read_filter(t, ps, it.filter, it.max_aniso);
        tex = it;
    } else if (t.type == "scale") {
        tex = ScaleFloatTexture{float_tex_arg(ps, "tex", 1), float_tex_arg(ps, "scale", 1)};
    } else if (t.type == "mix") {
        tex = MixFloatTexture{float_tex_arg(ps, "tex1", 0), float_tex_arg(ps, "tex2", 1),
                              float_tex_arg(ps, "amount", 0.5f)};
    } else if (t.type == "checkerboard") {
        check_checkerboard_dimension(t, ps);
        m_s.texture_footprints = true;
        tex = CheckerboardFloatTexture{float_tex_arg(ps, "tex1", 1), float_tex_arg(ps, "tex2", 0),
                                       read_mapping(t, ps)};
    } else if (t.type == "directionmix") {
        tex = DirectionMixFloatTexture{float_tex_arg(ps, "tex1", 0), float_tex_arg(ps, "tex2", 1),
                                       mix_direction(t, ps)};
    } else if (t.type == "fbm" || t.type == "wrinkled" || t.type == "windy") {
        NoiseFloatTexture n;
        n.kind = t.type == "fbm"        ? NoiseFloatTexture::Kind::Fbm
                 : t.type == "wrinkled" ? NoiseFloatTexture::Kind::Wrinkled
                                        : NoiseFloatTexture::Kind::Windy;
        check_transform(t.world_from_texture, t.loc, "the texture's space");
        n.texture_from_world = t.world_from_texture.inverse();
        m_s.texture_footprints = true;
        if (n.kind != NoiseFloatTexture::Kind::Windy) {
            n.octaves = ps.get_int("octaves", 8);
            n.omega = ps.get_float("roughness", 0.5f);
            if (n.octaves < 0 || n.octaves > 64)
                throw_error(t.loc, "Texture \"{}\": \"octaves\" must be from 0 to 64", t.name);
        }
        tex = n;
    } else if (t.type == "dots") {
        tex = DotsFloatTexture{read_mapping(t, ps), float_tex_arg(ps, "inside", 1),
                               float_tex_arg(ps, "outside", 0)};
    } else if (t.type == "bilerp") {
        tex =
            BilerpFloatTexture{read_mapping(t, ps), ps.get_float("v00", 0), ps.get_float("v01", 1),
                               ps.get_float("v10", 0), ps.get_float("v11", 1)};
    } else {
        unsupported(t, "Texture");
    }
    ps.check_unused(fmt::format("Texture \"{}\"", t.name));
    m_float_tex[t.name] = int(m_s.float_textures.size());
    m_s.float_textures.push_back(tex);
}

void Builder::build_spectrum_texture(const TextureDesc& t) {
    const ParamSet& ps = t.params;
    if (t.type == "constant") {
        const Param* v = ps.find_spectrum("value");
        Spectrum s = v ? spectrum_from_param(*v, SpectrumKind::Albedo, m_d.base_dir)
                       : Spectrum(ConstantSpectrum{1});
        ps.check_unused(fmt::format("Texture \"{}\"", t.name));
        m_spec_tex[t.name] = int(m_s.spectrum_textures.size());
        m_s.spectrum_textures.push_back(ConstantSpectrumTexture{densely_sampled(s)});
    } else if (t.type == "imagemap") {
        ImageSpectrumTexture it;
        it.mapping = read_mapping(t, ps);
        it.image = load_image(t, ps);
        // Per-lookup RGB uplift (once per process; after the image, whose errors come first).
        build_rgb_uplift_table();
        it.scale = ps.get_float("scale", 1);
        it.invert = ps.get_bool("invert", false);
        read_filter(t, ps, it.filter, it.max_aniso);
        ps.check_unused(fmt::format("Texture \"{}\"", t.name));
        m_spec_tex[t.name] = int(m_s.spectrum_textures.size());
        m_s.spectrum_textures.push_back(it);
    } else if (t.type == "scale" || t.type == "mix" || t.type == "checkerboard" ||
               t.type == "directionmix" || t.type == "bilerp" || t.type == "dots") {
        SpectrumTexture tex;
        if (t.type == "dots") {
            tex = DotsSpectrumTexture{read_mapping(t, ps), spectrum_tex_arg(ps, "inside", 1),
                                      spectrum_tex_arg(ps, "outside", 0)};
        } else if (t.type == "directionmix") {
            tex =
                DirectionMixSpectrumTexture{spectrum_tex_arg(ps, "tex1", 0),
                                            spectrum_tex_arg(ps, "tex2", 1), mix_direction(t, ps)};
        } else if (t.type == "bilerp") {
            auto corner = [&](std::string_view name, Float def) {
                const Param* p = ps.find_spectrum(name);
                return p ? Spectrum(densely_sampled(
                               spectrum_from_param(*p, SpectrumKind::Albedo, m_d.base_dir)))
                         : Spectrum(ConstantSpectrum{def});
            };
            tex = BilerpSpectrumTexture{read_mapping(t, ps), corner("v00", 0), corner("v01", 1),
                                        corner("v10", 0), corner("v11", 1)};
        } else if (t.type == "scale") {
            tex =
                ScaleSpectrumTexture{spectrum_tex_arg(ps, "tex", 1), float_tex_arg(ps, "scale", 1)};
        } else if (t.type == "mix") {
            tex =
                MixSpectrumTexture{spectrum_tex_arg(ps, "tex1", 0), spectrum_tex_arg(ps, "tex2", 1),
                                   float_tex_arg(ps, "amount", 0.5f)};
        } else {
            check_checkerboard_dimension(t, ps);
            m_s.texture_footprints = true;
            tex = CheckerboardSpectrumTexture{spectrum_tex_arg(ps, "tex1", 1),
                                              spectrum_tex_arg(ps, "tex2", 0), read_mapping(t, ps)};
        }
        ps.check_unused(fmt::format("Texture \"{}\"", t.name));
        m_spec_tex[t.name] = int(m_s.spectrum_textures.size());
        m_s.spectrum_textures.push_back(std::move(tex));
    } else if (t.type == "marble") {
        build_rgb_uplift_table();
        MarbleSpectrumTexture m;
        check_transform(t.world_from_texture, t.loc, "the texture's space");
        m.texture_from_world = t.world_from_texture.inverse();
        m.octaves = ps.get_int("octaves", 8);
        m.omega = ps.get_float("roughness", 0.5f);
        m.scale = ps.get_float("scale", 1);
        m.variation = ps.get_float("variation", 0.2f);
        if (m.octaves < 0 || m.octaves > 64)
            throw_error(t.loc, "Texture \"{}\": \"octaves\" must be from 0 to 64", t.name);
        if (!std::isfinite(m.omega) || !std::isfinite(m.scale) || !std::isfinite(m.variation))
            throw_error(t.loc, "Texture \"{}\": parameters must be finite", t.name);
        m_s.texture_footprints = true;
        ps.check_unused(fmt::format("Texture \"{}\"", t.name));
        m_spec_tex[t.name] = int(m_s.spectrum_textures.size());
        m_s.spectrum_textures.push_back(m);
    } else {
        unsupported(t, "Texture");
    }
}

/// pbrt-v4's checkerboard has "dimension" 2 or 3; only the 2D (uv) form is supported.
void Builder::check_checkerboard_dimension(const TextureDesc& t, const ParamSet& ps) {
    int dim = ps.get_int("dimension", 2);
    if (dim == 3)
        throw_unsupported(ps.find("dimension")->loc,
                          "Texture \"{}\": 3D checkerboards are not supported yet", t.name);
    if (dim != 2)
        throw_error(ps.find("dimension")->loc,
                    "Texture \"{}\": \"dimension\" must be 2 or 3, not {}", t.name, dim);
}

/// An input of a composite texture: a copy of the named texture or of the constant that
/// float_texture_param / spectrum_texture_param make (textures are immutable once built).
std::shared_ptr<const FloatTexture> Builder::float_tex_arg(const ParamSet& ps,
                                                           std::string_view name, Float def) {
    return std::make_shared<const FloatTexture>(
        m_s.float_textures[size_t(float_texture_param(ps, name, def))]);
}

std::shared_ptr<const SpectrumTexture> Builder::spectrum_tex_arg(const ParamSet& ps,
                                                                 std::string_view name, Float def) {
    return std::make_shared<const SpectrumTexture>(
        m_s.spectrum_textures[size_t(spectrum_texture_param(ps, name, def))]);
}

/// A spectrum-texture index for material parameter `name`: a texture reference, an
/// inline spectrum (of the given kind: RGB values are uplifted as albedos or unbounded), or
/// the default constant.
int Builder::spectrum_texture_param(const ParamSet& ps, std::string_view name, Float def,
                                    SpectrumKind kind) {
    if (auto tn = ps.find_texture(name)) {
        auto it = m_spec_tex.find(*tn);
        if (it == m_spec_tex.end()) {
            const Param* p = ps.find(name);
            throw_error(p ? p->loc : SourceLoc{}, "unknown spectrum texture \"{}\"", *tn);
        }
        return it->second;
    }
    Spectrum s = ConstantSpectrum{def};
    if (const Param* p = ps.find_spectrum(name))
        s = spectrum_from_param(*p, kind, m_d.base_dir);
    m_s.spectrum_textures.push_back(ConstantSpectrumTexture{densely_sampled(s)});
    return int(m_s.spectrum_textures.size()) - 1;
}

/// A float-texture index for parameter `name`: a texture reference, a float, or `def`.
int Builder::float_texture_param(const ParamSet& ps, std::string_view name, Float def) {
    if (auto tn = ps.find_texture(name)) {
        auto it = m_float_tex.find(*tn);
        if (it == m_float_tex.end()) {
            const Param* p = ps.find(name);
            throw_error(p ? p->loc : SourceLoc{}, "unknown float texture \"{}\"", *tn);
        }
        return it->second;
    }
    m_s.float_textures.push_back(ConstantFloatTexture{ps.get_float(name, def)});
    return int(m_s.float_textures.size()) - 1;
}

}  // namespace sr::build_detail
