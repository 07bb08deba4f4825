/// Meters (the Meter directive) from their descriptions: points, grids and luminance cones.
#include <fmt/format.h>

#include "steradian/scene/build.h"
#include "steradian/scene/build/builder.h"
#include "steradian/scene/desc.h"
#include "steradian/sensors/meter.h"

namespace sr {

namespace {

/// Reads a list of 3-vectors of any of the given parameter types (point3, vector3,
/// normal); empty when absent.
std::vector<Vec3> vec3s(const ParamSet& ps, std::string_view name, ParamType type) {
    const Param* p = ps.find(name, type);
    std::vector<Vec3> out;
    if (!p) return out;
    for (size_t i = 0; i + 2 < p->numbers.size(); i += 3) {
        Vec3 v(Float(p->numbers[i]), Float(p->numbers[i + 1]), Float(p->numbers[i + 2]));
        if (!std::isfinite(v.x) || !std::isfinite(v.y) || !std::isfinite(v.z))
            throw_error(p->loc, "\"{}\": values must be finite", name);
        out.push_back(v);
    }
    if (out.empty()) throw_error(p->loc, "\"{}\" needs at least one value triple", name);
    return out;
}

const Param* require(const ParamSet& ps, std::string_view name, const SourceLoc& loc,
                     std::string_view what, std::string_view decl) {
    const Param* p = ps.find(name);
    if (!p) throw_error(loc, "{} needs \"{}\"", what, decl);
    return p;
}

/// One direction for all points, or one per point; unit length after the transform.
std::vector<Vec3> per_point(std::vector<Vec3> dirs, size_t n, const Param* p, bool is_normal,
                            const Transform& x, std::string_view what) {
    if (dirs.size() != 1 && dirs.size() != n)
        throw_error(p->loc, "{}: \"{}\" has {} values; give one, or one per point ({})", what,
                    p->name, dirs.size(), n);
    for (Vec3& d : dirs) {
        Vec3 w = is_normal ? x.normal(d) : x.vector(d);
        if (!(length(w) > 0)) throw_error(p->loc, "{}: \"{}\" must not be zero", what, p->name);
        d = normalize(w);
    }
    if (dirs.size() == 1) dirs.assign(n, dirs[0]);
    return dirs;
}

Meter build_meter(const MeterDesc& d, size_t index) {
    const ParamSet& ps = d.params;
    const Transform& x = d.world_from_meter;
    const std::string what = fmt::format("Meter \"{}\"", d.type);
    Meter m;
    m.type = d.type;
    m.loc = d.loc;
    bool radiometric;
    if (d.type == "illuminance" || d.type == "irradiance") {
        m.kind = MeterKind::Point;
        radiometric = d.type == "irradiance";
    } else if (d.type == "illuminancegrid" || d.type == "irradiancegrid") {
        m.kind = MeterKind::Grid;
        radiometric = d.type == "irradiancegrid";
    } else if (d.type == "luminance" || d.type == "radiance") {
        m.kind = MeterKind::Luminance;
        radiometric = d.type == "radiance";
    } else if (d.type == "ugr") {
        // CIE 117:1995's unified glare rating: photopic, from the indirect illuminance at the
        // eye (the background luminance) and the luminaires in view (integrators/glare.h).
        m.kind = MeterKind::Point;
        m.glare = true;
        radiometric = false;
        for (const char* bad : {"vision", "component", "n", "maxdepth"})
            if (const Param* p = ps.find(bad))
                throw_error(p->loc,
                            "{}: a glare meter takes no \"{}\" (it is photopic and reads the "
                            "indirect illuminance on the eye's plane facing \"direction\")",
                            what, bad);
    } else {
        throw_error(d.loc,
                    "unknown meter type \"{}\" (expected \"illuminance\", \"irradiance\", "
                    "\"illuminancegrid\", \"irradiancegrid\", \"luminance\", \"radiance\" "
                    "or \"ugr\")",
                    d.type);
    }
    m.name = ps.get_string("name", fmt::format("{}{}", d.type, index + 1));

    std::string vision = ps.get_string("vision", "photopic");
    if (vision != "photopic" && vision != "scotopic")
        throw_error(ps.find("vision")->loc,
                    "{}: \"vision\" must be \"photopic\" or \"scotopic\", not \"{}\"", what,
                    vision);
    if (radiometric && ps.find("vision"))
        throw_error(ps.find("vision")->loc, "{}: a radiometric meter has no \"vision\"", what);
    m.weighting = radiometric            ? MeterWeighting::Radiometric
                  : vision == "scotopic" ? MeterWeighting::Scotopic
                                         : MeterWeighting::Photopic;
    m.max_depth = ps.get_int("maxdepth", -1);

    if (m.kind != MeterKind::Luminance) {
        std::string comp = ps.get_string("component", "all");
        if (comp == "all")
            m.component = MeterComponent::All;
        else if (comp == "direct")
            m.component = MeterComponent::Direct;
        else if (comp == "indirect")
            m.component = MeterComponent::Indirect;
        else
            throw_error(ps.find("component")->loc,
                        "{}: \"component\" must be \"all\", \"direct\" or \"indirect\", not \"{}\"",
                        what, comp);
    }

    if (m.glare) {
        m.component = MeterComponent::Indirect;
        require(ps, "p", d.loc, what, "point3 p");
        for (Vec3 v : vec3s(ps, "p", ParamType::Point3)) m.points.push_back(x.point(Point3(v)));
        const Param* pd = require(ps, "direction", d.loc, what, "vector3 direction");
        m.directions = per_point(vec3s(ps, "direction", ParamType::Vector3), m.points.size(), pd,
                                 false, x, what);
        Vec3 up(0, 0, 1);
        const Param* pu = ps.find("up", ParamType::Vector3);
        if (pu) up = per_point(vec3s(ps, "up", ParamType::Vector3), 1, pu, false, x, what)[0];
        else up = normalize(x.vector(up));
        for (Vec3 v : m.directions)
            if (std::abs(dot(v, up)) > 1 - 1e-6f)
                throw_error(pu ? pu->loc : pd->loc,
                            "{}: the view \"direction\" must not be parallel to \"up\" "
                            "(default [0 0 1]: give \"vector3 up\")",
                            what);
        m.glare_up = up;
    } else if (m.kind == MeterKind::Point) {
        require(ps, "p", d.loc, what, "point3 p");
        for (Vec3 v : vec3s(ps, "p", ParamType::Point3)) m.points.push_back(x.point(Point3(v)));
        const Param* pn = require(ps, "n", d.loc, what, "normal n");
        m.directions =
            per_point(vec3s(ps, "n", ParamType::Normal3), m.points.size(), pn, true, x, what);
    } else if (m.kind == MeterKind::Grid) {
        require(ps, "corner", d.loc, what, "point3 corner");
        Point3 corner = ps.find_point3("corner").value();
        const Param* pu = require(ps, "u", d.loc, what, "vector3 u");
        const Param* pv = require(ps, "v", d.loc, what, "vector3 v");
        Vec3 u = ps.find_vector3("u").value(), v = ps.find_vector3("v").value();
        const Param* pr = require(ps, "resolution", d.loc, what, "integer resolution [nu nv]");
        std::vector<int> res = ps.get_ints("resolution");
        if (res.size() != 2 || res[0] < 1 || res[1] < 1)
            throw_error(pr->loc, "{}: \"resolution\" must be two positive integers [nu nv]", what);
        // A cell costs its point, direction and readings in memory and a line of the
        // readings' JSON; 1024 x 1024 cells is far beyond a lighting calculation grid (the
        // former limit, 1e8, let a 300-byte scene allocate gigabytes).
        constexpr int64_t kMaxGridCells = int64_t(1) << 20;
        if (int64_t(res[0]) * res[1] > kMaxGridCells)
            throw_error(pr->loc, "{}: \"resolution\" [{} {}] has more than {} cells", what, res[0],
                        res[1], kMaxGridCells);
        m.nu = res[0];
        m.nv = res[1];
        Vec3 wu = x.vector(u), wv = x.vector(v);
        if (!(length(wu) > 0)) throw_error(pu->loc, "{}: \"u\" must not be zero", what);
        if (!(length(wv) > 0)) throw_error(pv->loc, "{}: \"v\" must not be zero", what);
        if (!(length(cross(wu, wv)) > 1e-6f * length(wu) * length(wv)))
            throw_error(pv->loc, "{}: \"u\" and \"v\" must not be parallel", what);
        m.cell_u = wu / Float(m.nu);
        m.cell_v = wv / Float(m.nv);
        m.cell_average = ps.get_bool("cellaverage", false);
        Point3 c = x.point(corner);
        for (int j = 0; j < m.nv; ++j)
            for (int i = 0; i < m.nu; ++i)
                m.points.push_back(c + m.cell_u * (Float(i) + Float(0.5)) +
                                   m.cell_v * (Float(j) + Float(0.5)));
        if (const Param* pn = ps.find("n")) {
            m.directions = per_point(vec3s(ps, "n", ParamType::Normal3), 1, pn, true, x, what);
            m.directions.assign(m.points.size(), m.directions[0]);
        } else {
            m.directions.assign(m.points.size(), normalize(cross(wu, wv)));
        }
    } else {
        require(ps, "p", d.loc, what, "point3 p");
        for (Vec3 v : vec3s(ps, "p", ParamType::Point3)) m.points.push_back(x.point(Point3(v)));
        const Param* pd = require(ps, "direction", d.loc, what, "vector3 direction");
        m.directions = per_point(vec3s(ps, "direction", ParamType::Vector3), m.points.size(), pd,
                                 false, x, what);
        Float cone = ps.get_float("coneangle", Float(0.5));
        if (!(cone >= 0 && cone < 90))
            throw_error(ps.find("coneangle")->loc,
                        "{}: \"coneangle\" (half-angle, degrees) must be in [0, 90)", what);
        m.cone_half_angle = radians(cone);
    }
    ps.check_unused(what);
    build_detail::check_transform(x, d.loc, what);
    for (Point3 p : m.points) build_detail::check_position(p, d.loc, "a measuring point");
    for (Vec3 v : m.directions)
        if (!std::isfinite(v.x) || !std::isfinite(v.y) || !std::isfinite(v.z))
            throw_error(d.loc, "{}: a direction or normal is not finite", what);
    return m;
}

}  // namespace

std::vector<Meter> build_meters(const std::vector<MeterDesc>& descs) {
    std::vector<Meter> out;
    for (size_t i = 0; i < descs.size(); ++i) {
        out.push_back(build_meter(descs[i], i));
        for (size_t k = 0; k + 1 < out.size(); ++k)
            if (out[k].name == out.back().name)
                throw_error(descs[i].loc, "a meter named \"{}\" already exists", out.back().name);
    }
    return out;
}

}  // namespace sr
