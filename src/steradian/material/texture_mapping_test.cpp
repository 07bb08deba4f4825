// pbrt-v4's 2D texture mappings (textures.h: UVMapping, SphericalMapping, CylindricalMapping,
// PlanarMapping) against (s, t) computed by hand from their definitions.
#include <gtest/gtest.h>

#include "steradian/material/texture.h"

namespace sr {
namespace {

constexpr Float kEps = 1e-6f;

TEST(TextureMapping, UvScalesAndOffsets) {
    UvMapping m;
    m.su = 2;
    m.sv = 3;
    m.du = 0.5f;
    m.dv = -1;
    SurfaceHit h;
    h.uv = Point2(0.25f, 0.5f);
    h.p = Point3(7, 8, 9);  // ignored by "uv"
    const Point2 st = m.map(h);
    EXPECT_NEAR(st.x, 2 * 0.25f + 0.5f, kEps);
    EXPECT_NEAR(st.y, 3 * 0.5f - 1, kEps);
}

TEST(TextureMapping, SphericalIsThetaOverPiAndPhiOverTwoPi) {
    UvMapping m;
    m.kind = UvMapping::Kind::Spherical;
    // +z: theta 0. +x: theta pi/2, phi 0. -y: theta pi/2, phi 3 pi/2. Distance is irrelevant.
    EXPECT_NEAR(m.map_position(Point3(0, 0, 2)).x, 0, kEps);
    const Point2 a = m.map_position(Point3(3, 0, 0));
    EXPECT_NEAR(a.x, 0.5f, kEps);
    EXPECT_NEAR(a.y, 0, kEps);
    const Point2 b = m.map_position(Point3(0, -1, 0));
    EXPECT_NEAR(b.x, 0.5f, kEps);
    EXPECT_NEAR(b.y, 0.75f, kEps);
    // theta = 135 degrees: s = 0.75; phi = 45 degrees: t = 0.125.
    const Point2 c = m.map_position(Point3(1, 1, -std::sqrt(Float(2))));
    EXPECT_NEAR(c.x, 0.75f, 1e-5f);
    EXPECT_NEAR(c.y, 0.125f, 1e-5f);
    // The texture's space: a texture defined after "Translate 1 0 0" is centred at x = 1.
    m.texture_from_world = Transform::translate(Vec3d(-1, 0, 0));
    EXPECT_NEAR(m.map_position(Point3(1, 0, 5)).x, 0, kEps);
}

TEST(TextureMapping, CylindricalIsAngleAroundZAndHeight) {
    UvMapping m;
    m.kind = UvMapping::Kind::Cylindrical;
    // s = (pi + atan2(y, x)) / 2 pi, t = z.
    const Point2 a = m.map_position(Point3(-1, 0, 5));  // atan2(0, -1) = pi
    EXPECT_NEAR(a.x, 1, kEps);
    EXPECT_NEAR(a.y, 5, kEps);
    const Point2 b = m.map_position(Point3(0, 1, 2));  // atan2(1, 0) = pi / 2
    EXPECT_NEAR(b.x, 0.75f, kEps);
    EXPECT_NEAR(b.y, 2, kEps);
    const Point2 c = m.map_position(Point3(0, -3, -1));  // -pi / 2
    EXPECT_NEAR(c.x, 0.25f, kEps);
}

TEST(TextureMapping, PlanarProjectsOntoV1AndV2) {
    UvMapping m;
    m.kind = UvMapping::Kind::Planar;
    m.v1 = Vec3(1, 1, 0);
    m.v2 = Vec3(0, 0, 2);
    m.du = 0.5f;
    m.dv = -0.25f;
    const Point2 st = m.map_position(Point3(1, 2, 3));
    EXPECT_NEAR(st.x, 0.5f + 3, kEps);    // du + (1, 2, 3) . (1, 1, 0)
    EXPECT_NEAR(st.y, -0.25f + 6, kEps);  // dv + (1, 2, 3) . (0, 0, 2)
    SurfaceHit h;
    h.p = Point3(1, 2, 3);
    h.uv = Point2(0.9f, 0.9f);  // ignored by "planar"
    EXPECT_NEAR(m.map(h).x, 3.5f, kEps);
}

}  // namespace
}  // namespace sr
