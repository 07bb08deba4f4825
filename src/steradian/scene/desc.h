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
};

/// A reference to a material: an anonymous one by index, or a named one by name (resolved
/// by the builder, so MakeNamedMaterial may come after NamedMaterial as in pbrt-v4).
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
    std::string value_type;  ///< "float" or "spectrum"
    Transform world_from_texture;
};

struct LightDesc : EntityDesc {
    Transform world_from_light;
};

struct AreaLightDesc : EntityDesc {};

struct ShapeDesc : EntityDesc {
    Transform world_from_object;
    bool reverse_orientation = false;
    MaterialRef material;
    int area_light = -1;  ///< into SceneDesc::area_lights, or -1
};

/// ObjectBegin ... ObjectEnd: shapes in the instance's own space.
struct InstanceDefinition {
    std::string name;
    std::vector<ShapeDesc> shapes;
    SourceLoc loc;
};

struct InstanceUse {
    std::string name;
    Transform world_from_instance;
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
    std::vector<EntityDesc> color_spaces;  ///< ColorSpace directives (only "srgb" is supported)

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

    /// Directory of the main scene file: relative file names in parameters resolve here.
    std::string base_dir;
};

}  // namespace sr
