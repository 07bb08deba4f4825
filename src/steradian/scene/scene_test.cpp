#include "steradian/scene/scene.h"

#include <gtest/gtest.h>

#include <cstring>
#include <vector>

#include "steradian/scene/build.h"
#include "steradian/scene/pbrt/parser.h"

namespace sr {
namespace {

// SurfaceHit is compared byte for byte below: it must have no padding.
static_assert(sizeof(SurfaceHit) == 37 * 4, "SurfaceHit: 37 four-byte fields, no padding");

// One shape of each kind the accelerator fills differently: a curved triangle mesh with vertex
// normals (its hits have normal derivatives), a flat mesh without, a sphere, a disk, and an
// instanced sphere. The rays run along -z towards them.
const char* kScene = R"(
Camera "perspective"
Film "rgb" "integer xresolution" [4] "integer yresolution" [4]
WorldBegin
Material "diffuse"
Shape "trianglemesh" "integer indices" [0 1 2]
    "point3 P" [-10 -1 0  -8 -1 0  -9 1 0.5]
    "normal N" [-0.3 0 1  0.3 0 1  0 0.4 1]
Shape "trianglemesh" "integer indices" [0 1 2] "point3 P" [-6 -1 0  -4 -1 0  -5 1 0]
Shape "sphere" "float radius" 1
AttributeBegin
  Translate 5 0 0
  Shape "disk" "float radius" 1
AttributeEnd
ObjectBegin "ball"
  Shape "sphere" "float radius" 0.8
ObjectEnd
AttributeBegin
  Translate 9 0 0
  ObjectInstance "ball"
AttributeEnd
)";

Ray ray_at(Float x) { return Ray{Point3(x, 0.1f, 10), Vec3(0, 0, -1), kInfinity}; }

// Scene::intersect writes every field of the record, whatever it held: a record first filled
// with NaN bytes, or with a previous hit that had normal derivatives, ends byte for byte as a
// fresh one does. (The path integrator keeps one record per path and relies on this.)
TEST(SceneIntersect, WritesEveryFieldOfTheHit) {
    Scene s = build_scene(parse_pbrt_string(kScene, "<test>"));
    const std::vector<Float> xs = {-9, -5, 0, 5, 9};
    SurfaceHit curved;
    ASSERT_TRUE(s.intersect(ray_at(-9), curved));
    ASSERT_NE(length_squared(curved.dndu) + length_squared(curved.dndv), 0)
        << "the curved mesh should give normal derivatives";
    for (Float x : xs) {
        SurfaceHit fresh;
        ASSERT_TRUE(s.intersect(ray_at(x), fresh)) << x;
        SurfaceHit garbage;
        std::memset(static_cast<void*>(&garbage), 0xff, sizeof garbage);
        ASSERT_TRUE(s.intersect(ray_at(x), garbage)) << x;
        EXPECT_EQ(std::memcmp(&fresh, &garbage, sizeof fresh), 0) << "after NaN bytes, x = " << x;
        SurfaceHit reused = curved;
        ASSERT_TRUE(s.intersect(ray_at(x), reused)) << x;
        EXPECT_EQ(std::memcmp(&fresh, &reused, sizeof fresh), 0) << "after a curved hit, x = " << x;
    }
}

}  // namespace
}  // namespace sr
