/// The pbrt reader's graphics state directives: matrices, the attribute and object stack,
/// Attribute defaults and ActiveTransform.
#include "steradian/scene/pbrt/graphics_state.h"

#include <array>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

#include "steradian/scene/pbrt/parser_impl.h"
#include "steradian/scene/pbrt/stream.h"

namespace sr::pbrt_detail {

Transform Parser::read_matrix(Stream& s, std::string_view what, const SourceLoc& loc) {
    Token t = s.require(what, "'['");
    if (t.kind != TokenKind::LBracket)
        throw_error(s.loc(t), "{}: expected '[' before the 16 matrix values, got {}", what,
                    describe(t));
    std::array<double, 16> v;
    for (double& x : v) x = s.expect_number(what);
    t = s.require(what, "']'");
    if (t.kind != TokenKind::RBracket)
        throw_error(s.loc(t), "{}: expected ']' after 16 matrix values, got {}", what, describe(t));
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
    if (target == "shape")
        dst = &m_gs.shape_attrs;
    else if (target == "light")
        dst = &m_gs.light_attrs;
    else if (target == "material")
        dst = &m_gs.material_attrs;
    else if (target == "medium")
        dst = &m_gs.medium_attrs;
    else if (target == "texture")
        dst = &m_gs.texture_attrs;
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

}  // namespace sr::pbrt_detail
