#pragma once
/// Format-neutral triangle mesh data as produced by the mesh readers (PLY, OBJ): plain arrays,
/// no runtime objects. The builder turns it into a geometry::TriangleMesh.
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <limits>
#include <string>
#include <string_view>
#include <vector>

#include "steradian/core/error.h"
#include "steradian/core/math.h"

namespace sr {

/// An indexed triangle mesh in the file's own (object) space.
/// The readers reserve one position more than they store, so that the builder's padding
/// (Embree reads 16 bytes per vertex) costs no copy; the indices have the type of Embree's.
struct TriangleMeshData {
    std::vector<Point3> p;          ///< vertex positions
    std::vector<Normal3> n;         ///< empty, or one (not necessarily unit) normal per vertex
    std::vector<Point2> uv;         ///< empty, or one texture coordinate per vertex
    std::vector<uint32_t> indices;  ///< 3 vertex indices per triangle
    std::vector<int> face_indices;  ///< empty, or one "face_indices" value per triangle

    std::size_t triangle_count() const { return indices.size() / 3; }
};

/// Checks the invariants of `mesh`: indices a multiple of 3 and in [0, p.size()), n/uv/
/// face_indices either empty or of the right length, finite positions, normals and uvs.
/// Throws sr::Error("name: ...") naming the first offending triangle or vertex.
inline void validate(const TriangleMeshData& mesh, std::string_view name) {
    auto fail = [&](const std::string& msg) { throw Error(fmt::format("{}: {}", name, msg)); };
    const std::size_t nv = mesh.p.size();
    if (nv > static_cast<std::size_t>(std::numeric_limits<int>::max()))
        fail(fmt::format("too many vertices ({})", nv));
    if (mesh.indices.size() % 3 != 0)
        fail(fmt::format("index count {} is not a multiple of 3", mesh.indices.size()));
    if (!mesh.n.empty() && mesh.n.size() != nv)
        fail(fmt::format("{} normals for {} vertices", mesh.n.size(), nv));
    if (!mesh.uv.empty() && mesh.uv.size() != nv)
        fail(fmt::format("{} texture coordinates for {} vertices", mesh.uv.size(), nv));
    if (!mesh.face_indices.empty() && mesh.face_indices.size() != mesh.triangle_count())
        fail(fmt::format("{} face indices for {} triangles", mesh.face_indices.size(),
                         mesh.triangle_count()));
    for (std::size_t i = 0; i < mesh.indices.size(); ++i) {
        const uint32_t v = mesh.indices[i];
        if (v >= nv)
            fail(fmt::format("triangle {} references vertex {} but there are {} vertices", i / 3, v,
                             nv));
    }
    auto finite3 = [](const Vec3& v) {
        return std::isfinite(v.x) && std::isfinite(v.y) && std::isfinite(v.z);
    };
    for (std::size_t i = 0; i < nv; ++i) {
        const Point3& q = mesh.p[i];
        if (!finite3(q))
            fail(fmt::format("vertex {} has a non-finite position ({}, {}, {})", i, q.x, q.y, q.z));
    }
    for (std::size_t i = 0; i < mesh.n.size(); ++i) {
        const Normal3& q = mesh.n[i];
        if (!finite3(q))
            fail(fmt::format("vertex {} has a non-finite normal ({}, {}, {})", i, q.x, q.y, q.z));
    }
    for (std::size_t i = 0; i < mesh.uv.size(); ++i) {
        const Point2& q = mesh.uv[i];
        if (!std::isfinite(q.x) || !std::isfinite(q.y))
            fail(
                fmt::format("vertex {} has a non-finite texture coordinate ({}, {})", i, q.x, q.y));
    }
}

}  // namespace sr
