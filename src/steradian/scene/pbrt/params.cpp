/// The pbrt reader's parameter lists: declarations, typed values and their counts, the
/// Attribute defaults merged into an entity's parameters, and Option values.
#include <algorithm>
#include <cctype>
#include <cmath>
#include <limits>
#include <optional>
#include <string>
#include <string_view>
#include <unordered_map>
#include <utility>
#include <vector>

#include "steradian/scene/pbrt/parser_impl.h"
#include "steradian/scene/pbrt/stream.h"

namespace sr::pbrt_detail {
namespace {

/// pbrt-v4 parameter type names, plus the pbrt-v3 names pbrt-v4 only takes with --upgrade.
std::optional<ParamType> param_type_from_name(std::string_view s) {
    static const std::unordered_map<std::string_view, ParamType> table = {
        {"integer", ParamType::Integer},
        {"float", ParamType::Float},
        {"point2", ParamType::Point2},
        {"vector2", ParamType::Vector2},
        {"point3", ParamType::Point3},
        {"point", ParamType::Point3},
        {"vector3", ParamType::Vector3},
        {"vector", ParamType::Vector3},
        {"normal3", ParamType::Normal3},
        {"normal", ParamType::Normal3},
        {"bool", ParamType::Bool},
        {"string", ParamType::String},
        {"texture", ParamType::Texture},
        {"spectrum", ParamType::Spectrum},
        {"rgb", ParamType::Rgb},
        {"color", ParamType::Rgb},
        {"blackbody", ParamType::Blackbody},
    };
    auto it = table.find(s);
    if (it == table.end()) return std::nullopt;
    return it->second;
}

}  // namespace

ParamSet make_params(std::vector<Param>&& own, const std::vector<Param>* attrs,
                     std::string_view skip) {
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

ParamSet Parser::make_params(std::vector<Param>&& own, const std::vector<Param>* attrs,
                             std::string_view skip) {
    if (attrs)
        for (const Param& a : *attrs) {
            m_attribute_values_copied += a.numbers.size() + a.strings.size() + a.bools.size() + 1;
            if (m_attribute_values_copied > kMaxAttributeValuesCopied)
                throw_error(a.loc,
                            "the Attribute defaults have been copied into the scene's entities "
                            "more than {} values' worth (each shape, light or material gets its "
                            "own copy); give large values to the entities themselves",
                            kMaxAttributeValuesCopied);
        }
    return pbrt_detail::make_params(std::move(own), attrs, skip);
}

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
        // pbrt-v4 looks parameters up in reverse order of the list, so the last of two with
        // one name wins and the first is silently shadowed (ParameterDictionary's
        // constructor reverses the list; ReportUnused accepts a shadowed one). We do the
        // same and say so. Different types under one name cannot both be meant: an error
        // (pbrt-v4 would report one of them as unused), except among the colour types,
        // which pbrt-v4's spectrum lookup matches by name alone.
        auto is_colour = [](ParamType k) {
            return k == ParamType::Rgb || k == ParamType::Blackbody || k == ParamType::Spectrum;
        };
        auto same = std::find_if(out.begin(), out.end(),
                                 [&](const Param& q) { return q.name == p.name; });
        if (same == out.end()) {
            out.push_back(std::move(p));
        } else if (same->type == p.type || (is_colour(same->type) && is_colour(p.type))) {
            warning(p.loc, fmt::format("parameter \"{}\" given again (first at {}): the last "
                                       "value is used, as pbrt-v4 does",
                                       p.name, same->loc.to_string()));
            *same = std::move(p);
        } else {
            throw_error(p.loc, "parameter \"{}\" given again with another type (first at {})",
                        p.name, same->loc.to_string());
        }
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
        case ParamType::Integer:
            kind = ValueKind::Integer;
            break;
        case ParamType::Bool:
            kind = ValueKind::Bool;
            break;
        case ParamType::String:
        case ParamType::Texture:
            kind = ValueKind::String;
            break;
        case ParamType::Spectrum:
            kind = ValueKind::Spectrum;
            break;
        default:
            kind = ValueKind::Number;
            break;
    }
    auto what = [&] { return fmt::format("parameter \"{} {}\"", type_name, name); };

    // Parameter values are 32-bit floats at run time: beyond their range a value would turn
    // into an infinity silently (a sphere of radius 1e39).
    auto check_float_range = [&](double x, const Token& v) {
        if (std::abs(x) > double(std::numeric_limits<float>::max()))
            throw_error(s.loc(v), "{}: {} is outside the range of a 32-bit float (+-3.4e38)",
                        what(), printable(v.text));
    };
    auto add_value = [&](const Token& v) {
        switch (kind) {
            case ValueKind::Number: {
                double x;
                if (v.kind != TokenKind::Number || !parse_double(v.text, x))
                    throw_error(s.loc(v), "{}: expected a number, got {}", what(), describe(v));
                check_float_range(x, v);
                p.numbers.push_back(x);
                return;
            }
            case ValueKind::Integer: {
                int x = 0;
                IntParse r =
                    v.kind == TokenKind::Number ? parse_int(v.text, x) : IntParse::NotInteger;
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
                    check_float_range(x, v);
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
            // One colour for a spectrum parameter (the builder checks that), a list of them
            // for an rgbgrid medium's grids (pbrt-v4's GetRGBArray).
            if (n == 0 || n % 3 != 0)
                throw_error(p.loc, "{} needs 3 values (or a multiple of 3 for a grid), got {}",
                            what(), n);
            break;
        case ParamType::Blackbody:
            if (n != 1)
                throw_error(p.loc, "{} needs exactly 1 value (temperature in K), got {}{}", what(),
                            n,
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
                throw_error(p.loc, "{} needs (wavelength, value) pairs, got {} values", what(), n);
            break;
        default:
            break;
    }
    return p;
}

std::pair<std::string, std::vector<Param>> Parser::parse_entity(Stream& s, std::string_view what) {
    Token t = s.expect_string(what);
    std::string type(t.text);
    return {std::move(type), parse_params(s)};
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
        throw_error(s.loc(v),
                    "Option \"{}\": expected true, false, a number or a quoted string, got {}",
                    name_tok.text, describe(v));
    }
    for (Param& q : m_options)
        if (q.name == p.name) {
            q = std::move(p);
            return;
        }
    m_options.push_back(std::move(p));
}

}  // namespace sr::pbrt_detail
