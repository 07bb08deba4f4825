#include "steradian/scene/build.h"

#include <filesystem>
#include <fstream>
#include <map>
#include <sstream>
#include <tuple>

#include "steradian/accel/accel.h"
#include "steradian/film/image_io.h"
#include "steradian/lights/photometric/eulumdat.h"
#include "steradian/lights/photometric/ies.h"
#include "steradian/scene/mesh_io/ply.h"

namespace sr {

namespace {

std::string resolve_path(const std::string& base_dir, const std::string& file) {
    std::filesystem::path p(file);
    if (p.is_absolute() || base_dir.empty()) return file;
    return (std::filesystem::path(base_dir) / p).string();
}

[[noreturn]] void unsupported(const EntityDesc& e, std::string_view what) {
    throw_error(e.loc, "{} \"{}\" is not supported yet (see docs/pbrt-support.md)", what, e.type);
}

/// Reads a two-column (wavelength, value) text file.
std::vector<Float> read_spectrum_file(const std::string& path, const SourceLoc& loc) {
    std::ifstream f(path);
    if (!f) throw_error(loc, "cannot open spectrum file \"{}\"", path);
    std::vector<Float> v;
    std::string line;
    int line_no = 0;
    while (std::getline(f, line)) {
        ++line_no;
        auto hash = line.find('#');
        if (hash != std::string::npos) line.resize(hash);
        std::istringstream ss(line);
        double a, b;
        if (!(ss >> a)) continue;
        if (!(ss >> b)) throw_error(loc, "{}:{}: expected \"wavelength value\"", path, line_no);
        v.push_back(Float(a));
        v.push_back(Float(b));
    }
    if (v.size() < 4) throw_error(loc, "spectrum file \"{}\" has fewer than two samples", path);
    return v;
}

}  // namespace

Spectrum spectrum_from_param(const Param& p, SpectrumKind kind, const std::string& base_dir) {
    switch (p.type) {
        case ParamType::Rgb: {
            if (p.numbers.size() != 3)
                throw_error(p.loc, "\"rgb {}\" needs 3 values, got {}", p.name, p.numbers.size());
            Rgb c{Float(p.numbers[0]), Float(p.numbers[1]), Float(p.numbers[2])};
            if (c.r < 0 || c.g < 0 || c.b < 0)
                throw_error(p.loc, "\"rgb {}\" has a negative component", p.name);
            switch (kind) {
                case SpectrumKind::Albedo:
                    if (c.r > 1 || c.g > 1 || c.b > 1)
                        throw_error(p.loc,
                                    "\"rgb {}\" is a reflectance and must be in [0, 1], got "
                                    "[{} {} {}]",
                                    p.name, c.r, c.g, c.b);
                    return rgb_albedo_spectrum(c);
                case SpectrumKind::Unbounded: return rgb_unbounded_spectrum(c);
                case SpectrumKind::Illuminant: return rgb_illuminant_spectrum(c);
            }
            break;
        }
        case ParamType::Blackbody: {
            if (p.numbers.size() != 1)
                throw_error(p.loc, "\"blackbody {}\" needs one temperature", p.name);
            if (!(p.numbers[0] > 0))
                throw_error(p.loc, "\"blackbody {}\": temperature must be positive", p.name);
            return BlackbodySpectrum(Float(p.numbers[0]));
        }
        case ParamType::Spectrum: {
            if (!p.strings.empty()) {
                if (p.strings.size() != 1)
                    throw_error(p.loc, "\"spectrum {}\" expects one name or file", p.name);
                if (auto s = named_spectrum(p.strings[0])) return *s;
                std::string path = resolve_path(base_dir, p.strings[0]);
                if (!std::filesystem::exists(path))
                    throw_error(p.loc, "\"{}\" is neither a named spectrum nor a file",
                                p.strings[0]);
                auto pairs = read_spectrum_file(path, p.loc);
                return densely_sampled(piecewise_linear_from_interleaved(pairs, false));
            }
            if (p.numbers.size() < 4 || p.numbers.size() % 2)
                throw_error(p.loc,
                            "\"spectrum {}\" needs (wavelength, value) pairs, at least two",
                            p.name);
            std::vector<Float> pairs(p.numbers.begin(), p.numbers.end());
            for (size_t i = 2; i < pairs.size(); i += 2)
                if (!(pairs[i] > pairs[i - 2]))
                    throw_error(p.loc, "\"spectrum {}\": wavelengths must increase", p.name);
            return densely_sampled(piecewise_linear_from_interleaved(pairs, false));
        }
        default: break;
    }
    throw_error(p.loc, "parameter \"{} {}\" is not a spectrum", to_string(p.type), p.name);
}

namespace {

class Builder {
public:
    Builder(const SceneDesc& d, const BuildOptions& o) : m_d(d), m_o(o) {}

    Scene build() {
        build_options_block();
        build_textures();
        build_materials();
        for (const ShapeDesc& s : m_d.shapes) add_shape(s, nullptr);
        build_instances();
        build_luminaires();
        // Lights are created by build_lights() once the geometry's bounds are known.
        return std::move(m_s);
    }

private:
    // ---- options block --------------------------------------------------------------
    void build_options_block() {
        for (const EntityDesc& cs : m_d.color_spaces)
            if (cs.type != "srgb")
                throw_error(cs.loc, "ColorSpace \"{}\" is not supported yet (only \"srgb\")", cs.type);
        if (!m_d.accelerator.type.empty())
            warning(m_d.accelerator.loc, fmt::format("Accelerator \"{}\" ignored: steradian always uses Embree",
                                                     m_d.accelerator.type));
        for (const Param& p : m_d.options.params())
            if (p.name != "seed")
                warning(p.loc, fmt::format("Option \"{}\" is ignored", p.name));
        build_film();
        build_camera();
        build_filter();
        build_sampler();
        build_integrator();
    }

    void build_film() {
        const EntityDesc& f = m_d.film;
        FilmParams fp;
        if (!f.type.empty() && f.type != "rgb") unsupported(f, "Film");
        const ParamSet& ps = f.params;
        fp.resolution = Vec2i(ps.get_int("xresolution", 1280), ps.get_int("yresolution", 720));
        if (fp.resolution.x <= 0 || fp.resolution.y <= 0)
            throw_error(f.loc, "film resolution must be positive");
        fp.filename = ps.get_string("filename", "pbrt.exr");
        fp.x0 = 0;
        fp.x1 = fp.resolution.x;
        fp.y0 = 0;
        fp.y1 = fp.resolution.y;
        if (auto pb = ps.get_ints("pixelbounds"); !pb.empty()) {
            if (pb.size() != 4) throw_error(f.loc, "\"pixelbounds\" needs 4 values");
            fp.x0 = clamp(pb[0], 0, fp.resolution.x);
            fp.x1 = clamp(pb[1], 0, fp.resolution.x);
            fp.y0 = clamp(pb[2], 0, fp.resolution.y);
            fp.y1 = clamp(pb[3], 0, fp.resolution.y);
        }
        if (auto cw = ps.get_floats("cropwindow"); !cw.empty()) {
            if (cw.size() != 4) throw_error(f.loc, "\"cropwindow\" needs 4 values");
            Float x0 = clamp(std::min(cw[0], cw[1]), Float(0), Float(1));
            Float x1 = clamp(std::max(cw[0], cw[1]), Float(0), Float(1));
            Float y0 = clamp(std::min(cw[2], cw[3]), Float(0), Float(1));
            Float y1 = clamp(std::max(cw[2], cw[3]), Float(0), Float(1));
            fp.x0 = int(std::ceil(fp.resolution.x * x0));
            fp.x1 = int(std::ceil(fp.resolution.x * x1));
            fp.y0 = int(std::ceil(fp.resolution.y * y0));
            fp.y1 = int(std::ceil(fp.resolution.y * y1));
        }
        if (fp.x1 <= fp.x0 || fp.y1 <= fp.y0)
            throw_error(f.loc, "the crop window / pixel bounds select no pixels");
        Float iso = ps.get_float("iso", 100);
        m_exposure_iso = iso / 100;
        std::string sensor = ps.get_string("sensor", "cie1931");
        if (sensor != "cie1931")
            throw_error(f.loc, "sensor \"{}\" is not supported yet (only \"cie1931\")", sensor);
        Float wb = ps.get_float("whitebalance", 0);
        if (wb > 0) {
            // White balance from the CIE daylight illuminant of that temperature.
            Xyz w = spectrum_to_xyz(cie_d_illuminant(wb));
            Float sum = w.x + w.y + w.z;
            fp.rgb_from_sensor = srgb_from_xyz_white_balanced(w.x / sum, w.y / sum);
        } else {
            fp.rgb_from_sensor = srgb_from_xyz_matrix();
        }
        fp.max_component = ps.get_float("maxcomponentvalue", kInfinity);
        fp.half_float = ps.get_bool("savefp16", false);
        ps.get_float("diagonal", 35);  // only meaningful for the realistic camera
        ps.check_unused("Film \"rgb\"");
        m_s.film = fp;
    }

    void build_camera() {
        const CameraDesc& c = m_d.camera;
        std::string type = c.type.empty() ? "perspective" : c.type;
        const ParamSet& ps = c.params;
        CameraParams cp;
        cp.world_from_camera = c.world_from_camera;
        cp.resolution = m_s.film.resolution;
        Float shutter_open = ps.get_float("shutteropen", 0);
        Float shutter_close = ps.get_float("shutterclose", 1);
        if (shutter_close < shutter_open)
            throw_error(c.loc, "shutterclose is before shutteropen");
        m_s.film.imaging_ratio = (shutter_close - shutter_open) * m_exposure_iso;
        Float frame = ps.get_float("frameaspectratio",
                                   Float(cp.resolution.x) / Float(cp.resolution.y));
        if (frame > 1) {
            cp.screen[0] = -frame; cp.screen[1] = frame; cp.screen[2] = -1; cp.screen[3] = 1;
        } else {
            cp.screen[0] = -1; cp.screen[1] = 1; cp.screen[2] = -1 / frame; cp.screen[3] = 1 / frame;
        }
        if (auto sw = ps.get_floats("screenwindow"); !sw.empty()) {
            if (sw.size() != 4) throw_error(c.loc, "\"screenwindow\" needs 4 values");
            for (int i = 0; i < 4; ++i) cp.screen[i] = sw[i];
        }
        cp.lens_radius = ps.get_float("lensradius", 0);
        cp.focal_distance = ps.get_float("focaldistance", 1e6f);
        if (type == "perspective") {
            Float fov = ps.get_float("fov", 90);
            if (!(fov > 0 && fov < 180)) throw_error(c.loc, "fov must be in (0, 180) degrees");
            ps.check_unused("Camera \"perspective\"");
            m_s.camera = std::make_unique<PerspectiveCamera>(cp, fov);
        } else if (type == "orthographic") {
            ps.check_unused("Camera \"orthographic\"");
            m_s.camera = std::make_unique<OrthographicCamera>(cp);
        } else {
            CameraDesc cc = c;
            cc.type = type;
            unsupported(cc, "Camera");
        }
    }

    void build_filter() {
        const EntityDesc& f = m_d.filter;
        std::string type = f.type.empty() ? "gaussian" : f.type;
        const ParamSet& ps = f.params;
        FilterType t;
        Float def_r;
        if (type == "box") t = FilterType::Box, def_r = 0.5f;
        else if (type == "triangle") t = FilterType::Triangle, def_r = 2;
        else if (type == "gaussian") t = FilterType::Gaussian, def_r = 1.5f;
        else {
            EntityDesc e = f;
            e.type = type;
            unsupported(e, "PixelFilter");
        }
        Vec2 r(ps.get_float("xradius", def_r), ps.get_float("yradius", def_r));
        if (!(r.x > 0 && r.y > 0)) throw_error(f.loc, "filter radius must be positive");
        Float sigma = t == FilterType::Gaussian ? ps.get_float("sigma", 0.5f) : 0.5f;
        ps.check_unused(fmt::format("PixelFilter \"{}\"", type));
        m_s.filter = std::make_unique<Filter>(t, r, sigma);
    }

    void build_sampler() {
        const EntityDesc& s = m_d.sampler;
        std::string type = s.type.empty() ? "zsobol" : s.type;
        const ParamSet& ps = s.params;
        SamplerSettings ss;
        static const std::map<std::string, std::string> names = {
            {"independent", "independent"}, {"stratified", "stratified"},
            {"zsobol", "zsobol"},           {"sobol", "sobol"},
            {"paddedsobol", "paddedsobol"}, {"halton", "zsobol"},
            {"pmj02bn", "paddedsobol"}};
        auto it = names.find(type);
        if (it == names.end()) {
            EntityDesc e = s;
            e.type = type;
            unsupported(e, "Sampler");
        }
        if (it->first != it->second && type != "sobol")
            warning(s.loc, fmt::format("Sampler \"{}\" is rendered with our \"{}\" sampler", type,
                                       it->second));
        ss.type = it->second;
        int option_seed = 0;
        if (const Param* p = m_d.options.find("seed"))
            option_seed = p->numbers.empty() ? 0 : int(p->numbers[0]);
        ss.seed = uint64_t(ps.get_int("seed", option_seed));
        if (type == "stratified") {
            ss.x_samples = ps.get_int("xsamples", 4);
            ss.y_samples = ps.get_int("ysamples", 4);
            ss.jitter = ps.get_bool("jitter", true);
            if (ss.x_samples <= 0 || ss.y_samples <= 0)
                throw_error(s.loc, "xsamples and ysamples must be positive");
            ss.spp = ss.x_samples * ss.y_samples;
        } else {
            ss.spp = ps.get_int("pixelsamples", 16);
            if (ss.spp <= 0) throw_error(s.loc, "pixelsamples must be positive");
            ps.get_string("randomization", "");
        }
        if (m_o.spp_override > 0) ss.spp = m_o.spp_override;
        ps.check_unused(fmt::format("Sampler \"{}\"", type));
        m_s.sampler = ss;
    }

    void build_integrator() {
        const EntityDesc& e = m_d.integrator;
        std::string type = e.type.empty() ? "volpath" : e.type;
        const ParamSet& ps = e.params;
        IntegratorSettings is;
        if (type == "path" || type == "volpath") {
            if (type == "volpath" && !e.type.empty())
                warning(e.loc, "Integrator \"volpath\" is rendered by \"path\" (no participating media)");
            is.max_depth = ps.get_int("maxdepth", 5);
            is.regularize = ps.get_bool("regularize", false);
            if (is.regularize)
                throw_error(e.loc, "\"regularize\" is not supported yet");
            std::string strategy = ps.get_string("strategy", "mis");
            if (strategy == "mis") is.strategy = LightStrategy::Mis;
            else if (strategy == "bsdf") is.strategy = LightStrategy::BsdfOnly;
            else if (strategy == "light") is.strategy = LightStrategy::LightOnly;
            else throw_error(e.loc, "unknown \"strategy\" \"{}\": expected mis, bsdf or light", strategy);
        } else if (type == "simplepath") {
            is.max_depth = ps.get_int("maxdepth", 5);
            bool lights = ps.get_bool("samplelights", true);
            bool bsdf = ps.get_bool("samplebsdf", true);
            if (!bsdf) throw_error(e.loc, "\"samplebsdf\" false (uniform sampling) is not supported");
            is.strategy = lights ? LightStrategy::LightOnly : LightStrategy::BsdfOnly;
        } else {
            EntityDesc ee = e;
            ee.type = type;
            unsupported(ee, "Integrator");
        }
        if (is.max_depth < 0) throw_error(e.loc, "maxdepth must be >= 0");
        std::string ls = ps.get_string("lightsampler", "bvh");
        if (ls == "uniform") is.light_sampler = "uniform";
        else if (ls == "power" || ls == "bvh") is.light_sampler = "power";
        else throw_error(e.loc, "unknown light sampler \"{}\"", ls);
        ps.check_unused(fmt::format("Integrator \"{}\"", type));
        is.type = "path";
        m_s.integrator = is;
    }

    // ---- textures -------------------------------------------------------------------
    std::shared_ptr<const TextureImage> load_image(const TextureDesc& t, const ParamSet& ps) {
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
        if (wrap == "repeat") img->wrap = WrapMode::Repeat;
        else if (wrap == "clamp") img->wrap = WrapMode::Clamp;
        else if (wrap == "black") img->wrap = WrapMode::Black;
        else throw_error(t.loc, "unknown wrap mode \"{}\"", wrap);
        m_images[key] = img;
        return img;
    }

    UvMapping read_mapping(const TextureDesc& t, const ParamSet& ps) {
        std::string mapping = ps.get_string("mapping", "uv");
        if (mapping != "uv")
            throw_error(t.loc, "texture mapping \"{}\" is not supported yet (only \"uv\")", mapping);
        return {ps.get_float("uscale", 1), ps.get_float("vscale", 1), ps.get_float("udelta", 0),
                ps.get_float("vdelta", 0)};
    }

    void build_textures() {
        for (const TextureDesc& t : m_d.float_textures) {
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
                ps.get_string("filter", "bilinear");
                ps.get_float("maxanisotropy", 8);
                tex = it;
            } else if (t.type == "scale") {
                tex = ScaleFloatTexture{float_tex_arg(ps, "tex", 1), float_tex_arg(ps, "scale", 1)};
            } else if (t.type == "mix") {
                tex = MixFloatTexture{float_tex_arg(ps, "tex1", 0), float_tex_arg(ps, "tex2", 1),
                                      float_tex_arg(ps, "amount", 0.5f)};
            } else if (t.type == "checkerboard") {
                check_checkerboard_dimension(t, ps);
                tex = CheckerboardFloatTexture{float_tex_arg(ps, "tex1", 1), float_tex_arg(ps, "tex2", 0),
                                               read_mapping(t, ps)};
            } else {
                unsupported(t, "Texture");
            }
            ps.check_unused(fmt::format("Texture \"{}\"", t.name));
            m_float_tex[t.name] = int(m_s.float_textures.size());
            m_s.float_textures.push_back(tex);
        }
        for (const TextureDesc& t : m_d.spectrum_textures) {
            const ParamSet& ps = t.params;
            if (t.type == "constant") {
                const Param* v = ps.find_spectrum("value");
                Spectrum s = v ? spectrum_from_param(*v, SpectrumKind::Albedo, m_d.base_dir)
                               : Spectrum(ConstantSpectrum{1});
                ps.check_unused(fmt::format("Texture \"{}\"", t.name));
                m_spec_tex[t.name] = int(m_s.spectrum_textures.size());
                m_s.spectrum_textures.push_back(ConstantSpectrumTexture{densely_sampled(s)});
            } else if (t.type == "imagemap") {
                build_rgb_uplift_table();  // per-lookup RGB uplift (once per process)
                ImageSpectrumTexture it;
                it.mapping = read_mapping(t, ps);
                it.image = load_image(t, ps);
                it.scale = ps.get_float("scale", 1);
                it.invert = ps.get_bool("invert", false);
                ps.get_string("filter", "bilinear");
                ps.get_float("maxanisotropy", 8);
                ps.check_unused(fmt::format("Texture \"{}\"", t.name));
                m_spec_tex[t.name] = int(m_s.spectrum_textures.size());
                m_s.spectrum_textures.push_back(it);
            } else if (t.type == "scale" || t.type == "mix" || t.type == "checkerboard") {
                SpectrumTexture tex;
                if (t.type == "scale") {
                    tex = ScaleSpectrumTexture{spectrum_tex_arg(ps, "tex", 1), float_tex_arg(ps, "scale", 1)};
                } else if (t.type == "mix") {
                    tex = MixSpectrumTexture{spectrum_tex_arg(ps, "tex1", 0), spectrum_tex_arg(ps, "tex2", 1),
                                             float_tex_arg(ps, "amount", 0.5f)};
                } else {
                    check_checkerboard_dimension(t, ps);
                    tex = CheckerboardSpectrumTexture{spectrum_tex_arg(ps, "tex1", 1),
                                                      spectrum_tex_arg(ps, "tex2", 0), read_mapping(t, ps)};
                }
                ps.check_unused(fmt::format("Texture \"{}\"", t.name));
                m_spec_tex[t.name] = int(m_s.spectrum_textures.size());
                m_s.spectrum_textures.push_back(std::move(tex));
            } else {
                unsupported(t, "Texture");
            }
        }
    }

    /// pbrt-v4's checkerboard has "dimension" 2 or 3; only the 2D (uv) form is supported.
    static void check_checkerboard_dimension(const TextureDesc& t, const ParamSet& ps) {
        int dim = ps.get_int("dimension", 2);
        if (dim == 3)
            throw_error(ps.find("dimension")->loc, "Texture \"{}\": 3D checkerboards are not supported yet", t.name);
        if (dim != 2)
            throw_error(ps.find("dimension")->loc, "Texture \"{}\": \"dimension\" must be 2 or 3, not {}", t.name, dim);
    }

    /// An input of a composite texture: a copy of the named texture or of the constant that
    /// float_texture_param / spectrum_texture_param make (textures are immutable once built).
    std::shared_ptr<const FloatTexture> float_tex_arg(const ParamSet& ps, std::string_view name, Float def) {
        return std::make_shared<const FloatTexture>(m_s.float_textures[size_t(float_texture_param(ps, name, def))]);
    }
    std::shared_ptr<const SpectrumTexture> spectrum_tex_arg(const ParamSet& ps, std::string_view name, Float def) {
        return std::make_shared<const SpectrumTexture>(
            m_s.spectrum_textures[size_t(spectrum_texture_param(ps, name, def))]);
    }

    /// A spectrum-texture index for material parameter `name`: a texture reference, an
    /// inline spectrum, or the default constant.
    int spectrum_texture_param(const ParamSet& ps, std::string_view name, Float def) {
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
            s = spectrum_from_param(*p, SpectrumKind::Albedo, m_d.base_dir);
        m_s.spectrum_textures.push_back(ConstantSpectrumTexture{densely_sampled(s)});
        return int(m_s.spectrum_textures.size()) - 1;
    }

    /// A float-texture index for parameter `name`: a texture reference, a float, or `def`.
    int float_texture_param(const ParamSet& ps, std::string_view name, Float def) {
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

    /// "roughness", or "uroughness"/"vroughness" (pbrt-v4: each defaults to roughness), and
    /// "remaproughness".
    Roughness roughness_params(const ParamSet& ps) {
        Roughness r;
        bool has_u = ps.find("uroughness") != nullptr, has_v = ps.find("vroughness") != nullptr;
        int both = (!has_u || !has_v) ? float_texture_param(ps, "roughness", 0) : -1;
        r.u = has_u ? float_texture_param(ps, "uroughness", 0) : both;
        r.v = has_v ? float_texture_param(ps, "vroughness", 0) : both;
        r.remap = ps.get_bool("remaproughness", true);
        return r;
    }

    /// An index of refraction: "float eta" or "spectrum eta" (named glasses disperse).
    std::pair<Spectrum, bool> eta_param(const ParamSet& ps, Float def) {
        if (const Param* p = ps.find("eta")) {
            if (p->type == ParamType::Float) return {ConstantSpectrum{ps.get_float("eta", def)}, false};
            Spectrum s = spectrum_from_param(*ps.find_spectrum("eta"), SpectrumKind::Unbounded,
                                             m_d.base_dir);
            if (const auto* c = s.get_if<ConstantSpectrum>()) return {*c, false};
            return {densely_sampled(s), true};
        }
        return {ConstantSpectrum{def}, false};
    }

    Spectrum unbounded_param(const ParamSet& ps, std::string_view name, const char* def_named) {
        if (const Param* p = ps.find_spectrum(name))
            return densely_sampled(spectrum_from_param(*p, SpectrumKind::Unbounded, m_d.base_dir));
        return *named_spectrum(def_named);
    }

    // ---- parameters of steradian's extension materials (phong, lafortune, ward) ---------
    /// A reflectance parameter that may also be a plain "float" (a grey constant in [0, 1]);
    /// otherwise as spectrum_texture_param.
    int albedo_param(const ParamSet& ps, std::string_view name, Float def) {
        const Param* p = ps.find(name);
        if (!p || p->type != ParamType::Float) return spectrum_texture_param(ps, name, def);
        Float v = ps.get_float(name, def);
        if (!(v >= 0 && v <= 1))
            throw_error(p->loc, "\"float {}\" is a reflectance and must be in [0, 1], got {}", name,
                        v);
        m_s.spectrum_textures.push_back(ConstantSpectrumTexture{ConstantSpectrum{v}});
        return int(m_s.spectrum_textures.size()) - 1;
    }

    /// max over the tabulated wavelengths of clamp(a) + clamp(b) (clamped to [0, 1] as the
    /// materials do) when both spectrum textures are constant; empty otherwise.
    std::optional<Float> constant_albedo_sum(int a, int b) const {
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
    Float energy_scale(int kd, int ks, const SourceLoc& loc, const std::string& what) {
        std::optional<Float> sum = constant_albedo_sum(kd, ks);
        if (!sum || *sum <= 1) return 1;
        warning(loc, fmt::format("{}: Kd + Ks reaches {:.4g} > 1, which would create energy; both "
                                 "are scaled by {:.4g}",
                                 what, *sum, 1 / *sum));
        return 1 / *sum;
    }

    /// A float-texture parameter whose constant value must be >= 0 (or > 0 if `positive`);
    /// a violation is an error at the parameter.
    int bounded_float_param(const ParamSet& ps, std::string_view name, Float def, bool positive) {
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
    LafortuneMaterial lafortune_params(const ParamSet& ps, const SourceLoc& loc,
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
                            "{}: lobe {}: \"n\" and \"rhos\" must be finite and >= 0, C finite",
                            what, i + 1);
            // The lobe's peak rhos (Cmax cos)^n must stay far inside float range.
            if (double(c.rho) * std::pow(double(cmax), double(c.n)) > 1e30)
                throw_error(ps.find("n")->loc, "{}: lobe {}: rhos * max|C|^n = {:.3g} overflows",
                            what, i + 1, double(c.rho) * std::pow(double(cmax), double(c.n)));
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
    Roughness prefixed_roughness_params(const ParamSet& ps, const std::string& prefix) {
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
    std::pair<Spectrum, bool> named_eta_param(const ParamSet& ps, const std::string& name,
                                              Float def) {
        const Param* p = ps.find(name);
        if (!p) return {ConstantSpectrum{def}, false};
        if (p->type == ParamType::Float) return {ConstantSpectrum{ps.get_float(name, def)}, false};
        Spectrum s = spectrum_from_param(*ps.find_spectrum(name), SpectrumKind::Unbounded,
                                         m_d.base_dir);
        if (const auto* c = s.get_if<ConstantSpectrum>()) return {*c, false};
        return {densely_sampled(s), true};
    }

    /// The slab between coating and base and the random-walk settings: "thickness" (0.01),
    /// "albedo" (0), "g" (0), "maxdepth" (10), "nsamples" (1), pbrt-v4's defaults.
    LayerParams layer_params(const ParamSet& ps, const std::string& what) {
        LayerParams l;
        l.thickness = float_texture_param(ps, "thickness", 0.01f);
        l.albedo = spectrum_texture_param(ps, "albedo", 0);
        l.g = float_texture_param(ps, "g", 0);
        auto count = [&](const char* name, int def, int lo) {
            int v = ps.get_int(name, def);
            if (v < lo || v > 65535) {
                const Param* p = ps.find(name);
                throw_error(p ? p->loc : SourceLoc{}, "{}: \"{}\" must be in [{}, 65535], got {}",
                            what, name, lo, v);
            }
            return uint16_t(v);
        };
        l.max_depth = count("maxdepth", 10, 0);
        l.n_samples = count("nsamples", 1, 1);
        return l;
    }

    /// Maps the description indices that make_material stored in "mix" materials to scene
    /// material indices, and rejects a mix that contains itself (it would never resolve).
    void resolve_mixes() {
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
                throw_error(m_d.materials[i].loc,
                            "material \"{}\": a \"mix\" material contains itself",
                            m_d.materials[i].name);
    }

    // ---- materials ------------------------------------------------------------------
    /// A material with pbrt-v4's shading-normal parameters ("normalmap", "displacement")
    /// read for every reflection model (interface and mix have none, as in pbrt-v4).
    Material make_material(const MaterialDesc& m) {
        const ParamSet& ps = m.params;
        MaterialCommon common;
        bool has_perturbation = false;
        if (m.type != "interface" && m.type != "none" && !m.type.empty() && m.type != "mix") {
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

    Material make_material_model(const MaterialDesc& m) {
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
            w.alpha_y =
                ps.find("alpha_y") ? bounded_float_param(ps, "alpha_y", 0.1f, true) : w.alpha_x;
            ps.check_unused(what);
            w.energy_scale = energy_scale(w.kd, w.ks, m.loc, what);
            return w;
        }
        throw_error(m.loc, "material type \"{}\" is not supported yet (see docs/pbrt-support.md)",
                    m.type);
    }

    void build_materials() {
        m_material_index.resize(m_d.materials.size(), -1);
        for (size_t i = 0; i < m_d.materials.size(); ++i) {
            m_material_index[i] = int(m_s.materials.size());
            m_s.materials.push_back(make_material(m_d.materials[i]));
        }
        resolve_mixes();
    }

    int resolve_material(const MaterialRef& r) {
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
            m_s.spectrum_textures.push_back(ConstantSpectrumTexture{densely_sampled(ConstantSpectrum{0.5f})});
            d.reflectance = int(m_s.spectrum_textures.size()) - 1;
            m_default_material = int(m_s.materials.size());
            m_s.materials.push_back(d);
        }
        return m_default_material;
    }

    // ---- shapes ---------------------------------------------------------------------
    static std::shared_ptr<std::vector<Point3>> padded_positions(std::vector<Point3> p) {
        p.push_back(Point3(0, 0, 0));  // Embree reads up to 16 bytes past the last vertex
        return std::make_shared<std::vector<Point3>>(std::move(p));
    }

    TriangleMesh make_mesh(const ShapeDesc& s, std::vector<Point3> p, std::vector<Normal3> n,
                           std::vector<Point2> uv, std::vector<int> idx) {
        const Transform& x = s.world_from_object;
        const size_t nv = p.size();
        for (int i : idx)
            if (i < 0 || size_t(i) >= nv)
                throw_error(s.loc, "Shape \"{}\": vertex index {} out of range (there are {} vertices)",
                            s.type, i, nv);
        if (!n.empty() && n.size() != nv)
            throw_error(s.loc, "Shape \"{}\": {} normals for {} vertices", s.type, n.size(), nv);
        if (!uv.empty() && uv.size() != nv)
            throw_error(s.loc, "Shape \"{}\": {} uvs for {} vertices", s.type, uv.size(), nv);
        for (auto& v : p) {
            if (!std::isfinite(v.x) || !std::isfinite(v.y) || !std::isfinite(v.z))
                throw_error(s.loc, "Shape \"{}\": non-finite vertex position", s.type);
            v = x.point(v);
        }
        for (auto& v : n) {
            Vec3 w = x.normal(v);
            Float l = length(w);
            v = l > 0 ? w / l : w;
        }
        TriangleMesh m;
        m.p = padded_positions(std::move(p));
        m.n = std::make_shared<std::vector<Normal3>>(std::move(n));
        m.uv = std::make_shared<std::vector<Point2>>(std::move(uv));
        m.indices = std::make_shared<std::vector<uint32_t>>(idx.begin(), idx.end());
        m.flip_normals = s.reverse_orientation != x.swaps_handedness();
        return m;
    }

    std::optional<ShapeGeometry> make_geometry(const ShapeDesc& s) {
        const ParamSet& ps = s.params;
        std::string what = fmt::format("Shape \"{}\"", s.type);
        if (s.type == "trianglemesh") {
            auto p = ps.get_point3s("P");
            auto idx = ps.get_ints("indices");
            if (idx.empty() && p.size() == 3) idx = {0, 1, 2};
            if (p.empty()) throw_error(s.loc, "{}: \"P\" is required", what);
            if (idx.empty() || idx.size() % 3)
                throw_error(s.loc, "{}: \"indices\" must hold a multiple of 3 values, has {}", what,
                            idx.size());
            auto n = ps.get_normals("N");
            auto uv = ps.get_point2s("uv");
            ps.get_floats("S");
            ps.get_ints("faceIndices");
            check_alpha(s);
            ps.check_unused(what);
            return make_mesh(s, std::move(p), std::move(n), std::move(uv), std::move(idx));
        }
        if (s.type == "plymesh") {
            std::string file = ps.get_string("filename", "");
            if (file.empty()) throw_error(s.loc, "{}: \"filename\" is required", what);
            if (ps.find("displacement"))
                throw_error(s.loc, "{}: \"displacement\" is not supported yet", what);
            ps.get_float("edgelength", 1);
            check_alpha(s);
            ps.check_unused(what);
            TriangleMeshData d;
            try {
                d = read_ply(resolve_path(m_d.base_dir, file));
            } catch (const Error& e) {
                throw_error(s.loc, "{}", e.what());
            }
            std::vector<int> idx(d.indices.begin(), d.indices.end());
            return make_mesh(s, std::move(d.p), std::move(d.n), std::move(d.uv), std::move(idx));
        }
        if (s.type == "bilinearmesh") return make_bilinear(s);
        if (s.type == "sphere") {
            Sphere sp;
            sp.world_from_object = s.world_from_object;
            sp.radius = ps.get_float("radius", 1);
            if (!(sp.radius > 0)) throw_error(s.loc, "{}: radius must be positive", what);
            Float zmin = ps.get_float("zmin", -sp.radius), zmax = ps.get_float("zmax", sp.radius);
            sp.z_min = clamp(std::min(zmin, zmax), -sp.radius, sp.radius);
            sp.z_max = clamp(std::max(zmin, zmax), -sp.radius, sp.radius);
            sp.theta_z_min = std::acos(clamp(std::min(zmin, zmax) / sp.radius, Float(-1), Float(1)));
            sp.theta_z_max = std::acos(clamp(std::max(zmin, zmax) / sp.radius, Float(-1), Float(1)));
            sp.phi_max = radians(clamp(ps.get_float("phimax", 360), Float(0), Float(360)));
            sp.flip_normals = s.reverse_orientation != s.world_from_object.swaps_handedness();
            check_alpha(s);
            ps.check_unused(what);
            return sp;
        }
        if (s.type == "disk") {
            Disk d;
            d.world_from_object = s.world_from_object;
            d.height = ps.get_float("height", 0);
            d.radius = ps.get_float("radius", 1);
            d.inner_radius = ps.get_float("innerradius", 0);
            d.phi_max = radians(clamp(ps.get_float("phimax", 360), Float(0), Float(360)));
            if (!(d.radius > 0) || d.inner_radius < 0 || d.inner_radius >= d.radius)
                throw_error(s.loc, "{}: need 0 <= innerradius < radius", what);
            d.flip_normals = s.reverse_orientation != s.world_from_object.swaps_handedness();
            check_alpha(s);
            ps.check_unused(what);
            return d;
        }
        throw_error(s.loc, "shape type \"{}\" is not supported yet (see docs/pbrt-support.md)",
                    s.type);
    }

    void check_alpha(const ShapeDesc& s) {
        if (const Param* a = s.params.find("alpha")) {
            if (a->type == ParamType::Float && a->numbers.size() == 1 && a->numbers[0] == 1) return;
            throw_error(a->loc, "\"alpha\" cut-outs are not supported yet");
        }
    }

    ShapeGeometry make_bilinear(const ShapeDesc& s) {
        const ParamSet& ps = s.params;
        auto p = ps.get_point3s("P");
        auto idx = ps.get_ints("indices");
        if (idx.empty() && p.size() == 4) idx = {0, 1, 2, 3};
        if (idx.empty() || idx.size() % 4)
            throw_error(s.loc, "Shape \"bilinearmesh\": \"indices\" must hold 4 values per patch");
        auto n = ps.get_normals("N");
        auto uv = ps.get_point2s("uv");
        ps.get_ints("faceIndices");
        check_alpha(s);
        ps.check_unused("Shape \"bilinearmesh\"");
        for (int i : idx)
            if (i < 0 || size_t(i) >= p.size())
                throw_error(s.loc, "Shape \"bilinearmesh\": vertex index {} out of range", i);
        std::vector<Point3> op;
        std::vector<Normal3> on;
        std::vector<Point2> ouv;
        std::vector<int> oi;
        bool warned = false;
        const int kTess = 16;
        for (size_t q = 0; q < idx.size(); q += 4) {
            int v00 = idx[q], v10 = idx[q + 1], v01 = idx[q + 2], v11 = idx[q + 3];
            Point3 p00 = p[v00], p10 = p[v10], p01 = p[v01], p11 = p[v11];
            Vec3 nrm = cross(p10 - p00, p01 - p00);
            Float scale = std::max({length(p10 - p00), length(p01 - p00), Float(1e-30)});
            bool planar = std::abs(dot(normalize(nrm), p11 - p00)) <= 1e-5f * scale;
            int res = planar ? 1 : kTess;
            if (!planar && !warned) {
                warning(s.loc, "non-planar bilinear patches are tessellated (16x16 quads)");
                warned = true;
            }
            auto uvat = [&](int v, Point2 def) { return uv.empty() ? def : uv[v]; };
            Point2 t00 = uvat(v00, {0, 0}), t10 = uvat(v10, {1, 0}), t01 = uvat(v01, {0, 1}),
                   t11 = uvat(v11, {1, 1});
            int base = int(op.size());
            for (int j = 0; j <= res; ++j)
                for (int i = 0; i <= res; ++i) {
                    Float u = Float(i) / res, v = Float(j) / res;
                    op.push_back((p00 * (1 - u) + p10 * u) * (1 - v) + (p01 * (1 - u) + p11 * u) * v);
                    Point2 a = t00 * (1 - u) + t10 * u, b = t01 * (1 - u) + t11 * u;
                    ouv.push_back(a * (1 - v) + b * v);
                    if (!n.empty())
                        on.push_back(normalize((n[v00] * (1 - u) + n[v10] * u) * (1 - v) +
                                               (n[v01] * (1 - u) + n[v11] * u) * v));
                }
            for (int j = 0; j < res; ++j)
                for (int i = 0; i < res; ++i) {
                    int a = base + j * (res + 1) + i, b = a + 1, c = a + (res + 1), d = c + 1;
                    oi.insert(oi.end(), {a, b, d, a, d, c});
                }
        }
        return make_mesh(s, std::move(op), std::move(on), std::move(ouv), std::move(oi));
    }

    /// Adds a shape (world-level when proto is null, else to the prototype).
    void add_shape(const ShapeDesc& s, Prototype* proto) {
        auto geom = make_geometry(s);
        if (!geom) return;
        ShapeEntry e;
        e.geometry = std::move(*geom);
        e.material = resolve_material(s.material);
        int index = int(m_s.shapes.size());
        if (s.area_light >= 0) {
            if (proto)
                throw_error(s.loc, "area lights are not supported inside ObjectBegin (as in pbrt-v4)");
            if (e.material < 0)
                warning(s.loc, "area light on a shape with an \"interface\" material is ignored "
                               "(as in pbrt-v4)");
            else
                m_pending_area.push_back({index, s.area_light});
        }
        m_s.shapes.push_back(std::move(e));
        if (proto)
            proto->shapes.push_back(index);
        else
            m_s.top_level_shapes.push_back(index);
    }

    void build_instances() {
        std::map<std::string, int> proto_index;
        for (const auto& [name, def] : m_d.instances) {
            Prototype p;
            p.name = name;
            for (const ShapeDesc& s : def.shapes) add_shape(s, &p);
            proto_index[name] = int(m_s.prototypes.size());
            m_s.prototypes.push_back(std::move(p));
        }
        for (const InstanceUse& u : m_d.instance_uses) {
            auto it = proto_index.find(u.name);
            if (it == proto_index.end())
                throw_error(u.loc, "ObjectInstance \"{}\": no such object", u.name);
            if (m_s.prototypes[it->second].shapes.empty()) continue;
            m_s.instances.push_back({it->second, u.world_from_instance});
        }
    }

    // ---- photometric luminaires (goniometric lights with an IES/LDT file) ----------
    // Read before the geometry is finalised: a luminous opening is a shape (with the
    // "interface" material, so it emits but does not block light).
    struct Luminaire {
        std::optional<GoniometricLight> point;          ///< the point form, or
        std::shared_ptr<GoniometricEmission> emission;  ///< the luminous opening
        int shape = -1;                                 ///< its shape
    };

    /// ".ies", ".ldt", ... in lower case.
    static std::string lower_extension(const std::string& f) {
        std::string ext = std::filesystem::path(f).extension().string();
        for (char& c : ext) c = char(std::tolower(static_cast<unsigned char>(c)));
        return ext;
    }

    void build_luminaires() {
        for (size_t i = 0; i < m_d.lights.size(); ++i) {
            const LightDesc& l = m_d.lights[i];
            if (l.type != "goniometric") continue;
            m_luminaires[i] = make_luminaire(l);
        }
    }

    Luminaire make_luminaire(const LightDesc& l) {
        const ParamSet& ps = l.params;
        const std::string what = "LightSource \"goniometric\"";
        std::optional<std::string> file = ps.find_string("filename");
        if (!file)
            throw_error(l.loc, "{}: needs \"string filename\" (an .ies or .ldt photometric file)", what);
        const std::string ext = lower_extension(*file);
        std::string path = resolve_path(m_d.base_dir, *file);
        if (ext != ".ies" && ext != ".ldt") return make_image_goniometric(l, path, *file);
        auto data = std::make_shared<PhotometricData>(ext == ".ldt" ? read_eulumdat(path)
                                                                    : read_ies(path));
        // The lamp spectrum gives the shape only: normalised to unit photometric value, so
        // I_e(lambda) = I_v * S(lambda) / integral(S ybar) (course notes eq. 12-17 with
        // K_m folded into the scene unit, docs/units.md).
        Spectrum S = illum_param(ps, "I");
        Float sc = ps.get_float("scale", 1) / photometric_or_fail(S, l.loc);
        Spectrum S_dense = densely_sampled(S);
        // LM-63 TILT: the multiplying factor at the lamp's tilt angle in this mounting.
        Float tilt = ps.get_float("tiltangle", 0);
        if (data->tilt.mode != "NONE") sc *= Float(data->tilt.factor(tilt));
        Float flux = Float(data->total_flux());
        if (!(flux > 0)) throw_error(l.loc, "{}: \"{}\" has no luminous flux", what, *file);
        Float phi = ps.get_float("power", -1);
        if (phi > 0) sc *= phi / flux;
        std::string emission = ps.get_string("emission", "auto");
        if (emission != "auto" && emission != "point" && emission != "area")
            throw_error(ps.find("emission")->loc,
                        "{}: \"emission\" must be \"auto\", \"point\" or \"area\", not \"{}\"",
                        what, emission);
        ps.check_unused(what);

        const Transform& world_from_light = l.world_from_light;
        GoniometricProfile profile{data, world_from_light.inverse()};
        Luminaire lum;
        LuminousShape shape = data->shape;
        bool flat = shape == LuminousShape::Rectangular || shape == LuminousShape::Circular;
        bool round = shape == LuminousShape::Sphere;
        if (emission == "area" && !flat && !round)
            throw_error(l.loc,
                        "{}: \"emission\" \"area\" needs a rectangular, circular or spherical "
                        "luminous opening; \"{}\" has {}",
                        what, *file, to_string(shape));
        if (emission != "point" && shape != LuminousShape::Point && !flat && !round)
            warning(l.loc, fmt::format("{}: the {} luminous opening of \"{}\" is emitted from "
                                       "its photometric centre (point form)",
                                       what, to_string(shape), *file));
        if (emission == "point" || (!flat && !round)) {
            GoniometricLight g;
            g.p = world_from_light.point(Point3(0, 0, 0));
            g.profile = std::move(profile);
            g.spectrum = S_dense;
            g.scale = sc;
            g.flux_lm = flux;
            lum.point = std::move(g);
            return lum;
        }
        auto em = std::make_shared<GoniometricEmission>();
        em->profile = std::move(profile);
        em->spectrum = S_dense;
        em->scale = sc;
        em->flux_lm = flux;
        ShapeEntry e;
        if (round) {
            Sphere sp;
            sp.world_from_object = world_from_light;
            sp.radius = Float(data->width / 2);
            sp.z_min = -sp.radius;
            sp.z_max = sp.radius;
            sp.theta_z_min = 0;
            sp.theta_z_max = kPi;
            sp.flip_normals = world_from_light.swaps_handedness();
            em->sphere_radius = sp.radius;
            em->opening_area = sp.area();
            e.geometry = sp;
        } else if (shape == LuminousShape::Circular) {
            Disk d;
            d.world_from_object = world_from_light;
            d.radius = Float(data->width / 2);
            d.flip_normals = !world_from_light.swaps_handedness();  // facing nadir (-z)
            em->opening_area = d.area();
            e.geometry = d;
        } else {
            // Length along the photometric horizontal (x), width along C90 (y).
            Float hx = Float(data->length / 2), hy = Float(data->width / 2);
            ShapeDesc sd;
            sd.type = "luminous opening";
            sd.loc = l.loc;
            sd.world_from_object = world_from_light;
            TriangleMesh m = make_mesh(sd, {Point3(-hx, -hy, 0), Point3(hx, -hy, 0), Point3(hx, hy, 0),
                                            Point3(-hx, hy, 0)},
                                       {}, {}, {0, 2, 1, 0, 3, 2});
            em->opening_area = m.triangle_area(0) + m.triangle_area(1);
            e.geometry = std::move(m);
        }
        if (!(em->opening_area > 0))
            throw_error(l.loc, "{}: the luminous opening of \"{}\" has no area", what, *file);
        e.material = -1;
        lum.shape = int(m_s.shapes.size());
        m_s.shapes.push_back(std::move(e));
        m_s.top_level_shapes.push_back(lum.shape);
        lum.emission = std::move(em);
        return lum;
    }

    /// pbrt-v4's goniometric light: an equal-area image of relative intensity.
    Luminaire make_image_goniometric(const LightDesc& l, const std::string& path,
                                     const std::string& file) {
        const ParamSet& ps = l.params;
        const std::string what = "LightSource \"goniometric\"";
        const SourceLoc& floc = ps.find("filename")->loc;
        Image img;
        try {
            img = read_image(path, true);
        } catch (const Error& e) {
            throw_error(floc, "{}: {}", what, e.what());
        }
        if (img.width != img.height || img.width == 0)
            throw_error(floc, "{}: \"{}\" is {}x{}; an equal-area goniometric image must be square",
                        what, file, img.width, img.height);
        auto gi = std::make_shared<GoniometricImage>();
        gi->res = img.width;
        gi->y.resize(size_t(img.width) * img.height);
        const int nc = std::min(img.channels, 3);
        for (size_t i = 0; i < gi->y.size(); ++i) {
            double v = 0;
            for (int c = 0; c < nc; ++c) v += img.data[i * size_t(img.channels) + size_t(c)];
            v /= nc;
            if (!std::isfinite(v))
                throw_error(floc, "{}: \"{}\" has NaN or infinite pixels", what, file);
            gi->y[i] = float(v);
        }
        Spectrum S = illum_param(ps, "I");
        Float sc = ps.get_float("scale", 1) / photometric_or_fail(S, l.loc);
        Float mean = gi->mean();
        Float phi = ps.get_float("power", -1);
        if (phi > 0) {
            if (!(mean > 0)) throw_error(l.loc, "{}: \"{}\" is black; \"power\" cannot be met", what, file);
            sc *= phi / (4 * kPi * mean);
        }
        ps.check_unused(what);
        GoniometricLight g;
        g.p = l.world_from_light.point(Point3(0, 0, 0));
        g.profile.light_from_world = l.world_from_light.inverse();
        g.image = std::move(gi);
        g.spectrum = densely_sampled(S);
        g.scale = sc;
        g.flux_lm = 4 * kPi * mean;
        Luminaire lum;
        lum.point = std::move(g);
        return lum;
    }

    void add_luminaire(Scene& s, const Luminaire& lum) {
        if (lum.point) {
            s.lights.push_back(*lum.point);
            return;
        }
        add_emitting_primitives(s, lum.shape, [&](Float area) {
            DiffuseAreaLight dl;
            dl.area = area;
            dl.goniometric = lum.emission;
            return dl;
        });
    }

    /// One DiffuseAreaLight per emitting primitive of shape `shape_index` (each triangle of
    /// a mesh, or the whole sphere or disk), made by make(primitive area), as pbrt-v4 does.
    template <typename Make>
    static void add_emitting_primitives(Scene& s, int shape_index, const Make& make) {
        ShapeEntry& e = s.shapes[shape_index];
        e.light_offset = int(s.lights.size());
        if (auto* mesh = std::get_if<TriangleMesh>(&e.geometry)) {
            for (size_t i = 0; i < mesh->num_triangles(); ++i) {
                DiffuseAreaLight dl = make(mesh->triangle_area(i));
                dl.triangle = mesh->triangle(i);
                s.lights.push_back(dl);
            }
        } else if (auto* sp = std::get_if<Sphere>(&e.geometry)) {
            DiffuseAreaLight dl = make(sp->area());
            dl.sphere = sp;
            s.lights.push_back(dl);
        } else {
            auto* d = std::get_if<Disk>(&e.geometry);
            DiffuseAreaLight dl = make(d->area());
            dl.disk = d;
            s.lights.push_back(dl);
        }
    }

public:
    // ---- lights (after geometry: distant and infinite lights need the bounds) --------
    void build_lights(Scene& s) {
        Point3 center = s.bounds.empty() ? Point3(0, 0, 0) : s.bounds.center();
        Float radius = s.bounds.empty() ? 1 : std::max(Float(1e-3), length(s.bounds.diagonal()) / 2);
        for (size_t i = 0; i < m_d.lights.size(); ++i) {
            if (auto it = m_luminaires.find(i); it != m_luminaires.end())
                add_luminaire(s, it->second);
            else
                add_light(s, m_d.lights[i], center, radius);
        }
        for (auto [shape, al] : m_pending_area) add_area_light(s, shape, m_d.area_lights[al]);
    }

private:
    Spectrum illum_param(const ParamSet& ps, std::string_view name) {
        if (const Param* p = ps.find_spectrum(name))
            return spectrum_from_param(*p, SpectrumKind::Illuminant, m_d.base_dir);
        return srgb_illuminant();
    }

    /// pbrt-v4's SpectrumToPhotometric of a light spectrum as given in the file: for RGB
    /// illuminants only the colour space's illuminant counts, so an "rgb L" of (4, 4, 4) is
    /// four times as bright as (1, 1, 1). Must be called before densely_sampled().
    static Float photometric_or_fail(const Spectrum& s, const SourceLoc& loc) {
        Float y = spectrum_to_photometric(s);
        if (!(y > 0)) throw_error(loc, "the light's spectrum has no visible (V(lambda)) content");
        return y;
    }

    void add_light(Scene& s, const LightDesc& l, Point3 center, Float radius) {
        const ParamSet& ps = l.params;
        std::string what = fmt::format("LightSource \"{}\"", l.type);
        const Transform& x = l.world_from_light;
        if (l.type == "point") {
            PointLight pl;
            Spectrum I = illum_param(ps, "I");
            pl.intensity = densely_sampled(I);
            Float sc = ps.get_float("scale", 1);
            Float phi = ps.get_float("power", -1);
            if (phi > 0) sc *= phi / (4 * kPi);
            sc /= photometric_or_fail(I, l.loc);
            Point3 from = ps.find_point3("from").value_or(Point3(0, 0, 0));
            pl.p = x.point(from);
            pl.scale = sc;
            ps.check_unused(what);
            s.lights.push_back(pl);
        } else if (l.type == "spot") {
            SpotLight sl;
            Spectrum I = illum_param(ps, "I");
            sl.intensity = densely_sampled(I);
            Float sc = ps.get_float("scale", 1);
            Float cone = ps.get_float("coneangle", 30), delta = ps.get_float("conedelta", 5);
            sl.cos_falloff_end = std::cos(radians(cone));
            sl.cos_falloff_start = std::cos(radians(cone - delta));
            Float phi = ps.get_float("power", -1);
            if (phi > 0) {
                Float k_e = 2 * kPi * ((1 - sl.cos_falloff_start) +
                                       (sl.cos_falloff_start - sl.cos_falloff_end) / 2);
                sc *= phi / k_e;
            }
            sc /= photometric_or_fail(I, l.loc);
            Point3 from = ps.find_point3("from").value_or(Point3(0, 0, 0));
            Point3 to = ps.find_point3("to").value_or(Point3(0, 0, 1));
            Vec3 dir = to - from;
            if (length(dir) == 0) throw_error(l.loc, "{}: \"from\" and \"to\" coincide", what);
            // light space: +z along the cone axis, origin at `from`.
            Frame f = Frame::from_z(normalize(dir));
            Matrix4 m = Matrix4::identity();
            for (int i = 0; i < 3; ++i) {
                m.m[i][0] = f.s[i];
                m.m[i][1] = f.t[i];
                m.m[i][2] = f.n[i];
                m.m[i][3] = from[i];
            }
            Transform world_from_spot = x * Transform(m);
            sl.light_from_world = world_from_spot.inverse();
            sl.p = world_from_spot.point(Point3(0, 0, 0));
            sl.scale = sc;
            ps.check_unused(what);
            s.lights.push_back(sl);
        } else if (l.type == "distant") {
            DistantLight dl;
            Spectrum L = illum_param(ps, "L");
            dl.radiance = densely_sampled(L);
            Float sc = ps.get_float("scale", 1);
            sc /= photometric_or_fail(L, l.loc);
            Float ev = ps.get_float("illuminance", -1);
            if (ev > 0) sc *= ev;
            Point3 from = ps.find_point3("from").value_or(Point3(0, 0, 0));
            Point3 to = ps.find_point3("to").value_or(Point3(0, 0, 1));
            Vec3 w = x.vector(from - to);
            if (length(w) == 0) throw_error(l.loc, "{}: \"from\" and \"to\" coincide", what);
            dl.w_light = normalize(w);
            dl.scale = sc;
            dl.scene_center = center;
            dl.scene_radius = radius;
            ps.check_unused(what);
            s.lights.push_back(dl);
        } else if (l.type == "infinite") {
            if (ps.find("filename") || ps.find("portal"))
                throw_error(l.loc, "{}: image-based (\"filename\") and portal infinite lights are "
                                   "not supported yet",
                            what);
            UniformInfiniteLight il;
            Spectrum L = illum_param(ps, "L");
            il.radiance = densely_sampled(L);
            Float sc = ps.get_float("scale", 1);
            sc /= photometric_or_fail(L, l.loc);
            Float ev = ps.get_float("illuminance", -1);
            if (ev > 0) sc *= ev / kPi;
            il.scale = sc;
            il.scene_center = center;
            il.scene_radius = radius;
            ps.check_unused(what);
            s.infinite_lights.push_back(int(s.lights.size()));
            s.lights.push_back(il);
        } else {
            throw_error(l.loc, "light type \"{}\" is not supported yet (see docs/pbrt-support.md)",
                        l.type);
        }
    }

    void add_area_light(Scene& s, int shape_index, const AreaLightDesc& a) {
        if (a.type != "diffuse")
            throw_error(a.loc, "area light type \"{}\" is not supported yet", a.type);
        const ParamSet& ps = a.params;
        if (ps.find("filename"))
            throw_error(a.loc, "image-textured area lights (\"filename\") are not supported yet");
        Spectrum L_param = illum_param(ps, "L");
        Float sc = ps.get_float("scale", 1);
        bool two_sided = ps.get_bool("twosided", false);
        // pbrt-v4 normalises by the photometric value of the spectrum as given (for RGB,
        // of the colour space's illuminant alone), so densify only afterwards.
        sc /= photometric_or_fail(L_param, a.loc);
        Spectrum L = densely_sampled(L_param);
        Float phi = ps.get_float("power", -1);
        ps.check_unused("AreaLightSource \"diffuse\"");
        add_emitting_primitives(s, shape_index, [&](Float area) {
            DiffuseAreaLight dl;
            dl.radiance = L;
            dl.two_sided = two_sided;
            dl.area = area;
            // pbrt-v4 applies "power" per emitting primitive (each triangle its own light).
            dl.scale = phi > 0 ? sc * phi / ((two_sided ? 2 : 1) * area * kPi) : sc;
            return dl;
        });
    }

    const SceneDesc& m_d;
    BuildOptions m_o;
    Scene m_s;
    Float m_exposure_iso = 1;
    std::map<std::string, std::shared_ptr<const TextureImage>> m_images;
    std::map<std::string, int> m_float_tex, m_spec_tex;
    std::vector<int> m_material_index;
    int m_default_material = -1;
    std::vector<std::pair<int, int>> m_pending_area;  ///< (shape, area light desc)
    std::map<size_t, Luminaire> m_luminaires;         ///< by index into SceneDesc::lights
};

}  // namespace

Scene build_scene(const SceneDesc& desc, const BuildOptions& options) {
    Builder b(desc, options);
    Scene s = b.build();
    s.finalize_geometry();
    b.build_lights(s);
    s.finalize_lights();
    s.meters = build_meters(desc.meters);
    return s;
}

}  // namespace sr
