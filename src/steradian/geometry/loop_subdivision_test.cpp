#include "steradian/geometry/loop_subdivision.h"

#include <gtest/gtest.h>

#include <cmath>

#include "steradian/core/error.h"

namespace sr {
namespace {

// A regular tetrahedron, faces wound counter-clockwise seen from outside.
const std::vector<Point3> kTetra = {{1, 1, 1}, {1, -1, -1}, {-1, 1, -1}, {-1, -1, 1}};
const std::vector<int> kTetraFaces = {0, 1, 2, 0, 3, 1, 0, 2, 3, 1, 3, 2};

// The limit position of a vertex is invariant under subdivision, and Loop's limit mask
// gives it from any level: for valence 3, gamma = 1 / (3 + 3 / (8 * 3/16)) = 1/5, so the
// tetrahedron's vertex v0 tends to (1 - 3/5) v0 + 1/5 (v1 + v2 + v3) = (1/5, 1/5, 1/5).
TEST(LoopSubdivision, TetrahedronVerticesTendToTheLimitMask) {
    for (int levels = 0; levels <= 4; ++levels) {
        SubdividedMesh m = loop_subdivide(kTetra, kTetraFaces, levels);
        EXPECT_EQ(m.indices.size(), kTetraFaces.size() * size_t(std::pow(4, levels)));
        for (int v = 0; v < 4; ++v) {
            Vec3 expected = Vec3(kTetra[size_t(v)]) * Float(0.4);
            for (int o = 0; o < 4; ++o)
                if (o != v) expected += Vec3(kTetra[size_t(o)]) * Float(0.2);
            EXPECT_NEAR(m.p[size_t(v)].x, expected.x, 1e-5f) << levels << " " << v;
            EXPECT_NEAR(m.p[size_t(v)].y, expected.y, 1e-5f) << levels << " " << v;
            EXPECT_NEAR(m.p[size_t(v)].z, expected.z, 1e-5f) << levels << " " << v;
            // By symmetry the limit normal at a vertex is radial. pbrt-v4 walks an interior
            // vertex's one-ring against the faces' winding (SDVertex::oneRing), so for
            // outward-wound faces the tangent masks' cross product points inwards.
            const Vec3 n = normalize(Vec3(m.n[size_t(v)].x, m.n[size_t(v)].y, m.n[size_t(v)].z));
            const Vec3 radial = normalize(Vec3(kTetra[size_t(v)]));
            EXPECT_NEAR(dot(n, radial), -1, 1e-5f) << levels << " " << v;
        }
    }
}

// One step of the masks by hand on the tetrahedron: an edge point is 3/8 of its ends plus
// 1/8 of the two opposite vertices; every limit point lies inside the control hull.
TEST(LoopSubdivision, EdgePointsAndHull) {
    SubdividedMesh m = loop_subdivide(kTetra, kTetraFaces, 1);
    ASSERT_EQ(m.p.size(), 4u + 6u);
    for (const Point3& p : m.p) EXPECT_LT(std::abs(p.x) + std::abs(p.y) + std::abs(p.z), 3.0f);
    // Every vertex of a regular tetrahedron's subdivision is at the same distance from the
    // centre as its kind (even or odd) by symmetry.
    const Float even = length(Vec3(m.p[0])), odd = length(Vec3(m.p[4]));
    for (size_t i = 0; i < 4; ++i) EXPECT_NEAR(length(Vec3(m.p[i])), even, 1e-5f);
    for (size_t i = 4; i < 10; ++i) EXPECT_NEAR(length(Vec3(m.p[i])), odd, 1e-5f);
}

// A flat open patch stays flat, and boundary vertices use the boundary masks: a square of
// two triangles at z = 0 keeps z = 0 and its corners move along the boundary only.
TEST(LoopSubdivision, FlatPatchWithBoundary) {
    const std::vector<Point3> p = {{0, 0, 0}, {1, 0, 0}, {1, 1, 0}, {0, 1, 0}};
    SubdividedMesh m = loop_subdivide(p, {0, 1, 2, 0, 2, 3}, 3);
    for (const Point3& q : m.p) EXPECT_NEAR(q.z, 0, 1e-6f);
    for (const Normal3& n : m.n) {
        EXPECT_NEAR(std::abs(n.z), length(Vec3(n.x, n.y, n.z)), 1e-5f);
        EXPECT_GT(length(Vec3(n.x, n.y, n.z)), 0);
    }
    // Corner 1 (valence 2 on the boundary): 3/5 v + 1/5 of its two boundary neighbours,
    // which after subdivision are edge midpoints, so the limit stays on the square's edges.
    EXPECT_GE(m.p[1].x, 0.5f);
}

TEST(LoopSubdivision, BadMeshesAreErrors) {
    // An edge of three triangles.
    EXPECT_THROW(loop_subdivide({{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {0, -1, 0}, {0, 0, 1}},
                                {0, 1, 2, 1, 0, 3, 0, 1, 4}, 1),
                 Error);
    EXPECT_THROW(loop_subdivide(kTetra, {0, 1, 7}, 1), Error);
    EXPECT_THROW(loop_subdivide(kTetra, {0, 1}, 1), Error);
    EXPECT_THROW(loop_subdivide(kTetra, kTetraFaces, 40), Error);  // too many triangles
}

}  // namespace
}  // namespace sr
