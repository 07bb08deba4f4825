#include "steradian/scene/param_set.h"

#include <cmath>
#include <limits>

namespace sr {

std::string_view to_string(ParamType t) {
    switch (t) {
        case ParamType::Integer: return "integer";
        case ParamType::Float: return "float";
        case ParamType::Point2: return "point2";
        case ParamType::Vector2: return "vector2";
        case ParamType::Point3: return "point3";
        case ParamType::Vector3: return "vector3";
        case ParamType::Normal3: return "normal";
        case ParamType::Bool: return "bool";
        case ParamType::String: return "string";
        case ParamType::Texture: return "texture";
        case ParamType::Spectrum: return "spectrum";
        case ParamType::Rgb: return "rgb";
        case ParamType::Blackbody: return "blackbody";
    }
    return "?";
}

namespace {

/// "float radius": the declaration as written in a pbrt file, for messages.
std::string decl(const Param& p) { return fmt::format("\"{} {}\"", to_string(p.type), p.name); }

/// Number of values a parameter holds, whatever its type.
size_t value_count(const Param& p) {
    return p.numbers.size() + p.strings.size() + p.bools.size();
}

void check_exactly(const Param& p, size_t n) {
    size_t got = value_count(p);
    if (got == n) return;
    if (got == 0) throw_error(p.loc, "parameter {} has no value", decl(p));
    throw_error(p.loc, "parameter {} needs exactly {} value{}, got {}", decl(p), n,
                n == 1 ? "" : "s", got);
}

void check_multiple_of(const Param& p, size_t n) {
    size_t got = value_count(p);
    if (got % n != 0)
        throw_error(p.loc, "parameter {} needs a multiple of {} values, got {}", decl(p), n, got);
}

int to_int(const Param& p, double v) {
    if (v != std::floor(v) || v < double(std::numeric_limits<int>::min()) ||
        v > double(std::numeric_limits<int>::max()))
        throw_error(p.loc, "parameter {}: value {} is not a 32-bit integer", decl(p), v);
    return int(v);
}

}  // namespace

void ParamSet::add(Param p) {
    for (const Param& q : m_params)
        if (q.name == p.name)
            throw_error(p.loc, "duplicate parameter \"{}\" (first given at {})", p.name,
                        q.loc.to_string());
    m_params.push_back(std::move(p));
}

const Param* ParamSet::find(std::string_view name) const {
    for (const Param& p : m_params)
        if (p.name == name) {
            p.used = true;
            return &p;
        }
    return nullptr;
}

const Param* ParamSet::find(std::string_view name, ParamType type) const {
    for (const Param& p : m_params) {
        if (p.name != name) continue;
        if (p.type != type)
            throw_error(p.loc, "parameter {} has the wrong type: expected \"{} {}\"", decl(p),
                        to_string(type), p.name);
        p.used = true;
        return &p;
    }
    return nullptr;
}

Float ParamSet::get_float(std::string_view name, Float def) const {
    return find_float(name).value_or(def);
}

int ParamSet::get_int(std::string_view name, int def) const { return find_int(name).value_or(def); }

bool ParamSet::get_bool(std::string_view name, bool def) const {
    const Param* p = find(name, ParamType::Bool);
    if (!p) return def;
    check_exactly(*p, 1);
    return p->bools[0] != 0;
}

std::string ParamSet::get_string(std::string_view name, const std::string& def) const {
    return find_string(name).value_or(def);
}

std::optional<Float> ParamSet::find_float(std::string_view name) const {
    const Param* p = find(name, ParamType::Float);
    if (!p) return std::nullopt;
    check_exactly(*p, 1);
    return Float(p->numbers[0]);
}

std::optional<int> ParamSet::find_int(std::string_view name) const {
    const Param* p = find(name, ParamType::Integer);
    if (!p) return std::nullopt;
    check_exactly(*p, 1);
    return to_int(*p, p->numbers[0]);
}

std::optional<std::string> ParamSet::find_string(std::string_view name) const {
    const Param* p = find(name, ParamType::String);
    if (!p) return std::nullopt;
    check_exactly(*p, 1);
    return p->strings[0];
}

namespace {
std::optional<Vec3> one_vec3(const ParamSet& ps, std::string_view name, ParamType type) {
    const Param* p = ps.find(name, type);
    if (!p) return std::nullopt;
    check_exactly(*p, 3);
    return Vec3(Float(p->numbers[0]), Float(p->numbers[1]), Float(p->numbers[2]));
}

std::vector<Vec3> vec3s(const ParamSet& ps, std::string_view name, ParamType type) {
    const Param* p = ps.find(name, type);
    if (!p) return {};
    check_multiple_of(*p, 3);
    std::vector<Vec3> r(p->numbers.size() / 3);
    for (size_t i = 0; i < r.size(); ++i)
        r[i] = Vec3(Float(p->numbers[3 * i]), Float(p->numbers[3 * i + 1]),
                    Float(p->numbers[3 * i + 2]));
    return r;
}
}  // namespace

std::optional<Point3> ParamSet::find_point3(std::string_view name) const {
    return one_vec3(*this, name, ParamType::Point3);
}

std::optional<Vec3> ParamSet::find_vector3(std::string_view name) const {
    return one_vec3(*this, name, ParamType::Vector3);
}

std::optional<Normal3> ParamSet::find_normal3(std::string_view name) const {
    return one_vec3(*this, name, ParamType::Normal3);
}

std::vector<Float> ParamSet::get_floats(std::string_view name) const {
    const Param* p = find(name, ParamType::Float);
    if (!p) return {};
    return std::vector<Float>(p->numbers.begin(), p->numbers.end());
}

std::vector<int> ParamSet::get_ints(std::string_view name) const {
    const Param* p = find(name, ParamType::Integer);
    if (!p) return {};
    std::vector<int> r(p->numbers.size());
    for (size_t i = 0; i < r.size(); ++i) r[i] = to_int(*p, p->numbers[i]);
    return r;
}

std::vector<Point3> ParamSet::get_point3s(std::string_view name) const {
    return vec3s(*this, name, ParamType::Point3);
}

std::vector<Vec3> ParamSet::get_normals(std::string_view name) const {
    return vec3s(*this, name, ParamType::Normal3);
}

std::vector<Point2> ParamSet::get_point2s(std::string_view name) const {
    const Param* p = find(name, ParamType::Point2);
    if (!p) return {};
    check_multiple_of(*p, 2);
    std::vector<Point2> r(p->numbers.size() / 2);
    for (size_t i = 0; i < r.size(); ++i)
        r[i] = Point2(Float(p->numbers[2 * i]), Float(p->numbers[2 * i + 1]));
    return r;
}

std::vector<std::string> ParamSet::get_strings(std::string_view name) const {
    const Param* p = find(name, ParamType::String);
    if (!p) return {};
    return p->strings;
}

const Param* ParamSet::find_spectrum(std::string_view name) const {
    for (const Param& p : m_params) {
        if (p.name != name) continue;
        switch (p.type) {
            case ParamType::Rgb: check_exactly(p, 3); break;
            case ParamType::Blackbody: check_exactly(p, 1); break;
            case ParamType::Spectrum:
                if (!p.strings.empty()) {
                    if (p.strings.size() != 1 || !p.numbers.empty())
                        throw_error(p.loc,
                                    "parameter {} given by name needs exactly one string, got {} "
                                    "values",
                                    decl(p), value_count(p));
                } else if (p.numbers.empty() || p.numbers.size() % 2 != 0) {
                    throw_error(p.loc,
                                "parameter {} needs (wavelength, value) pairs, got {} values",
                                decl(p), p.numbers.size());
                }
                break;
            default:
                throw_error(p.loc,
                            "parameter {} has the wrong type: expected a spectrum (\"spectrum\", "
                            "\"rgb\" or \"blackbody\")",
                            decl(p));
        }
        p.used = true;
        return &p;
    }
    return nullptr;
}

std::optional<std::string> ParamSet::find_texture(std::string_view name) const {
    for (const Param& p : m_params) {
        if (p.name != name) continue;
        if (p.type != ParamType::Texture) return std::nullopt;
        if (p.strings.size() != 1)
            throw_error(p.loc, "parameter {} needs exactly one texture name, got {} values",
                        decl(p), value_count(p));
        p.used = true;
        return p.strings[0];
    }
    return std::nullopt;
}

void ParamSet::check_unused(std::string_view what) const {
    for (const Param& p : m_params)
        if (!p.used) throw_unsupported(p.loc, "unused parameter {} for {}", decl(p), what);
}

}  // namespace sr
