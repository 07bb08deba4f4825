#pragma once
/// The format-neutral scene description (IR) that readers produce and the builder consumes.
/// No runtime objects here: only types, parameters, transforms and source locations.
#include <map>
#include <string>
#include <vector>

#include "steradian/core/error.h"
#include "steradian/core/transform.h"
#include "steradian/scene/param_set.h"

namespace sr {

/// An entity as written: its type name ("perspective", "diffuse", ...), parameters, and
/// the location of its directive.
struct EntityDesc {
    std::string type;
    ParamSet params;
    SourceLoc loc;
};

struct CameraDesc : EntityDesc {
    Transform camera_from_world;  ///< CTM at the Camera directive
    Transform world_from_camera;
    std::string medium;  ///< the outside medium of the MediumInterface at Camera ("": none)
};

/// MakeNamedMedium "name" "string type" ...: `type` is the "type" parameter's value.
struct MediumDesc : EntityDesc {
    std::string name;
    Transform world_from_medium;  ///< CTM at the directive
};

/// The MediumInterface in effect at a Shape directive (names of MakeNamedMedium; "" =
/// vacuum), with where it was given.
struct MediumNames {
    std::string inside, outside;
    SourceLoc loc;
};

/// A reference to a material: an anonymous one by index, or a named one by name (resolved
/// by the builder, so MakeNamedMaterial may come after NamedMaterial as in pbrt-v4).
/// Neither (index < 0, empty name): no Material/NamedMaterial directive was in effect, so
/// pbrt-v4's default material applies ("diffuse" with default parameters).
struct MaterialRef {
    int index = -1;    ///< into SceneDesc::materials, if >= 0
    std::string name;  ///< named material, if index < 0 and non-empty
    SourceLoc loc;     ///< where the Material/NamedMaterial directive was
};

struct MaterialDesc : EntityDesc {
    std::string name;  ///< empty for anonymous materials; for named ones, `type` is the
                       ///< "string type" parameter's value (consumed by the reader)
};

struct TextureDesc : EntityDesc {
    std::string name;
    std::string value_type;  ///< "float" or "spectrum"; each has its own name space
    Transform world_from_texture;  ///< CTM at the Texture directive
};

struct LightDesc : EntityDesc {
    Transform world_from_light;  ///< CTM at the LightSource directive
    /// The outside medium of the MediumInterface at the LightSource directive ("": none): the
    /// medium its light paths start in (pbrt-v4's light mediumInterface.outside).
    std::string medium;
};

/// Meter "type" ... (a steradian extension, docs/photometry.md): points and directions
/// are given in the coordinate system of the CTM at the directive.
struct MeterDesc : EntityDesc {
    Transform world_from_meter;
    /// The outside medium of the MediumInterface at the Meter directive ("": none): the
    /// medium its measuring points are in, as a camera's is the one at Camera.
    std::string medium;
};

/// One per AreaLightSource directive; every shape created while it is in effect refers to
/// it (pbrt-v4 creates one light per shape from these same parameters).
struct AreaLightDesc : EntityDesc {};

struct ShapeDesc : EntityDesc {
    /// CTM at the Shape directive. Inside ObjectBegin/ObjectEnd this is still the full CTM
    /// (including whatever was in effect at ObjectBegin), as in pbrt-v4.
    Transform world_from_object;
    /// ReverseOrientation state; the builder combines it with
    /// world_from_object.swaps_handedness() as pbrt-v4 does.
    bool reverse_orientation = false;
    MaterialRef material;
    int area_light = -1;  ///< into SceneDesc::area_lights, or -1
    MediumNames media;
};

/// ObjectBegin ... ObjectEnd: the shapes of an object, each with the full CTM that was in
/// effect at its Shape directive as world_from_object. pbrt-v4 semantics (scene.cpp): an
/// ObjectInstance places the object with CTM_use * CTM_shape, i.e. world-space points are
/// use.world_from_instance * shape.world_from_object * p_object. The CTM at ObjectBegin is
/// not factored out. Area lights are not instanced (pbrt-v4 ignores them with a warning, so
/// shapes here always have area_light == -1).
struct InstanceDefinition {
    std::string name;
    std::vector<ShapeDesc> shapes;
    SourceLoc loc;
};

/// ObjectInstance "name": may precede the definition (resolved at the end of parsing).
struct InstanceUse {
    std::string name;
    Transform world_from_instance;  ///< CTM at the ObjectInstance directive
    SourceLoc loc;
};

struct SceneDesc {
    // Options block (before WorldBegin). Absent directives keep type "" and use defaults.
    CameraDesc camera;
    EntityDesc film;
    EntityDesc sampler;
    EntityDesc integrator;
    EntityDesc filter;
    EntityDesc accelerator;
    std::vector<EntityDesc> color_spaces;  ///< ColorSpace directives (only "srgb" is supported);
                                           ///< type = the colour space name
    /// Option directives, one parameter each, named as pbrt-v4 normalises them (lower case,
    /// without '-' and '_'): quoted values are String, true/false Bool, numbers Float
    /// ("seed": Integer). A later Option of the same name replaces an earlier one.
    ParamSet options;

    // World block.
    std::vector<MaterialDesc> materials;             ///< anonymous and named
    std::map<std::string, int> named_materials;      ///< name -> index into materials
    std::vector<TextureDesc> float_textures;
    std::vector<TextureDesc> spectrum_textures;
    std::vector<LightDesc> lights;
    std::vector<AreaLightDesc> area_lights;
    std::vector<ShapeDesc> shapes;
    std::map<std::string, InstanceDefinition> instances;
    std::vector<InstanceUse> instance_uses;
    std::vector<MeterDesc> meters;
    std::vector<MediumDesc> media;  ///< in the order of their MakeNamedMedium directives

    /// Directory of the main scene file: relative file names in parameters resolve here.
    std::string base_dir;
};

}  // namespace sr
