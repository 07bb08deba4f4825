#pragma once
/// Loop subdivision (C. Loop, "Smooth Subdivision Surfaces Based on Triangles", M.S. thesis,
/// University of Utah, 1987), as pbrt-v4's "loopsubdiv" shape applies it: `levels` rounds of
/// 1-to-4 splitting with Loop's masks (even vertices: (1 - n beta) v + beta * one-ring, beta
/// = 3/16 for valence 3 and 3 / (8 n) otherwise; boundary 3/4 v + 1/8 of its two boundary
/// neighbours; odd vertices 3/8 of the edge's ends + 1/8 of the opposite vertices, 1/2 of
/// the ends on a boundary), then every vertex pushed to its limit position (gamma = 1 / (n +
/// 3 / (8 beta)); boundary 3/5 v + 1/5 of its boundary neighbours) with the normal of the
/// limit surface from Loop's tangent masks, oriented as pbrt-v4 orients them.
#include <vector>

#include "steradian/core/math.h"

namespace sr {

struct SubdividedMesh {
    std::vector<Point3> p;   ///< limit positions
    std::vector<Normal3> n;  ///< limit normals (not normalised)
    std::vector<int> indices;
};

/// Subdivides the triangle mesh (p, indices: 3 per triangle). Throws sr::Error for an edge
/// shared by more than two triangles, a vertex whose triangles do not form one fan, an
/// index out of range, or a result beyond kMaxSubdividedTriangles.
SubdividedMesh loop_subdivide(const std::vector<Point3>& p, const std::vector<int>& indices,
                              int levels);

inline constexpr size_t kMaxSubdividedTriangles = size_t(1) << 27;

}  // namespace sr
