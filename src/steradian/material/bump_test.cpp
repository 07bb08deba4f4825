#include <gtest/gtest.h>

#include "steradian/material/material.h"

namespace sr {
namespace {

// Bump mapping on a unit sphere at p = (1, 0, 0), n = (1, 0, 0), dp/du = (0, 1, 0),
// dp/dv = (0, 0, -1), and dn/du = dp/du / r, dn/dv = dp/dv / r (the sphere's normal is p/r).
// Displacement d(u) = 0.2 * ramp(u), the ramp of a 2x1 image (0, 1) bilinearly interpolated:
// 2 (u - 0.25) between the texel centres, so at u = 0.5: d = 0.1, dd/du = 0.4, dd/dv = 0.
// pbrt-v4's bump map: dp/du' = dp/du + dd/du n + d dn/du = (0.4, 1.1, 0),
// dp/dv' = dp/dv (1 + d) = (0, 0, -1.1), so n' ~ (1.21, -0.44, 0): the curvature term scales
// the tangents by (r + d) / r, as displacing a sphere of radius r by d gives radius r + d.
TEST(BumpMap, SphereRampMatchesTheDisplacedSurfaceNormal) {
    auto img = std::make_shared<TextureImage>();
    img->image.width = 2;
    img->image.height = 1;
    img->image.channels = 1;
    img->image.data = {0, 1};
    img->wrap = WrapMode::Clamp;
    ImageFloatTexture ramp;
    ramp.image = img;
    ramp.scale = 0.2f;
    std::vector<FloatTexture> ft = {ramp};
    std::vector<SpectrumTexture> st;
    MaterialContext ctx{&st, &ft};
    SurfaceHit h;
    h.p = Point3(1, 0, 0);
    h.ng = h.ns = Normal3(1, 0, 0);
    h.dpdu = Vec3(0, 1, 0);
    h.dpdv = Vec3(0, 0, -1);
    h.dndu = h.dpdu;
    h.dndv = h.dpdv;
    h.uv = Point2(0.5f, 0.5f);
    MaterialCommon c;
    c.displacement = 0;
    SurfaceHit b = h;
    perturb_shading(c, ctx, b);
    Vec3 expected = normalize(Vec3(1.21f, -0.44f, 0));
    EXPECT_NEAR(b.ns.x, expected.x, 2e-4);
    EXPECT_NEAR(b.ns.y, expected.y, 2e-4);
    EXPECT_NEAR(b.ns.z, 0, 1e-6);
    // The tangent lengths grow by (r + d) / r = 1.1 (dp/du' projected off the new normal).
    EXPECT_NEAR(length(b.dpdv), 1.1, 1e-4);

    // A constant displacement of a sphere leaves its normal unchanged.
    std::vector<FloatTexture> ct = {ConstantFloatTexture{0.3f}};
    MaterialContext cctx{&st, &ct};
    SurfaceHit k = h;
    perturb_shading(c, cctx, k);
    EXPECT_NEAR(k.ns.x, 1, 1e-6);
    EXPECT_NEAR(length(k.dpdu), 1.3, 1e-5);
}

}  // namespace
}  // namespace sr
