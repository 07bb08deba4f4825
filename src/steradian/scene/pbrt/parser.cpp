#include "steradian/scene/pbrt/parser.h"

#include <array>
#include <cctype>
#include <charconv>
#include <cmath>
#include <filesystem>
#include <limits>
#include <optional>
#include <unordered_map>
#include <utility>

#include "steradian/scene/pbrt/tokenizer.h"

// Semantics follow pbrt-v4's parser.cpp (syntax) and BasicSceneBuilder in scene.cpp
// (graphics state). In short:
// - The CTM starts as identity, is post-multiplied by Translate/Scale/Rotate/LookAt/
//   ConcatTransform, and is replaced by Identity/Transform/CoordSysTransform. Camera
//   records it as camera_from_world and defines the named coordinate system "camera"
//   (= world_from_camera); WorldBegin resets it to identity and defines "world". Named
//   coordinate systems are global (not scoped by AttributeBegin/End).
// - AttributeBegin/End save/restore the whole graphics state: CTM, active transform
//   times, ReverseOrientation, current material, current area light and Attribute
//   defaults. TransformBegin/End are the same (pbrt-v4 maps them to AttributeBegin/End),
//   with a one-time deprecation warning. ObjectBegin/End save/restore it as well.
// - Options-block directives (Camera, Film, Sampler, Integrator, PixelFilter, Accelerator,
//   TransformTimes) are errors after WorldBegin; world-block directives (Shape, Material,
//   AttributeBegin, ...) are errors before it. Transformations, CoordinateSystem,
//   ColorSpace, Option, Attribute, MakeNamedMedium, MediumInterface and Include may appear
//   anywhere; Import only in the world block.
// - Attribute "shape"|"light"|"material"|"medium"|"texture" params: implemented by merging.
//   The parameters become defaults of later entities of that kind in the same attribute
//   scope (a later Attribute overrides an earlier one of the same name; the entity's own
//   parameters override both). Merged copies are marked used, as pbrt-v4 lets them go
//   unused. "light" applies to LightSource and AreaLightSource, "material" to Material
//   and MakeNamedMaterial; "medium" is accepted and has no effect (media are ignored).
// - Include is textual (shared graphics state). Import parses the file with a copy of the
//   graphics state that is discarded afterwards, as pbrt-v4 does with its separate builder;
//   definitions it makes (shapes, lights, named materials, textures, objects) are global.
//   Named coordinate systems defined inside an Import are discarded too (pbrt-v4 starts
//   the imported file with none; we keep the importer's visible, a superset).
// - Relative Include/Import paths resolve against the main scene file's directory, as in
//   pbrt-v4; if the file is not there, against the including file's directory.
// - Duplicate parameters in one list are an error (pbrt-v4 silently uses the last one).
// - Errors are thrown at the first problem; pbrt-v4 defers some of them to the end.

namespace sr {
namespace {

namespace fs = std::filesystem;
using pbrt::Token;
using pbrt::TokenKind;
using pbrt::Tokenizer;

enum class Dir {
    Accelerator, ActiveTransform, AreaLightSource, Attribute, AttributeBegin, AttributeEnd,
    Camera, ColorSpace, ConcatTransform, CoordSysTransform, CoordinateSystem, Film, Identity,
    Import, Include, Integrator, LightSource, LookAt, MakeNamedMaterial, MakeNamedMedium,
    Material, MediumInterface, Meter, NamedMaterial, ObjectBegin, ObjectEnd, ObjectInstance, Option,
    PixelFilter, ReverseOrientation, Rotate, Sampler, Scale, Shape, Texture, Transform,
    TransformBegin, TransformEnd, TransformTimes, Translate, WorldBegin, WorldEnd
};

const std::unordered_map<std::string_view, Dir>& directive_table() {
    static const std::unordered_map<std::string_view, Dir> table = {
        {"Accelerator", Dir::Accelerator},
        {"ActiveTransform", Dir::ActiveTransform},
        {"AreaLightSource", Dir::AreaLightSource},
        {"Attribute", Dir::Attribute},
        {"AttributeBegin", Dir::AttributeBegin},
        {"AttributeEnd", Dir::AttributeEnd},
        {"Camera", Dir::Camera},
        {"ColorSpace", Dir::ColorSpace},
        {"ConcatTransform", Dir::ConcatTransform},
        {"CoordSysTransform", Dir::CoordSysTransform},
        {"CoordinateSystem", Dir::CoordinateSystem},
        {"Film", Dir::Film},
        {"Identity", Dir::Identity},
        {"Import", Dir::Import},
        {"Include", Dir::Include},
        {"Integrator", Dir::Integrator},
        {"LightSource", Dir::LightSource},
        {"LookAt", Dir::LookAt},
        {"MakeNamedMaterial", Dir::MakeNamedMaterial},
        {"MakeNamedMedium", Dir::MakeNamedMedium},
        {"Material", Dir::Material},
        {"MediumInterface", Dir::MediumInterface},
        {"Meter", Dir::Meter},
        {"NamedMaterial", Dir::NamedMaterial},
        {"ObjectBegin", Dir::ObjectBegin},
        {"ObjectEnd", Dir::ObjectEnd},
        {"ObjectInstance", Dir::ObjectInstance},
        {"Option", Dir::Option},
        {"PixelFilter", Dir::PixelFilter},
        {"ReverseOrientation", Dir::ReverseOrientation},
        {"Rotate", Dir::Rotate},
        {"Sampler", Dir::Sampler},
        {"Scale", Dir::Scale},
        {"Shape", Dir::Shape},
        {"Texture", Dir::Texture},
        {"Transform", Dir::Transform},
        {"TransformBegin", Dir::TransformBegin},
        {"TransformEnd", Dir::TransformEnd},
        {"TransformTimes", Dir::TransformTimes},
        {"Translate", Dir::Translate},
        {"WorldBegin", Dir::WorldBegin},
        {"WorldEnd", Dir::WorldEnd},
    };
    return table;
}

/// pbrt-v4 parameter type names, plus the pbrt-v3 names pbrt-v4 only takes with --upgrade.
std::optional<ParamType> param_type_from_name(std::string_view s) {
    static const std::unordered_map<std::string_view, ParamType> table = {
        {"integer", ParamType::Integer}, {"float", ParamType::Float},
        {"point2", ParamType::Point2},   {"vector2", ParamType::Vector2},
        {"point3", ParamType::Point3},   {"point", ParamType::Point3},
        {"vector3", ParamType::Vector3}, {"vector", ParamType::Vector3},
        {"normal3", ParamType::Normal3}, {"normal", ParamType::Normal3},
        {"bool", ParamType::Bool},       {"string", ParamType::String},
        {"texture", ParamType::Texture}, {"spectrum", ParamType::Spectrum},
        {"rgb", ParamType::Rgb},         {"color", ParamType::Rgb},
        {"blackbody", ParamType::Blackbody},
    };
    auto it = table.find(s);
    if (it == table.end()) return std::nullopt;
    return it->second;
}

std::string describe(const Token& t) {
    if (t.kind == TokenKind::String) return fmt::format("string \"{}\"", t.text);
    return fmt::format("'{}'", t.text);
}

bool parse_double(std::string_view s, double& v) {
    const char* b = s.data();
    const char* e = b + s.size();
    if (b != e && *b == '+') {
        ++b;
        if (b != e && (*b == '+' || *b == '-')) return false;
    }
    auto r = std::from_chars(b, e, v);
    return r.ec == std::errc() && r.ptr == e && std::isfinite(v);
}

enum class IntParse { Ok, NotInteger, OutOfRange };

IntParse parse_int(std::string_view s, int& v) {
    const char* b = s.data();
    const char* e = b + s.size();
    if (b != e && *b == '+') {
        ++b;
        if (b != e && (*b == '+' || *b == '-')) return IntParse::NotInteger;
    }
    long long x = 0;
    auto r = std::from_chars(b, e, x);
    if (b == e || r.ptr != e) return IntParse::NotInteger;
    if (r.ec == std::errc::result_out_of_range || x < std::numeric_limits<int>::min() ||
        x > std::numeric_limits<int>::max())
        return IntParse::OutOfRange;
    if (r.ec != std::errc()) return IntParse::NotInteger;
    v = int(x);
    return IntParse::Ok;
}

/// Tokens of one file with one token of look-ahead.
class Stream {
public:
    explicit Stream(Tokenizer& tz) : m_tz(tz) {}
    bool next(Token& t) {
        if (m_has_unget) {
            t = m_unget;
            m_has_unget = false;
            return true;
        }
        return m_tz.next(t);
    }
    void unget(const Token& t) {
        m_unget = t;
        m_has_unget = true;
    }
    SourceLoc loc(const Token& t) const { return m_tz.loc(t); }
    SourceLoc end_loc() const { return m_tz.end_loc(); }

    /// The next token, or an "unexpected end of file" error mentioning `expected`.
    Token require(std::string_view what, std::string_view expected) {
        Token t;
        if (!next(t)) throw_error(end_loc(), "{}: unexpected end of file, expected {}", what, expected);
        return t;
    }
    Token expect_string(std::string_view what) {
        Token t = require(what, "a quoted string");
        if (t.kind != TokenKind::String)
            throw_error(loc(t), "{}: expected a quoted string, got {}", what, describe(t));
        return t;
    }
    double expect_number(std::string_view what) {
        Token t = require(what, "a number");
        double v;
        if (t.kind != TokenKind::Number || !parse_double(t.text, v))
            throw_error(loc(t), "{}: expected a number, got {}", what, describe(t));
        return v;
    }

private:
    Tokenizer& m_tz;
    Token m_unget;
    bool m_has_unget = false;
};

struct GraphicsState {
    Transform ctm;
    bool start_active = true;  ///< ActiveTransform includes StartTime (we keep only that one)
    bool reverse_orientation = false;
    MaterialRef material;
    int area_light = -1;
    std::vector<Param> shape_attrs, light_attrs, material_attrs, medium_attrs, texture_attrs;
};

struct Pushed {
    const char* directive;  ///< "AttributeBegin", "TransformBegin" or "ObjectBegin"
    SourceLoc loc;
    GraphicsState state;
};

/// Builds a ParamSet from an entity's own parameters (already free of duplicates) and the
/// Attribute defaults that apply to it; `skip` names a parameter to leave out.
ParamSet make_params(std::vector<Param>&& own, const std::vector<Param>* attrs,
                     std::string_view skip = {}) {
    ParamSet ps;
    for (Param& p : own)
        if (skip.empty() || p.name != skip) ps.add(std::move(p));
    if (attrs)
        for (const Param& a : *attrs) {
            if (!skip.empty() && a.name == skip) continue;
            bool present = false;
            for (const Param& q : ps.params())
                if (q.name == a.name) {
                    present = true;
                    break;
                }
            if (present) continue;
            Param c = a;
            c.used = true;  // pbrt-v4 marks attribute parameters "may be unused"
            ps.add(std::move(c));
        }
    return ps;
}

std::string parent_dir(const std::string& path) {
    std::string d = fs::path(path).parent_path().string();
    return d.empty() ? "." : d;
}

class Parser {
public:
    explicit Parser(std::string base_dir) : m_base_dir(std::move(base_dir)) {
        m_scene.base_dir = m_base_dir;
    }

    void parse(Tokenizer& tz, const std::string& dir, int depth);
    SceneDesc finish(const SourceLoc& eof);

private:
    enum class ValueKind { Number, Integer, Bool, String, Spectrum };

    std::vector<Param> parse_params(Stream& s);
    Param parse_param(Stream& s, const Token& decl);
    std::pair<std::string, std::vector<Param>> parse_entity(Stream& s, std::string_view what);

    void require_world(std::string_view what, const SourceLoc& loc) const {
        if (!m_in_world) throw_error(loc, "{} is not allowed before WorldBegin", what);
    }
    void require_options(std::string_view what, const SourceLoc& loc) const {
        if (m_in_world)
            throw_error(loc, "{} is not allowed after WorldBegin (it belongs to the options block)",
                        what);
    }
    /// Applies `t` to the CTM: ctm = ctm * t (only the start-time transform is kept).
    void concat(const Transform& t) {
        if (m_gs.start_active) m_gs.ctm = m_gs.ctm * t;
    }
    void set_ctm(const Transform& t) {
        if (m_gs.start_active) m_gs.ctm = t;
    }
    Transform read_matrix(Stream& s, std::string_view what, const SourceLoc& loc);

    void attribute_begin(const char* what, const SourceLoc& loc);
    void attribute_end(std::string_view what, const SourceLoc& loc);
    void object_begin(Stream& s, const SourceLoc& loc);
    void object_end(const SourceLoc& loc);
    void attribute(Stream& s);
    void texture(Stream& s, const SourceLoc& loc);
    void make_named_material(Stream& s, const SourceLoc& loc);
    void shape(Stream& s, const SourceLoc& loc);
    void option(Stream& s);
    void active_transform(Stream& s, const SourceLoc& loc);
    std::string resolve(const std::string& name, const std::string& dir, std::string_view what,
                        const SourceLoc& loc) const;
    void include(Stream& s, const std::string& dir, int depth, const SourceLoc& loc, bool import);

    SceneDesc m_scene;
    GraphicsState m_gs;
    std::vector<Pushed> m_stack;
    size_t m_stack_floor = 0;  ///< entries below this belong to the file that Imports
    std::unordered_map<std::string, Transform> m_coordsys;
    bool m_in_world = false;
    SourceLoc m_world_loc;
    InstanceDefinition* m_object = nullptr;  ///< the open ObjectBegin, if any
    std::unordered_map<std::string, SourceLoc> m_float_textures, m_spectrum_textures;
    std::vector<Param> m_options;
    bool m_warned_transform_begin = false;
    std::string m_base_dir;
};

// ---- parameter lists --------------------------------------------------------------------

std::vector<Param> Parser::parse_params(Stream& s) {
    std::vector<Param> out;
    Token t;
    while (s.next(t)) {
        if (t.kind != TokenKind::String) {
            s.unget(t);
            break;
        }
        Param p = parse_param(s, t);
        for (const Param& q : out)
            if (q.name == p.name)
                throw_error(p.loc, "duplicate parameter \"{}\" (first given at {})", p.name,
                            q.loc.to_string());
        out.push_back(std::move(p));
    }
    return out;
}

Param Parser::parse_param(Stream& s, const Token& decl) {
    Param p;
    p.loc = s.loc(decl);

    // "type name", separated by spaces or tabs.
    std::string_view d = decl.text;
    auto is_space = [](char c) { return c == ' ' || c == '\t'; };
    size_t i = 0;
    while (i < d.size() && is_space(d[i])) ++i;
    size_t type_begin = i;
    while (i < d.size() && !is_space(d[i])) ++i;
    std::string_view type_name = d.substr(type_begin, i - type_begin);
    while (i < d.size() && is_space(d[i])) ++i;
    size_t name_begin = i;
    while (i < d.size() && !is_space(d[i])) ++i;
    std::string_view name = d.substr(name_begin, i - name_begin);
    while (i < d.size() && is_space(d[i])) ++i;
    if (type_name.empty() || name.empty() || i != d.size())
        throw_error(p.loc,
                    "malformed parameter declaration \"{}\": expected \"type name\" (or a "
                    "directive name without quotes)",
                    d);
    auto type = param_type_from_name(type_name);
    if (!type) throw_error(p.loc, "unknown parameter type \"{}\" in \"{}\"", type_name, d);
    p.type = *type;
    p.name = std::string(name);

    ValueKind kind = ValueKind::Number;
    switch (p.type) {
        case ParamType::Integer: kind = ValueKind::Integer; break;
        case ParamType::Bool: kind = ValueKind::Bool; break;
        case ParamType::String:
        case ParamType::Texture: kind = ValueKind::String; break;
        case ParamType::Spectrum: kind = ValueKind::Spectrum; break;
        default: kind = ValueKind::Number; break;
    }
    auto what = [&] { return fmt::format("parameter \"{} {}\"", type_name, name); };

    auto add_value = [&](const Token& v) {
        switch (kind) {
            case ValueKind::Number: {
                double x;
                if (v.kind != TokenKind::Number || !parse_double(v.text, x))
                    throw_error(s.loc(v), "{}: expected a number, got {}", what(), describe(v));
                p.numbers.push_back(x);
                return;
            }
            case ValueKind::Integer: {
                int x = 0;
                IntParse r = v.kind == TokenKind::Number ? parse_int(v.text, x)
                                                         : IntParse::NotInteger;
                if (r == IntParse::OutOfRange)
                    throw_error(s.loc(v), "{}: integer {} is out of the 32-bit range", what(),
                                v.text);
                if (r != IntParse::Ok)
                    throw_error(s.loc(v), "{}: expected an integer, got {}", what(), describe(v));
                p.numbers.push_back(double(x));
                return;
            }
            case ValueKind::Bool:
                if ((v.kind == TokenKind::Identifier || v.kind == TokenKind::String) &&
                    (v.text == "true" || v.text == "false")) {
                    p.bools.push_back(v.text == "true" ? 1 : 0);
                    return;
                }
                throw_error(s.loc(v), "{}: expected true or false, got {}", what(), describe(v));
            case ValueKind::String:
                if (v.kind != TokenKind::String)
                    throw_error(s.loc(v), "{}: expected a quoted string, got {}", what(),
                                describe(v));
                p.strings.emplace_back(v.text);
                return;
            case ValueKind::Spectrum: {
                double x;
                if (v.kind == TokenKind::String && p.numbers.empty()) {
                    p.strings.emplace_back(v.text);
                    return;
                }
                if (v.kind == TokenKind::Number && p.strings.empty() && parse_double(v.text, x)) {
                    p.numbers.push_back(x);
                    return;
                }
                throw_error(s.loc(v),
                            "{}: expected (wavelength, value) numbers or one spectrum name, got {}",
                            what(), describe(v));
            }
        }
    };

    Token v;
    if (!s.next(v)) throw_error(p.loc, "{} has no value (end of file)", what());
    if (v.kind == TokenKind::LBracket) {
        Token open = v;
        for (;;) {
            if (!s.next(v))
                throw_error(s.loc(open), "unterminated value list of {}: missing ']'", what());
            if (v.kind == TokenKind::RBracket) break;
            if (v.kind == TokenKind::LBracket)
                throw_error(s.loc(v), "{}: unexpected '[' inside a value list", what());
            add_value(v);
        }
    } else if (v.kind == TokenKind::RBracket) {
        throw_error(s.loc(v), "{}: unexpected ']' (missing '['?)", what());
    } else {
        add_value(v);
    }

    // Counts that do not depend on how the builder will use the parameter.
    size_t n = p.numbers.size() + p.strings.size() + p.bools.size();
    switch (p.type) {
        case ParamType::Point2:
        case ParamType::Vector2:
            if (n % 2 != 0)
                throw_error(p.loc, "{} needs a multiple of 2 values, got {}", what(), n);
            break;
        case ParamType::Point3:
        case ParamType::Vector3:
        case ParamType::Normal3:
            if (n % 3 != 0)
                throw_error(p.loc, "{} needs a multiple of 3 values, got {}", what(), n);
            break;
        case ParamType::Rgb:
            if (n != 3) throw_error(p.loc, "{} needs exactly 3 values, got {}", what(), n);
            break;
        case ParamType::Blackbody:
            if (n != 1)
                throw_error(p.loc,
                            "{} needs exactly 1 value (temperature in K), got {}{}", what(), n,
                            n == 2 ? " (pbrt-v3's scale value is gone in pbrt-v4: use the "
                                     "light's \"scale\" or \"power\")"
                                   : "");
            break;
        case ParamType::Texture:
            if (n != 1) throw_error(p.loc, "{} needs exactly 1 texture name, got {}", what(), n);
            break;
        case ParamType::Spectrum:
            if (!p.strings.empty() && n != 1)
                throw_error(p.loc, "{} needs exactly 1 spectrum name, got {}", what(), n);
            if (p.strings.empty() && (n == 0 || n % 2 != 0))
                throw_error(p.loc, "{} needs (wavelength, value) pairs, got {} values", what(),
                            n);
            break;
        default: break;
    }
    return p;
}

std::pair<std::string, std::vector<Param>> Parser::parse_entity(Stream& s, std::string_view what) {
    Token t = s.expect_string(what);
    std::string type(t.text);
    return {std::move(type), parse_params(s)};
}

// ---- directives -------------------------------------------------------------------------

Transform Parser::read_matrix(Stream& s, std::string_view what, const SourceLoc& loc) {
    Token t = s.require(what, "'['");
    if (t.kind != TokenKind::LBracket)
        throw_error(s.loc(t), "{}: expected '[' before the 16 matrix values, got {}", what,
                    describe(t));
    std::array<double, 16> v;
    for (double& x : v) x = s.expect_number(what);
    t = s.require(what, "']'");
    if (t.kind != TokenKind::RBracket)
        throw_error(s.loc(t), "{}: expected ']' after 16 matrix values, got {}", what,
                    describe(t));
    // pbrt lists the matrix column by column (translation in values 13-15).
    Matrix4 m = Matrix4::from_rows(v).transposed();
    auto inv = m.inverse();
    if (!inv) throw_error(loc, "{}: singular transformation matrix", what);
    return Transform(m, *inv);
}

void Parser::attribute_begin(const char* what, const SourceLoc& loc) {
    require_world(what, loc);
    m_stack.push_back({what, loc, m_gs});
}

void Parser::attribute_end(std::string_view what, const SourceLoc& loc) {
    require_world(what, loc);
    std::string_view begin = what == "TransformEnd" ? "TransformBegin" : "AttributeBegin";
    if (m_stack.size() <= m_stack_floor)
        throw_error(loc, "{} without matching {}{}", what, begin,
                    m_stack_floor > 0 ? " in this imported file" : "");
    Pushed& top = m_stack.back();
    if (m_object && std::string_view(top.directive) == "ObjectBegin")
        throw_error(loc, "{} closes ObjectBegin \"{}\" (at {}): expected ObjectEnd", what,
                    m_object->name, top.loc.to_string());
    m_gs = std::move(top.state);
    m_stack.pop_back();
}

void Parser::object_begin(Stream& s, const SourceLoc& loc) {
    require_world("ObjectBegin", loc);
    std::string name(s.expect_string("ObjectBegin").text);
    if (m_object)
        throw_error(loc,
                    "ObjectBegin \"{}\" inside the definition of object \"{}\" (started at "
                    "{}): object definitions cannot be nested",
                    name, m_object->name, m_object->loc.to_string());
    if (auto it = m_scene.instances.find(name); it != m_scene.instances.end())
        throw_error(loc, "object \"{}\" redefined (first defined at {})", name,
                    it->second.loc.to_string());
    m_stack.push_back({"ObjectBegin", loc, m_gs});
    InstanceDefinition& def = m_scene.instances[name];
    def.name = name;
    def.loc = loc;
    m_object = &def;
}

void Parser::object_end(const SourceLoc& loc) {
    require_world("ObjectEnd", loc);
    if (!m_object) throw_error(loc, "ObjectEnd without matching ObjectBegin");
    if (m_stack.size() <= m_stack_floor)
        throw_error(loc,
                    "ObjectEnd in an imported file for ObjectBegin \"{}\" (at {}) of the "
                    "importing file",
                    m_object->name, m_object->loc.to_string());
    Pushed& top = m_stack.back();
    if (std::string_view(top.directive) != "ObjectBegin")
        throw_error(loc, "ObjectEnd while {} at {} is still open", top.directive,
                    top.loc.to_string());
    m_gs = std::move(top.state);
    m_stack.pop_back();
    m_object = nullptr;
}

void Parser::attribute(Stream& s) {
    Token target_tok = s.expect_string("Attribute");
    std::string target(target_tok.text);
    SourceLoc target_loc = s.loc(target_tok);
    std::vector<Param> params = parse_params(s);
    std::vector<Param>* dst = nullptr;
    if (target == "shape") dst = &m_gs.shape_attrs;
    else if (target == "light") dst = &m_gs.light_attrs;
    else if (target == "material") dst = &m_gs.material_attrs;
    else if (target == "medium") dst = &m_gs.medium_attrs;
    else if (target == "texture") dst = &m_gs.texture_attrs;
    else
        throw_error(target_loc,
                    "unknown Attribute target \"{}\": must be \"shape\", \"light\", "
                    "\"material\", \"medium\" or \"texture\"",
                    target);
    for (Param& p : params) {
        bool replaced = false;
        for (Param& q : *dst)
            if (q.name == p.name) {
                q = std::move(p);
                replaced = true;
                break;
            }
        if (!replaced) dst->push_back(std::move(p));
    }
}

void Parser::texture(Stream& s, const SourceLoc& loc) {
    require_world("Texture", loc);
    std::string name(s.expect_string("Texture").text);
    Token vt = s.expect_string("Texture");
    std::string value_type(vt.text);
    if (value_type != "float" && value_type != "spectrum")
        throw_error(s.loc(vt), "unknown texture type \"{}\": must be \"float\" or \"spectrum\"{}",
                    value_type,
                    value_type == "color" ? " (pbrt-v3's \"color\" is \"spectrum\" in pbrt-v4)"
                                          : "");
    std::string cls(s.expect_string("Texture").text);
    std::vector<Param> params = parse_params(s);

    auto& names = value_type == "float" ? m_float_textures : m_spectrum_textures;
    if (auto it = names.find(name); it != names.end())
        throw_error(loc, "{} texture \"{}\" redefined (first defined at {})", value_type, name,
                    it->second.to_string());
    names.emplace(name, loc);

    TextureDesc t;
    t.type = std::move(cls);
    t.params = make_params(std::move(params), &m_gs.texture_attrs);
    t.loc = loc;
    t.name = name;
    t.value_type = value_type;
    t.world_from_texture = m_gs.ctm;
    (value_type == "float" ? m_scene.float_textures : m_scene.spectrum_textures)
        .push_back(std::move(t));
}

void Parser::make_named_material(Stream& s, const SourceLoc& loc) {
    require_world("MakeNamedMaterial", loc);
    std::string name(s.expect_string("MakeNamedMaterial").text);
    std::vector<Param> params = parse_params(s);
    if (auto it = m_scene.named_materials.find(name); it != m_scene.named_materials.end())
        throw_error(loc, "named material \"{}\" redefined (first defined at {})", name,
                    m_scene.materials[size_t(it->second)].loc.to_string());

    // The "string type" parameter names the material type; it is consumed here.
    const Param* type = nullptr;
    for (const Param& p : params)
        if (p.name == "type") type = &p;
    if (!type)
        for (const Param& p : m_gs.material_attrs)
            if (p.name == "type") type = &p;
    if (!type) throw_error(loc, "MakeNamedMaterial \"{}\": missing \"string type\" parameter", name);
    if (type->type != ParamType::String || type->strings.size() != 1)
        throw_error(type->loc,
                    "MakeNamedMaterial \"{}\": \"type\" must be a single string, e.g. \"string "
                    "type\" \"diffuse\"",
                    name);

    MaterialDesc m;
    m.type = type->strings[0];
    m.params = make_params(std::move(params), &m_gs.material_attrs, "type");
    m.loc = loc;
    m.name = name;
    m_scene.named_materials[name] = int(m_scene.materials.size());
    m_scene.materials.push_back(std::move(m));
}

void Parser::shape(Stream& s, const SourceLoc& loc) {
    require_world("Shape", loc);
    auto [type, params] = parse_entity(s, "Shape");
    ShapeDesc sh;
    sh.type = std::move(type);
    sh.params = make_params(std::move(params), &m_gs.shape_attrs);
    sh.loc = loc;
    sh.world_from_object = m_gs.ctm;
    sh.reverse_orientation = m_gs.reverse_orientation;
    sh.material = m_gs.material;
    sh.area_light = m_gs.area_light;
    if (!m_object) {
        m_scene.shapes.push_back(std::move(sh));
        return;
    }
    if (sh.area_light >= 0) {
        warning(loc, fmt::format("area lights are not supported with object instancing (as in "
                                 "pbrt-v4): this shape of object \"{}\" does not emit",
                                 m_object->name));
        sh.area_light = -1;
    }
    m_object->shapes.push_back(std::move(sh));
}

void Parser::option(Stream& s) {
    Token name_tok = s.expect_string("Option");
    SourceLoc loc = s.loc(name_tok);
    // pbrt-v4 normalises option names: lower case, '-' and '_' removed.
    std::string name;
    for (char c : name_tok.text)
        if (c != '-' && c != '_') name.push_back(char(std::tolower(static_cast<unsigned char>(c))));
    Token v = s.require("Option", "a value");
    Param p;
    p.name = name;
    p.loc = loc;
    double x;
    if (v.kind == TokenKind::String) {
        p.type = ParamType::String;
        p.strings.emplace_back(v.text);
    } else if (v.kind == TokenKind::Identifier && (v.text == "true" || v.text == "false")) {
        p.type = ParamType::Bool;
        p.bools.push_back(v.text == "true" ? 1 : 0);
    } else if (v.kind == TokenKind::Number && name == "seed") {
        int i = 0;
        if (parse_int(v.text, i) != IntParse::Ok)
            throw_error(s.loc(v), "Option \"seed\": expected an integer, got {}", describe(v));
        p.type = ParamType::Integer;
        p.numbers.push_back(i);
    } else if (v.kind == TokenKind::Number && parse_double(v.text, x)) {
        p.type = ParamType::Float;
        p.numbers.push_back(x);
    } else {
        throw_error(s.loc(v), "Option \"{}\": expected true, false, a number or a quoted string, got {}",
                    name_tok.text, describe(v));
    }
    for (Param& q : m_options)
        if (q.name == p.name) {
            q = std::move(p);
            return;
        }
    m_options.push_back(std::move(p));
}

void Parser::active_transform(Stream& s, const SourceLoc& loc) {
    Token t = s.require("ActiveTransform", "All, StartTime or EndTime");
    if (t.kind == TokenKind::Identifier && t.text == "All") {
        m_gs.start_active = true;
        return;
    }
    bool start = t.text == "StartTime", end = t.text == "EndTime";
    if (t.kind != TokenKind::Identifier || !(start || end))
        throw_error(s.loc(t), "ActiveTransform: expected All, StartTime or EndTime, got {}",
                    describe(t));
    m_gs.start_active = start;
    warning(loc, fmt::format("ActiveTransform {}: motion blur is not supported; only the "
                             "start-time transformation is used{}",
                             t.text, end ? " (transformations for EndTime are ignored)" : ""));
}

std::string Parser::resolve(const std::string& name, const std::string& dir,
                            std::string_view what, const SourceLoc& loc) const {
    std::error_code ec;
    fs::path p(name);
    if (p.is_absolute()) {
        if (fs::exists(p, ec)) return name;
        throw_error(loc, "{}: cannot find file \"{}\"", what, name);
    }
    fs::path a = fs::path(m_base_dir) / p;
    if (fs::exists(a, ec)) return a.lexically_normal().string();
    fs::path b = fs::path(dir) / p;
    if (dir != m_base_dir && fs::exists(b, ec)) return b.lexically_normal().string();
    if (dir != m_base_dir)
        throw_error(loc, "{}: cannot find file \"{}\" (looked in \"{}\" and \"{}\")", what, name,
                    m_base_dir, dir);
    throw_error(loc, "{}: cannot find file \"{}\" (looked in \"{}\")", what, name, m_base_dir);
}

void Parser::include(Stream& s, const std::string& dir, int depth, const SourceLoc& loc,
                     bool import) {
    const char* what = import ? "Import" : "Include";
    if (import && !m_in_world)
        throw_error(loc, "Import is only allowed after WorldBegin (in the world block)");
    std::string name(s.expect_string(what).text);
    if (depth >= 64)
        throw_error(loc, "{} nesting is deeper than 64 files (does a file include itself?)",
                    what);
    std::string path = resolve(name, dir, what, loc);
    std::unique_ptr<Tokenizer> tz = Tokenizer::from_file(path, &loc);
    if (!import) {
        parse(*tz, parent_dir(path), depth + 1);
        return;
    }
    GraphicsState saved = m_gs;
    auto saved_coordsys = m_coordsys;
    size_t saved_floor = m_stack_floor;
    m_stack_floor = m_stack.size();
    parse(*tz, parent_dir(path), depth + 1);
    if (m_stack.size() > m_stack_floor) {
        const Pushed& top = m_stack.back();
        if (std::string_view(top.directive) == "ObjectBegin")
            throw_error(top.loc, "ObjectBegin \"{}\" without matching ObjectEnd in imported file",
                        m_object ? m_object->name : "");
        throw_error(top.loc, "{} without matching {} in imported file", top.directive,
                    std::string_view(top.directive) == "TransformBegin" ? "TransformEnd"
                                                                        : "AttributeEnd");
    }
    m_stack_floor = saved_floor;
    m_gs = std::move(saved);
    m_coordsys = std::move(saved_coordsys);
}

void Parser::parse(Tokenizer& tz, const std::string& dir, int depth) {
    Stream s(tz);
    Token tok;
    while (s.next(tok)) {
        SourceLoc loc = s.loc(tok);
        if (tok.kind != TokenKind::Identifier)
            throw_error(loc, "expected a directive, got {}{}", describe(tok),
                        tok.kind == TokenKind::Number
                            ? " (a parameter with several values needs brackets: [ ... ])"
                            : "");
        auto it = directive_table().find(tok.text);
        if (it == directive_table().end()) throw_error(loc, "unknown directive '{}'", tok.text);

        switch (it->second) {
            // -- transformations (anywhere)
            case Dir::Identity: set_ctm(Transform()); break;
            case Dir::Translate: {
                double x = s.expect_number("Translate"), y = s.expect_number("Translate"),
                       z = s.expect_number("Translate");
                concat(Transform::translate({x, y, z}));
                break;
            }
            case Dir::Scale: {
                double x = s.expect_number("Scale"), y = s.expect_number("Scale"),
                       z = s.expect_number("Scale");
                if (x == 0 || y == 0 || z == 0)
                    throw_error(loc, "Scale: a zero scale factor makes the transformation singular");
                concat(Transform::scale({x, y, z}));
                break;
            }
            case Dir::Rotate: {
                double a = s.expect_number("Rotate"), x = s.expect_number("Rotate"),
                       y = s.expect_number("Rotate"), z = s.expect_number("Rotate");
                if (x == 0 && y == 0 && z == 0)
                    throw_error(loc, "Rotate: the rotation axis is the zero vector");
                concat(Transform::rotate(a, {x, y, z}));
                break;
            }
            case Dir::LookAt: {
                double v[9];
                for (double& x : v) x = s.expect_number("LookAt");
                try {
                    concat(Transform::look_at({v[0], v[1], v[2]}, {v[3], v[4], v[5]},
                                              {v[6], v[7], v[8]}));
                } catch (const Error& e) {
                    throw Error(loc, e.what());
                }
                break;
            }
            case Dir::Transform: set_ctm(read_matrix(s, "Transform", loc)); break;
            case Dir::ConcatTransform: concat(read_matrix(s, "ConcatTransform", loc)); break;
            case Dir::CoordinateSystem:
                m_coordsys[std::string(s.expect_string("CoordinateSystem").text)] = m_gs.ctm;
                break;
            case Dir::CoordSysTransform: {
                std::string name(s.expect_string("CoordSysTransform").text);
                auto c = m_coordsys.find(name);
                if (c == m_coordsys.end())
                    warning(loc, fmt::format("CoordSysTransform: no coordinate system named "
                                             "\"{}\"; the transformation is unchanged",
                                             name));
                else
                    m_gs.ctm = c->second;
                break;
            }
            case Dir::ActiveTransform: active_transform(s, loc); break;
            case Dir::TransformTimes:
                require_options("TransformTimes", loc);
                s.expect_number("TransformTimes");
                s.expect_number("TransformTimes");
                break;

            // -- options block
            case Dir::Camera: {
                require_options("Camera", loc);
                auto [type, params] = parse_entity(s, "Camera");
                CameraDesc c;
                c.type = std::move(type);
                c.params = make_params(std::move(params), nullptr);
                c.loc = loc;
                c.camera_from_world = m_gs.ctm;
                c.world_from_camera = m_gs.ctm.inverse();
                m_coordsys["camera"] = c.world_from_camera;
                m_scene.camera = std::move(c);
                break;
            }
            case Dir::Film:
            case Dir::Sampler:
            case Dir::Integrator:
            case Dir::PixelFilter:
            case Dir::Accelerator: {
                require_options(tok.text, loc);
                auto [type, params] = parse_entity(s, tok.text);
                EntityDesc e{std::move(type), make_params(std::move(params), nullptr), loc};
                Dir d = it->second;
                (d == Dir::Film          ? m_scene.film
                 : d == Dir::Sampler     ? m_scene.sampler
                 : d == Dir::Integrator  ? m_scene.integrator
                 : d == Dir::PixelFilter ? m_scene.filter
                                         : m_scene.accelerator) = std::move(e);
                break;
            }
            case Dir::ColorSpace: {
                std::string name(s.expect_string("ColorSpace").text);
                m_scene.color_spaces.push_back(EntityDesc{std::move(name), {}, loc});
                break;
            }
            case Dir::Option: option(s); break;
            case Dir::WorldBegin:
                if (m_in_world)
                    throw_error(loc, "WorldBegin: the world block already began at {}",
                                m_world_loc.to_string());
                m_in_world = true;
                m_world_loc = loc;
                m_gs.ctm = Transform();
                m_gs.start_active = true;
                m_coordsys["world"] = Transform();
                break;
            case Dir::WorldEnd: break;  // pbrt-v3; pbrt-v4 has no WorldEnd

            // -- attributes
            case Dir::AttributeBegin: attribute_begin("AttributeBegin", loc); break;
            case Dir::AttributeEnd: attribute_end("AttributeEnd", loc); break;
            case Dir::TransformBegin:
                attribute_begin("TransformBegin", loc);
                if (!m_warned_transform_begin) {
                    m_warned_transform_begin = true;
                    warning(loc,
                            "TransformBegin/TransformEnd are deprecated in pbrt-v4; like "
                            "AttributeBegin/AttributeEnd they save and restore all attributes");
                }
                break;
            case Dir::TransformEnd: attribute_end("TransformEnd", loc); break;
            case Dir::Attribute: attribute(s); break;
            case Dir::ReverseOrientation:
                require_world("ReverseOrientation", loc);
                m_gs.reverse_orientation = !m_gs.reverse_orientation;
                break;

            // -- world block
            case Dir::Shape: shape(s, loc); break;
            case Dir::Material: {
                require_world("Material", loc);
                auto [type, params] = parse_entity(s, "Material");
                MaterialDesc m;
                m.type = std::move(type);
                m.params = make_params(std::move(params), &m_gs.material_attrs);
                m.loc = loc;
                m_gs.material = MaterialRef{int(m_scene.materials.size()), "", loc};
                m_scene.materials.push_back(std::move(m));
                break;
            }
            case Dir::MakeNamedMaterial: make_named_material(s, loc); break;
            case Dir::NamedMaterial: {
                require_world("NamedMaterial", loc);
                std::string name(s.expect_string("NamedMaterial").text);
                if (name.empty()) throw_error(loc, "NamedMaterial: empty material name");
                m_gs.material = MaterialRef{-1, std::move(name), loc};
                break;
            }
            case Dir::Texture: texture(s, loc); break;
            case Dir::LightSource: {
                require_world("LightSource", loc);
                auto [type, params] = parse_entity(s, "LightSource");
                LightDesc l;
                l.type = std::move(type);
                l.params = make_params(std::move(params), &m_gs.light_attrs);
                l.loc = loc;
                l.world_from_light = m_gs.ctm;
                if (m_object)
                    warning(loc, fmt::format("LightSource inside ObjectBegin \"{}\" is not "
                                             "instanced: it is added once, with the current "
                                             "transformation (as in pbrt-v4)",
                                             m_object->name));
                m_scene.lights.push_back(std::move(l));
                break;
            }
            case Dir::Meter: {
                // steradian extension: a photometric meter (docs/photometry.md).
                require_world("Meter", loc);
                auto [type, params] = parse_entity(s, "Meter");
                MeterDesc m;
                m.type = std::move(type);
                m.params = make_params(std::move(params), nullptr);
                m.loc = loc;
                m.world_from_meter = m_gs.ctm;
                if (m_object) throw_error(loc, "Meter is not allowed inside ObjectBegin");
                m_scene.meters.push_back(std::move(m));
                break;
            }
            case Dir::AreaLightSource: {
                require_world("AreaLightSource", loc);
                auto [type, params] = parse_entity(s, "AreaLightSource");
                AreaLightDesc a;
                a.type = std::move(type);
                a.params = make_params(std::move(params), &m_gs.light_attrs);
                a.loc = loc;
                m_gs.area_light = int(m_scene.area_lights.size());
                m_scene.area_lights.push_back(std::move(a));
                break;
            }
            case Dir::ObjectBegin: object_begin(s, loc); break;
            case Dir::ObjectEnd: object_end(loc); break;
            case Dir::ObjectInstance: {
                require_world("ObjectInstance", loc);
                std::string name(s.expect_string("ObjectInstance").text);
                if (m_object)
                    throw_error(loc,
                                "ObjectInstance \"{}\" inside the definition of object \"{}\": "
                                "instances cannot be nested",
                                name, m_object->name);
                m_scene.instance_uses.push_back(InstanceUse{std::move(name), m_gs.ctm, loc});
                break;
            }

            // -- media: parsed and ignored
            case Dir::MakeNamedMedium: {
                auto [name, params] = parse_entity(s, "MakeNamedMedium");
                warning(loc, fmt::format("participating media are not supported; "
                                         "MakeNamedMedium \"{}\" is ignored",
                                         name));
                break;
            }
            case Dir::MediumInterface: {
                std::string inside(s.expect_string("MediumInterface").text), outside = inside;
                Token t;
                if (s.next(t)) {
                    if (t.kind == TokenKind::String) outside = std::string(t.text);
                    else s.unget(t);
                }
                if (!inside.empty() || !outside.empty())
                    warning(loc, "participating media are not supported; MediumInterface is "
                                 "ignored");
                break;
            }

            // -- files
            case Dir::Include: include(s, dir, depth, loc, false); break;
            case Dir::Import: include(s, dir, depth, loc, true); break;
        }
    }
}

SceneDesc Parser::finish(const SourceLoc& eof) {
    if (m_stack.size() > 0) {
        const Pushed& top = m_stack.back();
        std::string_view d = top.directive;
        if (d == "ObjectBegin")
            throw_error(top.loc, "ObjectBegin \"{}\" without matching ObjectEnd (end of file)",
                        m_object ? m_object->name : "");
        throw_error(top.loc, "{} without matching {} (end of file)", d,
                    d == "TransformBegin" ? "TransformEnd" : "AttributeEnd");
    }
    if (!m_in_world) throw_error(eof, "end of file before WorldBegin: the scene has no world block");
    for (const InstanceUse& u : m_scene.instance_uses)
        if (m_scene.instances.find(u.name) == m_scene.instances.end())
            throw_error(u.loc, "ObjectInstance: object \"{}\" is not defined", u.name);
    for (Param& p : m_options) m_scene.options.add(std::move(p));
    return std::move(m_scene);
}

}  // namespace

SceneDesc parse_pbrt_file(const std::string& path) {
    std::unique_ptr<Tokenizer> tz = Tokenizer::from_file(path);
    std::string dir = parent_dir(path);
    Parser parser(dir);
    parser.parse(*tz, dir, 0);
    return parser.finish(tz->end_loc());
}

SceneDesc parse_pbrt_string(const std::string& text, const std::string& filename,
                            const std::string& base_dir) {
    Tokenizer tz(text, filename);
    Parser parser(base_dir);
    parser.parse(tz, base_dir, 0);
    return parser.finish(tz.end_loc());
}

}  // namespace sr
