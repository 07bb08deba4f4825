#pragma once
/// The scene's geometry as the acceleration structure sees it: shapes with the material and
/// light ids their hits report, ObjectBegin/ObjectEnd prototypes and their instances, and a
/// non-owning view of them (GeometryView) from which accel/ builds Embree's scenes. The
/// runtime Scene (scene/) owns these vectors; accel/ reads them and knows nothing else of
/// the scene, so the layers run one way: geometry <- accel <- scene.
#include <span>
#include <string>
#include <variant>
#include <vector>

#include "steradian/core/transform.h"
#include "steradian/geometry/shapes.h"

namespace sr {

using ShapeGeometry = std::variant<TriangleMesh, Sphere, Disk>;

struct ShapeEntry {
    ShapeGeometry geometry;
    int material = -1;     ///< index into Scene::materials; -1 = interface
    int light_offset = -1; ///< first light of this shape (one per triangle), or -1
};

/// ObjectBegin/ObjectEnd: shapes in their own space, instanced by Embree.
struct Prototype {
    std::string name;
    std::vector<int> shapes;
};

struct Instance {
    int prototype = -1;
    Transform world_from_instance;
};

/// What the acceleration structure is built from. Indices in `top_level_shapes` and in the
/// prototypes' `shapes` refer to `shapes`; an instance's `prototype` to `prototypes`.
struct GeometryView {
    std::span<const ShapeEntry> shapes;
    std::span<const int> top_level_shapes;  ///< shapes in world space (not in prototypes)
    std::span<const Prototype> prototypes;
    std::span<const Instance> instances;
};

}  // namespace sr
