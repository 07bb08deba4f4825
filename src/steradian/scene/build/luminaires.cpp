/// Photometric luminaires: goniometric lights from IES/LDT files or equal-area images.
#include "steradian/film/image_io.h"
#include "steradian/lights/photometric/eulumdat.h"
#include "steradian/lights/photometric/ies.h"
#include "steradian/scene/build/builder.h"

namespace sr::build_detail {

/// ".ies", ".ldt", ... in lower case.
std::string Builder::lower_extension(const std::string& f) {
    std::string ext = std::filesystem::path(f).extension().string();
    for (char& c : ext) c = char(std::tolower(static_cast<unsigned char>(c)));
    return ext;
}

void Builder::build_luminaires() {
    m_failed_light.assign(m_d.lights.size(), false);
    for (size_t i = 0; i < m_d.lights.size(); ++i) {
        const LightDesc& l = m_d.lights[i];
        if (l.type != "goniometric") continue;
        m_failed_light[i] = !recorded([&] {
            Luminaire lum = make_luminaire(l);
            m_luminaires[i] = std::move(lum);
        });
    }
}

Builder::Luminaire Builder::make_luminaire(const LightDesc& l) {
    const ParamSet& ps = l.params;
    const std::string what = "LightSource \"goniometric\"";
    std::optional<std::string> file = ps.find_string("filename");
    if (!file)
        throw_error(l.loc, "{}: needs \"string filename\" (an .ies or .ldt photometric file)",
                    what);
    const std::string ext = lower_extension(*file);
    std::string path = resolve_path(m_d.base_dir, *file);
    if (ext != ".ies" && ext != ".ldt") return make_image_goniometric(l, path, *file);
    std::shared_ptr<PhotometricData> data;
    try {
        data = std::make_shared<PhotometricData>(ext == ".ldt" ? read_eulumdat(path)
                                                               : read_ies(path));
    } catch (const Error& e) {
        if (!e.loc().file.empty()) throw;  // located in the photometric file itself
        throw_error(ps.find("filename")->loc, "{}: {}", what, e.what());
    }
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
                    "{}: \"emission\" must be \"auto\", \"point\" or \"area\", not \"{}\"", what,
                    emission);
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
        TriangleMesh m = make_mesh(
            sd, {Point3(-hx, -hy, 0), Point3(hx, -hy, 0), Point3(hx, hy, 0), Point3(-hx, hy, 0)},
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
Builder::Luminaire Builder::make_image_goniometric(const LightDesc& l, const std::string& path,
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
        if (!(mean > 0))
            throw_error(l.loc, "{}: \"{}\" is black; \"power\" cannot be met", what, file);
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

void Builder::add_luminaire(Scene& s, const Luminaire& lum) {
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

}  // namespace sr::build_detail
