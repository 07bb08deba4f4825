/// MakeNamedMedium into media/ media, and the MediumInterface names of shapes and the camera
/// into medium indices (pbrt-v4's media.cpp Create functions and scene.cpp).
#include "steradian/media/nanovdb.h"
#include "steradian/scene/build/builder.h"

namespace sr::build_detail {

namespace {

/// An Unbounded spectrum parameter, or the constant `def` when absent.
Spectrum coefficient_param(const ParamSet& ps, std::string_view name, Float def,
                           const std::string& base_dir) {
    if (const Param* p = ps.find_spectrum(name))
        return densely_sampled(spectrum_from_param(*p, SpectrumKind::Unbounded, base_dir));
    return ConstantSpectrum{def};
}

/// Le (an Illuminant spectrum) normalised to one nit as pbrt-v4 does (its Lescale is divided
/// by the spectrum's photometric integral); empty when absent or zero.
std::optional<std::pair<Spectrum, Float>> emission_param(const ParamSet& ps,
                                                         const std::string& base_dir) {
    const Param* p = ps.find_spectrum("Le");
    if (!p) return std::nullopt;
    Spectrum s = spectrum_from_param(*p, SpectrumKind::Illuminant, base_dir);
    if (!(s.max_value() > 0)) return std::nullopt;
    Float y = spectrum_to_photometric(s);
    if (!(y > 0)) throw_error(p->loc, "\"Le\" has no visible (V(lambda)) content");
    return std::pair{Spectrum(densely_sampled(s)), 1 / y};
}

Float nonnegative(const ParamSet& ps, std::string_view name, Float def) {
    Float v = ps.get_float(name, def);
    if (!(v >= 0 && std::isfinite(v))) {
        const Param* p = ps.find(name);
        throw_error(p->loc, "\"{}\" must be finite and >= 0, got {}", name, v);
    }
    return v;
}

Float hg_g(const ParamSet& ps) {
    Float g = ps.get_float("g", 0);
    if (!(g > -1 && g < 1))
        throw_error(ps.find("g")->loc,
                    "\"g\" (Henyey-Greenstein asymmetry) must be in (-1, 1), "
                    "got {}",
                    g);
    return g;
}

/// nx, ny, nz and a check that `count` values fill them.
std::array<int, 3> grid_size(const ParamSet& ps, size_t count, const SourceLoc& loc,
                             std::string_view what) {
    std::array<int, 3> n{ps.get_int("nx", 1), ps.get_int("ny", 1), ps.get_int("nz", 1)};
    for (int v : n)
        if (v < 1 || v > 1 << 14) throw_error(loc, "nx, ny and nz must be in [1, 16384]");
    if (int64_t(n[0]) * n[1] * n[2] != int64_t(count))
        throw_error(loc, "{} has {} values; expected nx * ny * nz = {} x {} x {} = {}", what, count,
                    n[0], n[1], n[2], int64_t(n[0]) * n[1] * n[2]);
    return n;
}

template <typename T>
SampledGrid<T> make_grid(std::vector<T> v, std::array<int, 3> n) {
    SampledGrid<T> g;
    g.nx = n[0], g.ny = n[1], g.nz = n[2];
    g.values = std::move(v);
    return g;
}

Affine affine_of(const Transform& t) {
    const Matrix4& m = t.matrix();
    Affine a;
    for (int r = 0; r < 3; ++r)
        for (int c = 0; c < 4; ++c) a.m[size_t(r * 4 + c)] = Float(m.m[r][c]);
    return a;
}

/// The bounds p0, p1 of a grid medium, checked to be a non-empty box.
void grid_bounds(const ParamSet& ps, const SourceLoc& loc, Point3& p0, Point3& p1) {
    p0 = ps.find_point3("p0").value_or(Point3(0, 0, 0));
    p1 = ps.find_point3("p1").value_or(Point3(1, 1, 1));
    for (int a = 0; a < 3; ++a)
        if (!(p1[a] > p0[a]) || !std::isfinite(p0[a]) || !std::isfinite(p1[a]))
            throw_error(loc,
                        "the medium's bounds p0 ({}, {}, {}) and p1 ({}, {}, {}) are not a "
                        "box (p0 < p1 in x, y and z)",
                        p0.x, p0.y, p0.z, p1.x, p1.y, p1.z);
}

std::vector<Float> nonnegative_values(const ParamSet& ps, std::string_view name) {
    std::vector<Float> v = ps.get_floats(name);
    for (Float x : v)
        if (!(x >= 0 && std::isfinite(x)))
            throw_error(ps.find(name)->loc, "\"{}\" values must be finite and >= 0, got {}", name,
                        x);
    return v;
}

HomogeneousMedium make_homogeneous(const MediumDesc& d, const std::string& base_dir) {
    const ParamSet& ps = d.params;
    HomogeneousMedium m;
    std::string preset = ps.get_string("preset", "");
    bool have_preset = false;
    if (!preset.empty()) {
        Rgb s, a;
        if (measured_medium(preset, s, a)) {
            have_preset = true;
            m.sigma_a = rgb_unbounded_spectrum(a);
            m.sigma_s = rgb_unbounded_spectrum(s);
        } else {
            throw_error(ps.find("preset")->loc,
                        "unknown medium preset \"{}\" (the names are "
                        "pbrt-v4's, e.g. \"Wholemilk\", \"Skin1\", \"Ketchup\")",
                        preset);
        }
    }
    if (!have_preset) {
        m.sigma_a = coefficient_param(ps, "sigma_a", 1, base_dir);
        m.sigma_s = coefficient_param(ps, "sigma_s", 1, base_dir);
    }
    if (auto le = emission_param(ps, base_dir)) {
        m.le = le->first;
        m.le_scale = nonnegative(ps, "Lescale", 1) * le->second;
    } else {
        nonnegative(ps, "Lescale", 1);
        m.le_scale = 0;
    }
    m.scale = nonnegative(ps, "scale", 1);
    m.g = hg_g(ps);
    return m;
}

GridMedium make_uniform_grid(const MediumDesc& d, const std::string& base_dir) {
    const ParamSet& ps = d.params;
    GridMedium m;
    std::vector<Float> density = nonnegative_values(ps, "density");
    if (density.empty()) throw_error(d.loc, "no \"density\" values for the grid medium");
    std::vector<Float> temperature = ps.get_floats("temperature");
    if (!temperature.empty() && temperature.size() != density.size())
        throw_error(ps.find("temperature")->loc,
                    "{} \"temperature\" values for {} \"density\" values", temperature.size(),
                    density.size());
    auto n = grid_size(ps, density.size(), d.loc, "\"density\"");
    m.density = make_grid(std::move(density), n);
    if (!temperature.empty()) m.temperature = make_grid(std::move(temperature), n);
    auto le = emission_param(ps, base_dir);
    if (le && m.temperature)
        throw_error(ps.find("Le")->loc, "both \"Le\" and \"temperature\" were given");
    Float le_norm = 1;
    if (le) {
        m.le = le->first;
        le_norm = le->second;
    }
    std::vector<Float> le_scale = nonnegative_values(ps, "Lescale");
    if (le_scale.empty()) {
        m.le_scale = make_grid(std::vector<Float>{le_norm}, {1, 1, 1});
    } else {
        grid_size(ps, le_scale.size(), ps.find("Lescale")->loc, "\"Lescale\"");
        for (Float& v : le_scale) v *= le_norm;
        m.le_scale = make_grid(std::move(le_scale), n);
    }
    m.emissive = m.temperature.has_value() || le.has_value();
    grid_bounds(ps, d.loc, m.p0, m.p1);
    m.g = hg_g(ps);
    m.sigma_a = coefficient_param(ps, "sigma_a", 1, base_dir);
    m.sigma_s = coefficient_param(ps, "sigma_s", 1, base_dir);
    m.scale = nonnegative(ps, "scale", 1);
    m.temperature_offset = ps.get_float("temperatureoffset", ps.get_float("temperaturecutoff", 0));
    m.temperature_scale = ps.get_float("temperaturescale", 1);
    m.medium_from_world = affine_of(d.world_from_medium.inverse());
    build_majorants(m);
    return m;
}

std::optional<SampledGrid<RgbUnboundedSpectrum>> rgb_grid(const ParamSet& ps, std::string_view name,
                                                          std::array<int, 3> n) {
    const Param* p = ps.find(name, ParamType::Rgb);
    if (!p) return std::nullopt;
    std::vector<RgbUnboundedSpectrum> v;
    v.reserve(p->numbers.size() / 3);
    for (size_t i = 0; i + 2 < p->numbers.size(); i += 3) {
        Rgb c{Float(p->numbers[i]), Float(p->numbers[i + 1]), Float(p->numbers[i + 2])};
        try {
            v.push_back(rgb_unbounded_spectrum(c));
        } catch (const Error& e) {
            throw_error(p->loc, "\"rgb {}\" value {}: {}", name, i / 3, e.message());
        }
    }
    return make_grid(std::move(v), n);
}

RgbGridMedium make_rgb_grid(const MediumDesc& d) {
    const ParamSet& ps = d.params;
    RgbGridMedium m;
    size_t count = 0;
    std::string first;
    for (const char* name : {"sigma_a", "sigma_s", "Le"}) {
        const Param* p = ps.find(name);
        if (!p) continue;
        if (p->type != ParamType::Rgb || p->numbers.size() % 3 != 0)
            throw_error(p->loc, "\"{}\" of an rgbgrid medium must be \"rgb\" values", name);
        size_t c = p->numbers.size() / 3;
        if (count == 0) {
            count = c;
            first = name;
        } else if (c != count) {
            throw_error(p->loc, "\"{}\" has {} values but \"{}\" has {}", name, c, first, count);
        }
    }
    if (count == 0)
        throw_error(d.loc, "an rgbgrid medium needs \"rgb sigma_a\" or \"rgb sigma_s\"");
    if (ps.find("Le") && !ps.find("sigma_a"))
        throw_error(ps.find("Le")->loc, "an rgbgrid medium with \"Le\" needs \"sigma_a\"");
    auto n = grid_size(ps, count, d.loc, fmt::format("\"{}\"", first));
    m.sigma_a = rgb_grid(ps, "sigma_a", n);
    m.sigma_s = rgb_grid(ps, "sigma_s", n);
    m.le = rgb_grid(ps, "Le", n);
    m.illuminant = srgb_illuminant();
    grid_bounds(ps, d.loc, m.p0, m.p1);
    m.le_scale = nonnegative(ps, "Lescale", 1);
    m.g = hg_g(ps);
    m.scale = nonnegative(ps, "scale", 1);
    m.medium_from_world = affine_of(d.world_from_medium.inverse());
    build_majorants(m);
    return m;
}

Float finite_param(const ParamSet& ps, std::string_view name, Float def) {
    Float v = ps.get_float(name, def);
    if (!std::isfinite(v)) throw_error(ps.find(name)->loc, "\"{}\" must be finite, got {}", name, v);
    return v;
}

/// pbrt-v4's CloudMedium::Create: no "scale" and no emission (pbrt-v4 reads neither).
CloudMedium make_cloud(const MediumDesc& d, const std::string& base_dir) {
    const ParamSet& ps = d.params;
    CloudMedium m;
    m.density = finite_param(ps, "density", 1);
    m.g = hg_g(ps);
    m.wispiness = finite_param(ps, "wispiness", 1);
    m.frequency = finite_param(ps, "frequency", 5);
    m.sigma_a = coefficient_param(ps, "sigma_a", 1, base_dir);
    m.sigma_s = coefficient_param(ps, "sigma_s", 1, base_dir);
    grid_bounds(ps, d.loc, m.p0, m.p1);
    m.medium_from_world = affine_of(d.world_from_medium.inverse());
    build_majorants(m);
    return m;
}

/// pbrt-v4's NanoVDBMedium::Create: the "density" grid (or "gridname") and the optional
/// "temperature" grid (or "temperaturename") of the file.
NanoVdbMedium make_nanovdb(const MediumDesc& d, const std::string& base_dir) {
    const ParamSet& ps = d.params;
    NanoVdbMedium m;
    std::string file = ps.get_string("filename", "");
    if (file.empty()) throw_error(d.loc, "a \"nanovdb\" medium needs \"string filename\"");
    std::string density_name = ps.get_string("gridname", "density");
    std::string temperature_name = ps.get_string("temperaturename", "temperature");
    NanoVdbFile f;
    try {
        f = NanoVdbFile::read(resolve_path(base_dir, file), density_name, temperature_name,
                              kMaxNanoVdbFileBytes);
    } catch (const Error& e) {
        throw_error(d.loc, "{}", e.what());
    }
    m.density = std::move(f.density);
    m.temperature = std::move(f.temperature);
    m.le_scale = nonnegative(ps, "Lescale", 1);
    m.temperature_offset =
        finite_param(ps, "temperatureoffset", finite_param(ps, "temperaturecutoff", 0));
    m.temperature_scale = finite_param(ps, "temperaturescale", 1);
    m.g = hg_g(ps);
    m.sigma_a = coefficient_param(ps, "sigma_a", 1, base_dir);
    m.sigma_s = coefficient_param(ps, "sigma_s", 1, base_dir);
    m.scale = nonnegative(ps, "scale", 1);
    // Bounds: the density's, with the temperature's (pbrt-v4).
    m.p0 = m.density->world_min(), m.p1 = m.density->world_max();
    if (m.temperature) {
        m.p0 = vmin(m.p0, m.temperature->world_min());
        m.p1 = vmax(m.p1, m.temperature->world_max());
    }
    m.medium_from_world = affine_of(d.world_from_medium.inverse());
    build_majorants(m);
    return m;
}

}  // namespace

void Builder::build_media() {
    for (const MediumDesc& d : m_d.media) {
        std::string what = fmt::format("MakeNamedMedium \"{}\" (\"{}\")", d.name, d.type);
        check_transform(d.world_from_medium, d.loc, what);
        Medium m;
        bool ok = recorded([&] {
            if (d.type == "homogeneous")
                m = make_homogeneous(d, m_d.base_dir);
            else if (d.type == "uniformgrid")
                m = make_uniform_grid(d, m_d.base_dir);
            else if (d.type == "rgbgrid")
                m = make_rgb_grid(d);
            else if (d.type == "cloud")
                m = make_cloud(d, m_d.base_dir);
            else if (d.type == "nanovdb")
                m = make_nanovdb(d, m_d.base_dir);
            else
                throw_error(d.loc, "unknown medium type \"{}\"", d.type);
            d.params.check_unused(what);
        });
        if (!ok) continue;
        m_medium_index[d.name] = int(m_s.media.size());
        m_s.media.push_back(std::move(m));
    }
    // "path" renders media too, with volpath's estimator: pbrt-v4's PathIntegrator ignores
    // them (with a warning), which leaves a physically wrong image (docs/pbrt-support.md).
    if (!m_s.media.empty()) use_volumetric_kernel("participating media", "ignores them");
    m_s.camera_medium = medium_index(m_d.camera.medium, m_d.camera.loc);
}

void Builder::use_volumetric_kernel(const std::string& what, const std::string& pbrt_path) {
    const bool bidir = m_s.integrator.type == "bdpt" || m_s.integrator.type == "lightpath" ||
                       m_s.integrator.type == "mlt" || m_s.integrator.type == "vcm";
    if (bidir && what != "participating media") {
        // The bidirectional kernels trace media themselves (integrators/bdpt/, as pbrt-v4's
        // bdpt does, and integrators/vcm/), but not a subsurface material's interior.
        recorded([&] {
            throw_unsupported(m_d.integrator.loc,
                              "Integrator \"{}\": the scene has {}, which the bidirectional "
                              "integrators do not support (use \"volpath\")",
                              m_s.integrator.type, what);
        });
        return;
    }
    // (With a bidirectional integrator the volumetric kernel still serves what runs the path
    // kernel on the scene: meters.)
    if (!m_volpath && !bidir)
        warning(m_d.integrator.loc,
                fmt::format("the scene has {}: steradian's \"path\" renders them (as "
                            "\"volpath\"), where pbrt-v4's {}",
                            what, pbrt_path));
    if (m_s.integrator.volumetric) return;  // the checks below are made
    m_s.integrator.volumetric = true;
    recorded([&] {
        if (m_s.integrator.strategy != LightStrategy::Mis)
            throw_unsupported(m_d.integrator.loc,
                              "\"strategy\" other than \"mis\" is not supported yet in a "
                              "scene with {}",
                              what);
    });
}

int Builder::medium_index(const std::string& name, const SourceLoc& loc) const {
    if (name.empty()) return -1;
    auto it = m_medium_index.find(name);
    if (it != m_medium_index.end()) return it->second;
    for (const MediumDesc& d : m_d.media)
        if (d.name == name) return -1;  // left out (recorded as unsupported)
    throw_error(loc, "medium \"{}\" is not defined (no MakeNamedMedium \"{}\")", name, name);
}

}  // namespace sr::build_detail
