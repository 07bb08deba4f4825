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
    const LuminousShape shape = data->shape;
    const bool has_opening = shape != LuminousShape::Point && shape != LuminousShape::Unknown;
    if (emission == "area" && !has_opening)
        throw_error(l.loc,
                    "{}: \"emission\" \"area\" needs a luminous opening; \"{}\" has {}", what,
                    *file, to_string(shape));
    if (emission != "point" && shape == LuminousShape::Unknown)
        warning(l.loc, fmt::format("{}: the luminous opening of \"{}\" has an unknown sign "
                                   "pattern of width, length and height; it is emitted from "
                                   "its photometric centre (point form)",
                                   what, *file));
    if (emission == "point" || !has_opening) {
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
    // Half-extents along the luminaire frame's axes: length along the photometric
    // horizontal (x), width along C90 (y), height along z (LM-63-2019's table of shapes).
    const Float hx = Float(data->length / 2), hy = Float(data->width / 2),
                hz = Float(data->height / 2);
    if (shape == LuminousShape::Sphere) {
        Sphere sp;
        sp.world_from_object = world_from_light;
        sp.radius = Float(data->width / 2);
        sp.z_min = -sp.radius;
        sp.z_max = sp.radius;
        sp.theta_z_min = 0;
        sp.theta_z_max = kPi;
        sp.flip_normals = world_from_light.swaps_handedness();
        em->body = LuminousBody::Sphere;
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
        LuminousMesh lm = luminous_mesh(shape, hx, hy, hz);
        ShapeDesc sd;
        sd.type = "luminous opening";
        sd.loc = l.loc;
        sd.world_from_object = world_from_light;
        em->body = lm.flat ? LuminousBody::Flat : LuminousBody::Convex;
        em->flat_normal = lm.flat_normal;
        em->face_areas = std::move(lm.face_areas);
        TriangleMesh m = make_mesh(sd, std::move(lm.p), {}, {}, std::move(lm.idx));
        em->opening_area = 0;
        for (size_t t = 0; t < m.num_triangles(); ++t) em->opening_area += m.triangle_area(t);
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

Builder::LuminousMesh Builder::luminous_mesh(LuminousShape shape, Float hx, Float hy, Float hz) {
    LuminousMesh lm;
    auto ellipse = [](int n, auto&& at) {  // n points around, counterclockwise
        for (int k = 0; k < n; ++k) {
            const Float phi = 2 * kPi * Float(k) / Float(n);
            at(std::cos(phi), std::sin(phi));
        }
    };
    // A flat ellipse (semi-axes a, b along the unit axes ea, eb): a fan around its centre.
    auto flat_ellipse = [&](Float a, Vec3 ea, Float b, Vec3 eb) {
        lm.flat = true;
        lm.flat_normal = cross(ea, eb);
        lm.p.push_back(Point3(0, 0, 0));
        ellipse(kEllipseSegments, [&](Float c, Float s) {
            lm.p.push_back(Point3(0, 0, 0) + ea * (a * c) + eb * (b * s));
        });
        for (int k = 0; k < kEllipseSegments; ++k)
            lm.idx.insert(lm.idx.end(), {0, 1 + k, 1 + (k + 1) % kEllipseSegments});
    };
    // A cylinder along the unit axis ez (half-length h) with elliptical section (a along
    // ea, b along eb): its side as quads, its two ends as fans.
    auto cylinder = [&](Float h, Vec3 ez, Float a, Vec3 ea, Float b, Vec3 eb) {
        const int n = kEllipseSegments;
        for (int side = -1; side <= 1; side += 2) {
            lm.p.push_back(Point3(0, 0, 0) + ez * (Float(side) * h));
            ellipse(n, [&](Float c, Float s) {
                lm.p.push_back(Point3(0, 0, 0) + ez * (Float(side) * h) + ea * (a * c) + eb * (b * s));
            });
        }
        const int top = n + 1;  // index of the second end's centre
        for (int k = 0; k < n; ++k) {
            const int k1 = (k + 1) % n;
            lm.idx.insert(lm.idx.end(), {0, 1 + k, 1 + k1});
            lm.idx.insert(lm.idx.end(), {top, top + 1 + k, top + 1 + k1});
            lm.idx.insert(lm.idx.end(), {1 + k, 1 + k1, top + 1 + k1});
            lm.idx.insert(lm.idx.end(), {1 + k, top + 1 + k1, top + 1 + k});
        }
    };
    const Vec3 ex(1, 0, 0), ey(0, 1, 0), ez(0, 0, 1);
    switch (shape) {
        case LuminousShape::Rectangular:
            lm.flat = true;
            lm.p = {Point3(-hx, -hy, 0), Point3(hx, -hy, 0), Point3(hx, hy, 0), Point3(-hx, hy, 0)};
            lm.idx = {0, 2, 1, 0, 3, 2};
            break;
        case LuminousShape::Elliptical: flat_ellipse(hx, ex, hy, ey); break;
        case LuminousShape::VerticalCircleFacingHorizontal:
        case LuminousShape::VerticalEllipseFacingHorizontal: flat_ellipse(hy, ey, hz, ez); break;
        case LuminousShape::VerticalCirclePerpendicular:
        case LuminousShape::VerticalEllipsePerpendicular: flat_ellipse(hx, ex, hz, ez); break;
        case LuminousShape::RectangularWithLuminousSides:
            for (int k = 0; k < 8; ++k)
                lm.p.push_back(Point3((k & 1) ? hx : -hx, (k & 2) ? hy : -hy, (k & 4) ? hz : -hz));
            lm.idx = {0, 1, 3, 0, 3, 2, 4, 5, 7, 4, 7, 6, 0, 1, 5, 0, 5, 4,
                      2, 3, 7, 2, 7, 6, 0, 2, 6, 0, 6, 4, 1, 3, 7, 1, 7, 5};
            break;
        case LuminousShape::VerticalCylinder:
        case LuminousShape::VerticalEllipticalCylinder: cylinder(hz, ez, hx, ex, hy, ey); break;
        case LuminousShape::HorizontalCylinderAlong:
        case LuminousShape::HorizontalEllipticalCylinderAlong: cylinder(hx, ex, hy, ey, hz, ez); break;
        case LuminousShape::HorizontalCylinderPerpendicular:
        case LuminousShape::HorizontalEllipticalCylinderPerpendicular:
            cylinder(hy, ey, hz, ez, hx, ex);
            break;
        case LuminousShape::Ellipsoid: {
            // Rings of constant latitude between two poles.
            const int rings = kEllipsoidRings, n = kEllipseSegments;
            lm.p.push_back(Point3(0, 0, -hz));
            for (int r = 1; r < rings; ++r) {
                const Float theta = kPi * Float(r) / Float(rings);
                const Float z = -std::cos(theta), rho = std::sin(theta);
                ellipse(n, [&](Float c, Float s) {
                    lm.p.push_back(Point3(hx * rho * c, hy * rho * s, hz * z));
                });
            }
            lm.p.push_back(Point3(0, 0, hz));
            const int last = int(lm.p.size()) - 1;
            auto ring = [&](int r, int k) { return 1 + (r - 1) * n + (k % n); };
            for (int k = 0; k < n; ++k) {
                lm.idx.insert(lm.idx.end(), {0, ring(1, k), ring(1, k + 1)});
                lm.idx.insert(lm.idx.end(), {last, ring(rings - 1, k), ring(rings - 1, k + 1)});
                for (int r = 1; r + 1 < rings; ++r) {
                    lm.idx.insert(lm.idx.end(), {ring(r, k), ring(r, k + 1), ring(r + 1, k + 1)});
                    lm.idx.insert(lm.idx.end(), {ring(r, k), ring(r + 1, k + 1), ring(r + 1, k)});
                }
            }
            break;
        }
        default: break;  // Point, Circular, Sphere and Unknown are not meshes
    }
    // Orient every triangle: a flat figure's against flat_normal (a horizontal one faces
    // nadir, as the disk does; both faces emit), a convex body's outwards (the body is
    // centred on the origin, so outwards is where the centroid points).
    for (size_t t = 0; t + 2 < lm.idx.size(); t += 3) {
        const Point3 a = lm.p[size_t(lm.idx[t])], b = lm.p[size_t(lm.idx[t + 1])],
                     c = lm.p[size_t(lm.idx[t + 2])];
        const Vec3 n = cross(b - a, c - a);
        const Vec3 out = lm.flat ? -lm.flat_normal : (a - Point3(0, 0, 0)) + (b - Point3(0, 0, 0)) +
                                                        (c - Point3(0, 0, 0));
        if (dot(n, out) < 0) std::swap(lm.idx[t + 1], lm.idx[t + 2]);
        if (lm.flat) continue;
        // The body's area vectors, one per face plane (coplanar triangles merged), for its
        // projected area 1/2 sum |A_i n_i . w|.
        const Vec3 av = (dot(n, out) < 0 ? -n : n) / 2;
        const Float len = length(av);
        if (!(len > 0)) continue;
        bool merged = false;
        for (Vec3& f : lm.face_areas) {
            if (dot(f, av) > Float(0.999999) * length(f) * len) {
                f = f + av;
                merged = true;
                break;
            }
        }
        if (!merged) lm.face_areas.push_back(av);
    }
    return lm;
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
