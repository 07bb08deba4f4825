/// Shapes: triangle, PLY and bilinear meshes, spheres and disks, and object instances.
#include <map>

#include "steradian/scene/build/builder.h"

#include "steradian/geometry/loop_subdivision.h"
#include "steradian/scene/mesh_io/ply.h"

namespace sr::build_detail {

std::shared_ptr<std::vector<Point3>> Builder::padded_positions(std::vector<Point3> p) {
    p.push_back(Point3(0, 0, 0));  // Embree reads up to 16 bytes past the last vertex
    return std::make_shared<std::vector<Point3>>(std::move(p));
}

TriangleMesh Builder::make_mesh(const ShapeDesc& s, std::vector<Point3> p, std::vector<Normal3> n,
                                std::vector<Point2> uv, std::vector<int> idx) {
    for (int i : idx)
        if (i < 0 || size_t(i) >= p.size())
            throw_error(s.loc, "Shape \"{}\": vertex index {} out of range (there are {} vertices)",
                        s.type, i, p.size());
    return make_mesh_u32(s, std::move(p), std::move(n), std::move(uv),
                         std::vector<uint32_t>(idx.begin(), idx.end()));
}

TriangleMesh Builder::make_mesh_u32(const ShapeDesc& s, std::vector<Point3> p,
                                    std::vector<Normal3> n, std::vector<Point2> uv,
                                    std::vector<uint32_t> idx) {
    const Transform& x = s.world_from_object;
    const size_t nv = p.size();
    for (uint32_t i : idx)
        if (i >= nv)
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
    // The arrays are moved, not copied (a PLY reader's positions have room for the padding).
    m.p = padded_positions(std::move(p));
    m.n = std::make_shared<std::vector<Normal3>>(std::move(n));
    m.uv = std::make_shared<std::vector<Point2>>(std::move(uv));
    m.indices = std::make_shared<std::vector<uint32_t>>(std::move(idx));
    m.flip_normals = s.reverse_orientation != x.swaps_handedness();
    return m;
}

std::optional<ShapeGeometry> Builder::make_geometry(const ShapeDesc& s) {
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
            throw_unsupported(s.loc, "{}: \"displacement\" is not supported yet", what);
        ps.get_float("edgelength", 1);
        check_alpha(s);
        ps.check_unused(what);
        TriangleMeshData d;
        try {
            d = read_ply(resolve_path(m_d.base_dir, file));
        } catch (const Error& e) {
            throw_error(s.loc, "{}", e.what());
        }
        return make_mesh_u32(s, std::move(d.p), std::move(d.n), std::move(d.uv),
                             std::move(d.indices));
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
    if (s.type == "loopsubdiv") {
        // pbrt-v4's LoopSubdivide: "levels" (3), "indices", "P"; the limit surface with its
        // normals as a triangle mesh.
        auto p = ps.get_point3s("P");
        auto idx = ps.get_ints("indices");
        const int levels = ps.get_int("levels", 3);
        if (p.empty()) throw_error(s.loc, "{}: \"P\" is required", what);
        if (levels < 0 || levels > 12)
            throw_error(s.loc, "{}: \"levels\" must be from 0 to 12, is {}", what, levels);
        check_alpha(s);
        ps.check_unused(what);
        SubdividedMesh m;
        try {
            m = loop_subdivide(p, idx, levels);
        } catch (const Error& e) {
            throw_error(s.loc, "{}: {}", what, e.what());
        }
        return make_mesh(s, std::move(m.p), std::move(m.n), {}, std::move(m.indices));
    }
    if (s.type == "cylinder") {
        // pbrt-v4's Cylinder::Create: radius 1, zmin -1, zmax 1, phimax 360.
        Cylinder c;
        c.world_from_object = s.world_from_object;
        c.radius = ps.get_float("radius", 1);
        if (!(c.radius > 0)) throw_error(s.loc, "{}: radius must be positive", what);
        const Float zmin = ps.get_float("zmin", -1), zmax = ps.get_float("zmax", 1);
        c.z_min = std::min(zmin, zmax);
        c.z_max = std::max(zmin, zmax);
        if (!(c.z_max > c.z_min)) throw_error(s.loc, "{}: zmin and zmax must differ", what);
        c.phi_max = radians(clamp(ps.get_float("phimax", 360), Float(0), Float(360)));
        c.flip_normals = s.reverse_orientation != s.world_from_object.swaps_handedness();
        check_alpha(s);
        ps.check_unused(what);
        return c;
    }
    if (s.type == "curve") return make_curves(s);
    throw_unsupported(s.loc, "shape type \"{}\" is not supported yet (see docs/pbrt-support.md)",
                      s.type);
}

/// pbrt-v4's Curve::Create: "P", "basis" (bezier), "degree" (3), "type" (flat), "N" (ribbons
/// only), "width" (1), "width0" and "width1" (width), "splitdepth" (3; pbrt-v4's own
/// subdivision, which Embree does not need). Every input segment becomes a cubic Bézier
/// segment; the width varies linearly from width0 to width1 over the whole curve.
ShapeGeometry Builder::make_curves(const ShapeDesc& s) {
    const ParamSet& ps = s.params;
    const std::string what = "Shape \"curve\"";
    auto at = [&](std::string_view name) {
        const Param* p = ps.find(name);
        return p ? p->loc : s.loc;
    };
    const Float width = ps.get_float("width", 1);
    const Float width0 = ps.get_float("width0", width), width1 = ps.get_float("width1", width);
    const std::pair<const char*, Float> widths[] = {
        {"width", width}, {"width0", width0}, {"width1", width1}};
    for (const auto& [name, w] : widths)
        if (!(w >= 0) || !std::isfinite(w))
            throw_error(at(name), "{}: \"{}\" must be a finite width >= 0, is {}", what, name, w);
    const int degree = ps.get_int("degree", 3);
    if (degree != 2 && degree != 3)
        throw_error(at("degree"), "{}: \"degree\" must be 2 or 3, is {}", what, degree);
    const std::string basis = ps.get_string("basis", "bezier");
    if (basis != "bezier" && basis != "bspline")
        throw_error(at("basis"), "{}: \"basis\" must be \"bezier\" or \"bspline\", is \"{}\"",
                    what, basis);
    const std::string type_name = ps.get_string("type", "flat");
    Curves c;
    if (type_name == "flat")
        c.type = CurveType::Flat;
    else if (type_name == "cylinder")
        c.type = CurveType::Cylinder;
    else if (type_name == "ribbon")
        c.type = CurveType::Ribbon;
    else
        throw_error(at("type"),
                    "{}: \"type\" must be \"flat\", \"cylinder\" or \"ribbon\", is \"{}\"", what,
                    type_name);
    const std::vector<Point3> p = ps.get_point3s("P");
    const size_t np = p.size(), deg = size_t(degree);
    size_t segments = 0;
    if (basis == "bezier") {
        // degree + 1 points for the first segment, degree more for each further one.
        if (np < deg + 1 || (np - 1) % deg != 0)
            throw_error(at("P"),
                        "{}: a degree-{} Bézier curve needs {} + {} n control points (n >= 0), "
                        "\"P\" has {}",
                        what, degree, deg + 1, deg, np);
        segments = (np - 1) / deg;
    } else {
        if (np < deg + 1)
            throw_error(at("P"), "{}: a degree-{} B-spline needs at least {} control points, "
                        "\"P\" has {}",
                        what, degree, deg + 1, np);
        segments = np - deg;
    }
    std::vector<Normal3> n = ps.get_normals("N");
    if (c.type != CurveType::Ribbon && !n.empty()) {
        warning(at("N"), fmt::format("{}: \"N\" is used only by \"ribbon\" curves (ignored, as "
                                     "in pbrt-v4)",
                                     what));
        n.clear();
    }
    if (c.type == CurveType::Ribbon && n.size() != segments + 1)
        throw_error(at("N"), "{}: a ribbon with {} segments needs {} normals \"N\", has {}", what,
                    segments, segments + 1, n.size());
    ps.get_int("splitdepth", 3);
    check_alpha(s);
    ps.check_unused(what);

    const Transform& x = s.world_from_object;
    for (const Point3& q : p)
        if (!std::isfinite(q.x) || !std::isfinite(q.y) || !std::isfinite(q.z))
            throw_error(at("P"), "{}: non-finite control point", what);
    // Widths are in object space: scaled by the transform's mean linear scale (exact for
    // rigid motions and uniform scales).
    const auto& m = x.matrix().m;
    const double det = m[0][0] * (m[1][1] * m[2][2] - m[1][2] * m[2][1]) -
                       m[0][1] * (m[1][0] * m[2][2] - m[1][2] * m[2][0]) +
                       m[0][2] * (m[1][0] * m[2][1] - m[1][1] * m[2][0]);
    const Float scale = Float(std::cbrt(std::abs(det)));
    c.cp = std::make_shared<std::vector<CurvePoint>>();
    c.first = std::make_shared<std::vector<uint32_t>>();
    c.cp->reserve(4 * segments);
    for (size_t i = 0; i < segments; ++i) {
        std::array<Point3, 4> b;
        if (basis == "bezier") {
            const size_t o = i * deg;
            b = degree == 3 ? std::array<Point3, 4>{p[o], p[o + 1], p[o + 2], p[o + 3]}
                            : elevate_quadratic_bezier(std::span<const Point3, 3>(&p[o], 3));
        } else if (degree == 3) {
            b = cubic_bspline_to_bezier(std::span<const Point3, 4>(&p[i], 4));
        } else {
            const auto q = quadratic_bspline_to_bezier(std::span<const Point3, 3>(&p[i], 3));
            b = elevate_quadratic_bezier(q);
        }
        const Float wa = lerp(Float(i) / Float(segments), width0, width1);
        const Float wb = lerp(Float(i + 1) / Float(segments), width0, width1);
        c.first->push_back(uint32_t(c.cp->size()));
        for (int k = 0; k < 4; ++k) {
            const Point3 w = x.point(b[k]);
            c.cp->push_back({w.x, w.y, w.z, Float(0.5) * scale * lerp(Float(k) / 3, wa, wb)});
        }
    }
    if (c.type == CurveType::Ribbon) {
        c.end_normals = std::make_shared<std::vector<Normal3>>();
        c.embree_normals = std::make_shared<std::vector<Normal3>>();
        for (Normal3& v : n) {
            const Vec3 w = x.normal(v);
            if (!(length_squared(w) > 0) || !std::isfinite(length_squared(w)))
                throw_error(at("N"), "{}: \"N\" holds a zero or non-finite normal", what);
            v = normalize(w);
        }
        for (size_t i = 0; i < segments; ++i) {
            c.end_normals->insert(c.end_normals->end(), {n[i], n[i + 1]});
            for (int k = 0; k < 4; ++k)
                c.embree_normals->push_back(slerp_normal(n[i], n[i + 1], Float(k) / 3));
        }
        c.embree_normals->push_back(Normal3(0, 0, 0));  // Embree reads 16 bytes at a time
    }
    c.flip_normals = s.reverse_orientation != x.swaps_handedness();
    return c;
}

void Builder::check_alpha(const ShapeDesc& s) {
    // Read (so marked used) here; the mask is made by add_shape (alpha_mask()).
    s.params.find("alpha");
}

namespace {

/// A shape's "alpha" float texture as the acceleration structure's cut-out mask.
struct TextureAlphaMask final : AlphaMask {
    std::shared_ptr<const FloatTexture> texture;
    Float alpha(const SurfaceHit& hit) const override { return evaluate(*texture, hit); }
};

}  // namespace

std::shared_ptr<const AlphaMask> Builder::alpha_mask(const ShapeDesc& s) {
    const Param* a = s.params.find("alpha");
    if (!a || (a->type == ParamType::Float && a->numbers.size() == 1 && a->numbers[0] == 1))
        return nullptr;  // opaque, as pbrt-v4 makes an alpha of constant 1
    if (a->type == ParamType::Float && (a->numbers.size() != 1 || !std::isfinite(a->numbers[0])))
        throw_error(a->loc, "\"alpha\" takes one number or a float texture");
    auto mask = std::make_shared<TextureAlphaMask>();
    mask->texture = float_tex_arg(s.params, "alpha", 1);
    return mask;
}

ShapeGeometry Builder::make_bilinear(const ShapeDesc& s) {
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
    // One normal and uv per vertex: the tessellation below reads them by vertex index.
    if (!n.empty() && n.size() != p.size())
        throw_error(s.loc, "Shape \"bilinearmesh\": {} normals for {} vertices", n.size(),
                    p.size());
    if (!uv.empty() && uv.size() != p.size())
        throw_error(s.loc, "Shape \"bilinearmesh\": {} uvs for {} vertices", uv.size(), p.size());
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

namespace {

/// Throws at the shape unless all of it lies within kMaxCoordinate: beyond it Embree cannot
/// trace the rays that leave it (a sphere of radius 1e20 around the camera disappeared from
/// the image). Meshes: every vertex; spheres and disks: the corners of their object boxes.
void check_extent(const ShapeGeometry& g, const ShapeDesc& s) {
    const std::string what = fmt::format("Shape \"{}\"", s.type);
    // The messages are made once, not per vertex (a 10M-triangle mesh's 5M strings cost
    // 0.15 CPU-s).
    auto corners = [&](const Transform& x, Float r, Float z0, Float z1) {
        const std::string point = what + ": a point of it";
        for (Float cx : {-r, r})
            for (Float cy : {-r, r})
                for (Float cz : {z0, z1}) check_position(x.point(Point3(cx, cy, cz)), s.loc, point);
    };
    if (const auto* mesh = std::get_if<TriangleMesh>(&g)) {
        const std::string vertex = what + ": a vertex";
        for (const Point3& p : *mesh->p) check_position(p, s.loc, vertex);
    } else if (const auto* sp = std::get_if<Sphere>(&g)) {
        corners(sp->world_from_object, sp->radius, -sp->radius, sp->radius);
    } else if (const auto* d = std::get_if<Disk>(&g)) {
        corners(d->world_from_object, d->radius, d->height, d->height);
    } else if (const auto* c = std::get_if<Cylinder>(&g)) {
        corners(c->world_from_object, c->radius, c->z_min, c->z_max);
    } else if (const auto* cv = std::get_if<Curves>(&g)) {
        const std::string point = what + ": a control point";
        for (const CurvePoint& q : *cv->cp) check_position(Point3(q.x, q.y, q.z), s.loc, point);
    }
}

}  // namespace

/// Adds a shape (world-level when proto is null, else to the prototype).
void Builder::add_shape(const ShapeDesc& s, Prototype* proto) {
    check_transform(s.world_from_object, s.loc, fmt::format("Shape \"{}\"", s.type));
    auto geom = make_geometry(s);
    if (!geom) return;
    check_extent(*geom, s);
    ShapeEntry e;
    e.geometry = std::move(*geom);
    e.material = resolve_material(s.material);
    e.alpha = alpha_mask(s);
    const SourceLoc& mloc = s.media.loc.line > 0 ? s.media.loc : s.loc;
    e.medium_inside = medium_index(s.media.inside, mloc);
    e.medium_outside = medium_index(s.media.outside, mloc);
    int index = int(m_s.shapes.size());
    if (s.area_light >= 0 && std::holds_alternative<Cylinder>(e.geometry))
        throw_unsupported(s.loc, "an emitting cylinder (area light) is not supported yet");
    if (s.area_light >= 0 && std::holds_alternative<Curves>(e.geometry))
        throw_unsupported(s.loc, "an emitting curve (area light) is not supported (pbrt-v4 "
                                 "cannot sample points on curves either)");
    if (s.area_light >= 0) {
        if (proto)
            throw_error(s.loc, "area lights are not supported inside ObjectBegin (as in pbrt-v4)");
        if (e.material < 0)
            warning(s.loc,
                    "area light on a shape with an \"interface\" material is ignored "
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

void Builder::build_instances() {
    std::map<std::string, int> proto_index;
    for (const auto& [name, def] : m_d.instances) {
        Prototype p;
        p.name = name;
        for (const ShapeDesc& s : def.shapes) recorded([&] { add_shape(s, &p); });
        proto_index[name] = int(m_s.prototypes.size());
        m_s.prototypes.push_back(std::move(p));
    }
    for (const InstanceUse& u : m_d.instance_uses) {
        auto it = proto_index.find(u.name);
        if (it == proto_index.end())
            throw_error(u.loc, "ObjectInstance \"{}\": no such object", u.name);
        check_transform(u.world_from_instance, u.loc, "ObjectInstance");
        if (m_s.prototypes[it->second].shapes.empty()) continue;
        m_s.instances.push_back({it->second, u.world_from_instance});
    }
}

}  // namespace sr::build_detail
