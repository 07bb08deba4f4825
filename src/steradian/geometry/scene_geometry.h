#pragma once
/// The scene's geometry as the acceleration structure sees it: shapes with the material and
/// light ids their hits report, ObjectBegin/ObjectEnd prototypes and their instances, and a
/// non-owning view of them (GeometryView) from which accel/ builds Embree's scenes. The
/// runtime Scene (scene/) owns these vectors; accel/ reads them and knows nothing else of
/// the scene, so the layers run one way: geometry <- accel <- scene.
#include <memory>
#include <span>
#include <string>
#include <variant>
#include <vector>

#include "steradian/core/transform.h"
#include "steradian/geometry/curves.h"
#include "steradian/geometry/hit.h"
#include "steradian/geometry/shapes.h"
#include "steradian/sampling/hash.h"

namespace sr {

using ShapeGeometry = std::variant<TriangleMesh, Sphere, Disk, Cylinder, Curves>;

/// A shape's alpha (pbrt-v4's "alpha" cut-outs), given by the scene (a float texture):
/// the fraction of the rays meeting the surface at a hit that stop there.
class AlphaMask {
public:
    virtual ~AlphaMask() = default;
    virtual Float alpha(const SurfaceHit& hit) const = 0;
};

/// Whether a ray (origin o, direction d) stops at `hit` of a shape with alpha `mask`, as
/// pbrt-v4 decides: always where alpha >= 1, never where alpha <= 0, and in between when a
/// hash of the ray, uniform in [0, 1), is at most alpha (so a surface of alpha 0.3 stops 30 %
/// of the rays, deterministically: the same ray always decides the same way).
inline bool alpha_stops(const AlphaMask& mask, const SurfaceHit& hit, Point3 o, Vec3 d) {
    const Float a = mask.alpha(hit);
    if (a >= 1) return true;
    if (!(a > 0)) return false;
    const uint64_t h = hash(o.x, o.y, o.z, d.x, d.y, d.z);
    return Float(double(h >> 11) * 0x1p-53) <= a;
}

struct ShapeEntry {
    ShapeGeometry geometry;
    int material = -1;     ///< index into Scene::materials; -1 = interface
    int light_offset = -1; ///< first light of this shape (one per triangle), or -1
    /// Cut-outs; null: opaque.
    std::shared_ptr<const AlphaMask> alpha;
    /// MediumInterface: the media (indices into Scene::media, -1 = vacuum) on the side the
    /// geometric normal points away from (inside) and towards (outside). Only a transition
    /// (inside != outside) changes a ray's medium; other surfaces keep the ray's medium.
    int medium_inside = -1, medium_outside = -1;
    bool medium_transition() const { return medium_inside != medium_outside; }
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
    /// The camera paths the render will trace (pixels x samples per pixel), or 0 if not
    /// known (then the acceleration structure is built for tracing, whatever its build
    /// costs). It chooses Embree's build quality for very large meshes (accel.cpp).
    uint64_t expected_camera_paths = 0;
};

}  // namespace sr
