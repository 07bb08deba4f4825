/// Light sources (point, spot, distant, infinite) and the area lights of shapes.
#include <cmath>

#include "steradian/sampling/warp.h"
#include "steradian/scene/build/builder.h"

namespace sr::build_detail {

std::shared_ptr<const EnvironmentMap> Builder::environment_map(const std::string& path,
                                                               const SourceLoc& loc,
                                                               const std::string& what) {
    Image img;
    try {
        img = read_image(path, true);  // 8-bit formats are sRGB-encoded, float ones linear
    } catch (const Error& e) {
        throw_error(loc, "{}: {}", what, e.what());
    }
    if (img.channels < 3)
        throw_error(loc, "{}: \"{}\" has {} channel(s); an environment map needs R, G and B",
                    what, path, img.channels);
    std::vector<float> rgb(size_t(img.width) * size_t(img.height) * 3);
    for (size_t i = 0; i < size_t(img.width) * size_t(img.height); ++i)
        for (size_t c = 0; c < 3; ++c) rgb[i * 3 + c] = img.data[i * size_t(img.channels) + c];
    try {
        return make_environment_map(rgb, img.width, img.height);
    } catch (const Error& e) {
        throw_error(loc, "{}: \"{}\": {}", what, path, e.what());
    }
}

// ---- lights (after geometry: distant and infinite lights need the bounds) --------
void Builder::build_lights(Scene& s) {
    Point3 center = s.bounds.empty() ? Point3(0, 0, 0) : s.bounds.center();
    Float radius = s.bounds.empty() ? 1 : std::max(Float(1e-3), length(s.bounds.diagonal()) / 2);
    // A light whose power overflows a float (large values multiplied together) would put
    // infinities and NaNs into the image and the meters; it is an error at its directive.
    auto check_power = [&](size_t first, const SourceLoc& loc) {
        for (size_t k = first; k < s.lights.size(); ++k)
            if (!std::isfinite(light_phi_y(s.lights[k])))
                throw_error(loc,
                            "the light's emitted power overflows a 32-bit float: its "
                            "intensity, scale, power or size is too large");
    };
    for (size_t i = 0; i < m_d.lights.size(); ++i) {
        if (m_failed_light[i]) continue;  // already recorded
        size_t first = s.lights.size();
        if (auto it = m_luminaires.find(i); it != m_luminaires.end())
            add_luminaire(s, it->second);
        else
            recorded([&] { add_light(s, m_d.lights[i], center, radius); });
        check_power(first, m_d.lights[i].loc);
        // Lights at infinity emit in vacuum (pbrt-v4's infinite and distant lights' rays
        // have no medium); the others in the outside medium at their directive. (A
        // luminaire's opening is an emitting shape: add_emitting_primitives sets its media.)
        const Light* l0 = first < s.lights.size() ? &s.lights[first] : nullptr;
        const bool at_infinity = l0 && (std::holds_alternative<DistantLight>(*l0) ||
                                        std::holds_alternative<UniformInfiniteLight>(*l0) ||
                                        std::holds_alternative<ImageInfiniteLight>(*l0));
        int medium = -1;
        if (!at_infinity && first < s.lights.size())
            recorded([&] { medium = medium_index(m_d.lights[i].medium, m_d.lights[i].loc); });
        s.light_media.resize(s.lights.size(), Scene::LightMedia{medium, medium});
    }
    for (const auto& pending : m_pending_area) {
        // Named members, not a structured binding: clang 14 cannot capture a binding in a lambda.
        const auto& shape = pending.first;
        const size_t al = pending.second;
        size_t first = s.lights.size();
        recorded([&] { add_area_light(s, shape, m_d.area_lights[al]); });
        check_power(first, m_d.area_lights[al].loc);
    }
}

Spectrum Builder::illum_param(const ParamSet& ps, std::string_view name) {
    if (const Param* p = ps.find_spectrum(name))
        return spectrum_from_param(*p, SpectrumKind::Illuminant, m_d.base_dir);
    return srgb_illuminant();
}

/// pbrt-v4's SpectrumToPhotometric of a light spectrum as given in the file: for RGB
/// illuminants only the colour space's illuminant counts, so an "rgb L" of (4, 4, 4) is
/// four times as bright as (1, 1, 1). Must be called before densely_sampled().
Float Builder::photometric_or_fail(const Spectrum& s, const SourceLoc& loc) {
    Float y = spectrum_to_photometric(s);
    if (!(y > 0)) throw_error(loc, "the light's spectrum has no visible (V(lambda)) content");
    return y;
}

void Builder::add_light(Scene& s, const LightDesc& l, Point3 center, Float radius) {
    const ParamSet& ps = l.params;
    std::string what = fmt::format("LightSource \"{}\"", l.type);
    const Transform& x = l.world_from_light;
    check_transform(x, l.loc, what);
    if (l.type == "point" || l.type == "spot" || l.type == "goniometric") {
        // ("from" is a parameter of point and spot lights only.)
        Point3 from = l.type == "goniometric" ? Point3(0, 0, 0)
                                              : ps.find_point3("from").value_or(Point3(0, 0, 0));
        check_position(x.point(from), l.loc, "the light");
    }
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
        if (const Param* old = ps.find("conedelta"))
            throw_unsupported(old->loc,
                              "{}: \"conedelta\" is not a pbrt-v4 parameter: the width of "
                              "the cone's falloff is \"conedeltaangle\"",
                              what);
        Float cone = ps.get_float("coneangle", 30), delta = ps.get_float("conedeltaangle", 5);
        sl.cos_falloff_end = std::cos(radians(cone));
        sl.cos_falloff_start = std::cos(radians(cone - delta));
        Float phi = ps.get_float("power", -1);
        if (phi > 0) {
            Float k_e =
                2 * kPi *
                ((1 - sl.cos_falloff_start) + (sl.cos_falloff_start - sl.cos_falloff_end) / 2);
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
    } else if (l.type == "infinite" && (ps.find("filename") || ps.find("portal"))) {
        ImageInfiniteLight il;
        if (ps.find("filename")) {
            if (ps.find_spectrum("L"))
                throw_error(l.loc, "{}: both \"L\" and \"filename\" given; pbrt-v4 takes one",
                            what);
            const std::string file = resolve_path(m_d.base_dir, ps.get_string("filename", ""));
            il.map = environment_map(file, l.loc, what);
        } else {
            // A portal with a constant "L": as pbrt-v4, a 1 x 1 map of L's linear sRGB
            // (its XYZ through the sRGB matrix), normalised as image maps are below.
            const Xyz xyz = spectrum_to_xyz(illum_param(ps, "L"));
            const Rgb c = xyz_to_linear_srgb(xyz);
            try {
                il.map = make_environment_map({c.r, c.g, c.b}, 1, 1);
            } catch (const Error& e) {
                throw_error(l.loc, "{}: {}", what, e.what());
            }
        }
        Float sc = ps.get_float("scale", 1);
        // RGB texels are illuminants of the sRGB white (pbrt-v4 divides by the photometric
        // value of the image's colour space's illuminant).
        sc /= spectrum_to_photometric(Spectrum(srgb_illuminant()));
        Float ev = ps.get_float("illuminance", -1);
        if (ev > 0) {
            // The illuminance of the map on an upward (+z in the light's frame) patch: each
            // texel covers 4 pi / res^2 sr. pbrt-v4 (lights.cpp, "infinite") sums with
            // 2 pi / res^2, which gives twice the requested illuminance; steradian gives
            // the requested value (docs/pbrt-support.md).
            const Float k_e = il.map->upper_illuminance;
            if (!(k_e > 0))
                throw_error(l.loc, "{}: \"illuminance\" given, but the map has no light in its "
                                   "upper hemisphere", what);
            sc *= ev / k_e;
        }
        il.scale = sc;
        il.world_from_light = x;
        il.light_from_world = x.inverse();
        il.scene_center = center;
        il.scene_radius = radius;
        if (const Param* pp = ps.find("portal")) read_portal(il, *pp, ps, what);
        ps.check_unused(what);
        s.infinite_lights.push_back(int(s.lights.size()));
        s.lights.push_back(il);
    } else if (l.type == "infinite") {
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
        throw_unsupported(
            l.loc, "light type \"{}\" is not supported yet (see docs/pbrt-support.md)", l.type);
    }
}

/// pbrt-v4's "point3 portal": four world-space points (not moved by the light's CTM, as in
/// pbrt-v4) of a planar parallelogram; and the luminous flux through it (for the light
/// sampler), A times the integral of Y cos over the directions coming in through it.
void Builder::read_portal(ImageInfiniteLight& il, const Param& p, const ParamSet& ps,
                          const std::string& what) {
    const std::vector<Point3> q = ps.get_point3s("portal");
    if (q.size() != 4)
        throw_error(p.loc, "{}: \"portal\" needs 4 points, not {}", what, q.size());
    InfinitePortal portal;
    portal.p0 = q[0];
    portal.e1 = q[1] - q[0];
    portal.e3 = q[3] - q[0];
    const Vec3 c = cross(portal.e3, portal.e1);
    portal.area = length(c);
    const Float size = std::max(length(portal.e1), length(portal.e3));
    if (!(portal.area > 0) || !std::isfinite(portal.area) ||
        !(portal.area > 1e-6f * size * size))
        throw_error(p.loc, "{}: the \"portal\" points span no area", what);
    portal.n = c / portal.area;
    // pbrt-v4 asks for a planar rectangle; any planar parallelogram is exact here.
    if (length(q[0] + portal.e1 + portal.e3 - q[2]) > 1e-3f * size)
        throw_error(p.loc,
                    "{}: the \"portal\" is not a planar parallelogram (p0 + (p1 - p0) + (p3 - "
                    "p0) must be p2)",
                    what);
    il.portal = portal;
    // Flux through the portal from the map's coarse luminance blocks.
    const EnvironmentMap& m = *il.map;
    const int cr = m.coarse_res;
    double sum = 0;
    for (int by = 0; by < cr; ++by)
        for (int bx = 0; bx < cr; ++bx) {
            const Vec3 w = normalize(il.world_from_light.vector(equal_area_square_to_sphere(
                Point2((Float(bx) + Float(0.5)) / Float(cr), (Float(by) + Float(0.5)) / Float(cr)))));
            const Float cosine = dot(w, portal.n);
            if (cosine > 0) sum += double(m.coarse_y[size_t(by) * size_t(cr) + size_t(bx)]) * cosine;
        }
    const double texel_sr = 4 * kPi / (double(m.res) * double(m.res));
    il.portal_phi_y = Float(double(portal.area) * sum * texel_sr * il.scale *
                            spectrum_to_photometric(m.illuminant));
}

void Builder::add_area_light(Scene& s, int shape_index, const AreaLightDesc& a) {
    if (a.type != "diffuse")
        throw_unsupported(a.loc, "area light type \"{}\" is not supported yet", a.type);
    const ParamSet& ps = a.params;
    if (ps.find("filename"))
        throw_unsupported(a.loc, "image-textured area lights (\"filename\") are not supported yet");
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

}  // namespace sr::build_detail
