/// The pbrt reader's directives (dispatch, scene entities, Include/Import) and its entry points.
#include "steradian/scene/pbrt/parser.h"

#include <filesystem>
#include <memory>
#include <string>
#include <string_view>
#include <system_error>
#include <unordered_map>
#include <utility>

#include "steradian/scene/pbrt/parser_impl.h"
#include "steradian/scene/pbrt/stream.h"
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
//   and MakeNamedMaterial, "medium" to MakeNamedMedium.
// - Include is textual (shared graphics state) and token-transparent: the included file's
//   tokens are spliced into the including file's stream (pbrt-v4's file stack), so a
//   parameter list at the end of an included file continues after the Include. Import parses the
//   file with a copy of the graphics state that is discarded afterwards, as pbrt-v4 does with its
//   separate builder; definitions it makes (shapes, lights, named materials, textures, objects) are
//   global. Named coordinate systems defined inside an Import are discarded too (pbrt-v4 starts the
//   imported file with none; we keep the importer's visible, a superset).
// - Relative Include/Import paths resolve against the main scene file's directory, as in
//   pbrt-v4; if the file is not there, against the including file's directory.
// - A parameter given twice in one list: the last is used, with a warning (pbrt-v4 silently
//   uses the last one); twice with types that cannot both be meant is an error.
// - Errors are thrown at the first problem; pbrt-v4 defers some of them to the end.

namespace sr::pbrt_detail {
namespace {

namespace fs = std::filesystem;

enum class Dir {
    Accelerator,
    ActiveTransform,
    AreaLightSource,
    Attribute,
    AttributeBegin,
    AttributeEnd,
    Camera,
    ColorSpace,
    ConcatTransform,
    CoordSysTransform,
    CoordinateSystem,
    Film,
    Identity,
    Import,
    Include,
    Integrator,
    LightSource,
    LookAt,
    MakeNamedMaterial,
    MakeNamedMedium,
    Material,
    MediumInterface,
    Meter,
    NamedMaterial,
    ObjectBegin,
    ObjectEnd,
    ObjectInstance,
    Option,
    PixelFilter,
    ReverseOrientation,
    Rotate,
    Sampler,
    Scale,
    Shape,
    Texture,
    Transform,
    TransformBegin,
    TransformEnd,
    TransformTimes,
    Translate,
    WorldBegin,
    WorldEnd
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

std::string parent_dir(const std::string& path) {
    std::string d = fs::path(path).parent_path().string();
    return d.empty() ? "." : d;
}

}  // namespace

// ---- directives -------------------------------------------------------------------------

void Parser::texture(Stream& s, const SourceLoc& loc) {
    require_world("Texture", loc);
    std::string name(s.expect_string("Texture").text);
    Token vt = s.expect_string("Texture");
    std::string value_type(vt.text);
    if (value_type != "float" && value_type != "spectrum")
        throw_error(
            s.loc(vt), "unknown texture type \"{}\": must be \"float\" or \"spectrum\"{}",
            value_type,
            value_type == "color" ? " (pbrt-v3's \"color\" is \"spectrum\" in pbrt-v4)" : "");
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
    if (!type)
        throw_error(loc, "MakeNamedMaterial \"{}\": missing \"string type\" parameter", name);
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

void Parser::make_named_medium(Stream& s, const SourceLoc& loc) {
    std::string name(s.expect_string("MakeNamedMedium").text);
    std::vector<Param> params = parse_params(s);
    for (const MediumDesc& m : m_scene.media)
        if (m.name == name)
            throw_error(loc, "named medium \"{}\" redefined (first defined at {})", name,
                        m.loc.to_string());
    // The "string type" parameter names the medium type; it is consumed here.
    const Param* type = nullptr;
    for (const Param& p : params)
        if (p.name == "type") type = &p;
    if (!type)
        for (const Param& p : m_gs.medium_attrs)
            if (p.name == "type") type = &p;
    if (!type) throw_error(loc, "MakeNamedMedium \"{}\": missing \"string type\" parameter", name);
    if (type->type != ParamType::String || type->strings.size() != 1)
        throw_error(type->loc,
                    "MakeNamedMedium \"{}\": \"type\" must be a single string, e.g. \"string "
                    "type\" \"homogeneous\"",
                    name);
    MediumDesc m;
    m.type = type->strings[0];
    m.params = make_params(std::move(params), &m_gs.medium_attrs, "type");
    m.loc = loc;
    m.name = std::move(name);
    m.world_from_medium = m_gs.ctm;
    m_scene.media.push_back(std::move(m));
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
    sh.media = m_gs.media;
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

std::string Parser::resolve(const std::string& name, const std::string& dir, std::string_view what,
                            const SourceLoc& loc) const {
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

void Parser::include(Stream& s, const SourceLoc& loc, bool import) {
    const char* what = import ? "Import" : "Include";
    if (import && !m_in_world)
        throw_error(loc, "Import is only allowed after WorldBegin (in the world block)");
    // The directive's own file (the name could come from a file that follows it).
    const std::string dir = s.dir();
    const int depth = s.depth();
    std::string name(s.expect_string(what).text);
    if (depth >= 64)
        throw_error(loc, "{} nesting is deeper than 64 files (does a file include itself?)", what);
    std::string path = resolve(name, dir, what, loc);
    std::unique_ptr<Tokenizer> tz = Tokenizer::from_file(path, &loc);
    if (!import) {
        // Token-transparent, as pbrt-v4: the included file's tokens continue this stream.
        s.push(std::move(tz), parent_dir(path), depth + 1);
        return;
    }
    // Import parses the file as a stream of its own (pbrt-v4 gives it its own parser).
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
        throw_error(
            top.loc, "{} without matching {} in imported file", top.directive,
            std::string_view(top.directive) == "TransformBegin" ? "TransformEnd" : "AttributeEnd");
    }
    m_stack_floor = saved_floor;
    m_gs = std::move(saved);
    m_coordsys = std::move(saved_coordsys);
}

void Parser::parse(Tokenizer& tz, const std::string& dir, int depth) {
    Stream s(tz, dir, depth);
    Token tok;
    while (s.next(tok)) {
        s.release_finished();  // no token of an earlier directive is in use any more
        SourceLoc loc = s.loc(tok);
        if (tok.kind != TokenKind::Identifier)
            throw_error(loc, "expected a directive, got {}{}", describe(tok),
                        tok.kind == TokenKind::Number
                            ? " (a parameter with several values needs brackets: [ ... ])"
                            : "");
        auto it = directive_table().find(tok.text);
        if (it == directive_table().end()) throw_error(loc, "unknown directive '{}'", printable(tok.text));

        switch (it->second) {
            // -- transformations (anywhere)
            case Dir::Identity:
                set_ctm(Transform());
                break;
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
                    throw_error(loc,
                                "Scale: a zero scale factor makes the transformation singular");
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
            case Dir::Transform:
                set_ctm(read_matrix(s, "Transform", loc));
                break;
            case Dir::ConcatTransform:
                concat(read_matrix(s, "ConcatTransform", loc));
                break;
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
            case Dir::ActiveTransform:
                active_transform(s, loc);
                break;
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
                c.medium = m_gs.media.outside;
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
            case Dir::Option:
                option(s);
                break;
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
            case Dir::WorldEnd:
                break;  // pbrt-v3; pbrt-v4 has no WorldEnd

            // -- attributes
            case Dir::AttributeBegin:
                attribute_begin("AttributeBegin", loc);
                break;
            case Dir::AttributeEnd:
                attribute_end("AttributeEnd", loc);
                break;
            case Dir::TransformBegin:
                attribute_begin("TransformBegin", loc);
                if (!m_warned_transform_begin) {
                    m_warned_transform_begin = true;
                    warning(loc,
                            "TransformBegin/TransformEnd are deprecated in pbrt-v4; like "
                            "AttributeBegin/AttributeEnd they save and restore all attributes");
                }
                break;
            case Dir::TransformEnd:
                attribute_end("TransformEnd", loc);
                break;
            case Dir::Attribute:
                attribute(s);
                break;
            case Dir::ReverseOrientation:
                require_world("ReverseOrientation", loc);
                m_gs.reverse_orientation = !m_gs.reverse_orientation;
                break;

            // -- world block
            case Dir::Shape:
                shape(s, loc);
                break;
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
            case Dir::MakeNamedMaterial:
                make_named_material(s, loc);
                break;
            case Dir::NamedMaterial: {
                require_world("NamedMaterial", loc);
                std::string name(s.expect_string("NamedMaterial").text);
                if (name.empty()) throw_error(loc, "NamedMaterial: empty material name");
                m_gs.material = MaterialRef{-1, std::move(name), loc};
                break;
            }
            case Dir::Texture:
                texture(s, loc);
                break;
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
                l.medium = m_gs.media.outside;
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
                m.medium = m_gs.media.outside;
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
            case Dir::ObjectBegin:
                object_begin(s, loc);
                break;
            case Dir::ObjectEnd:
                object_end(loc);
                break;
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

            // -- media
            case Dir::MakeNamedMedium:
                make_named_medium(s, loc);
                break;
            case Dir::MediumInterface: {
                std::string inside(s.expect_string("MediumInterface").text), outside = inside;
                Token t;
                if (s.next(t)) {
                    if (t.kind == TokenKind::String)
                        outside = std::string(t.text);
                    else
                        s.unget(t);
                }
                m_gs.media = MediumNames{std::move(inside), std::move(outside), loc};
                break;
            }

            // -- files
            case Dir::Include:
                include(s, loc, false);
                break;
            case Dir::Import:
                include(s, loc, true);
                break;
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
    if (!m_in_world)
        throw_error(eof, "end of file before WorldBegin: the scene has no world block");
    for (const InstanceUse& u : m_scene.instance_uses)
        if (m_scene.instances.find(u.name) == m_scene.instances.end())
            throw_error(u.loc, "ObjectInstance: object \"{}\" is not defined", u.name);
    for (Param& p : m_options) m_scene.options.add(std::move(p));
    return std::move(m_scene);
}

}  // namespace sr::pbrt_detail

namespace sr {

using namespace pbrt_detail;

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
