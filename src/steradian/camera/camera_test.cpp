#include "steradian/camera/camera.h"

#include <gtest/gtest.h>

#include <cmath>
#include <numbers>

#include "steradian/geometry/hit.h"
#include "steradian/sampling/rng.h"

namespace sr {
namespace {

constexpr double kPiD = std::numbers::pi;

/// A camera set up as the scene builder does for pbrt-v4: the screen window spans
/// [-aspect, aspect] x [-1, 1] for landscape frames and [-1, 1] x [-1/aspect, 1/aspect] for
/// portrait ones, so the field of view applies to the shorter image axis.
struct Rig {
    Vec3d pos, look, up;
    Vec3d dir, right, new_up;  // world-space camera axes (+z, +x, +y)
    CameraParams params;
};

Rig make_rig(Vec2i res, Vec3d pos = {1, 2, 3}, Vec3d look = {4, 6, 3}, Vec3d up = {0, 0, 1}) {
    Rig r;
    r.pos = pos;
    r.look = look;
    r.up = up;
    r.dir = normalize(look - pos);
    // pbrt's LookAt camera axes: right = up x dir, up' = dir x right.
    r.right = normalize(cross(normalize(up), r.dir));
    r.new_up = cross(r.dir, r.right);
    r.params.world_from_camera = Transform::look_at(pos, look, up).inverse();
    r.params.resolution = res;
    Float frame = Float(res.x) / Float(res.y);
    if (frame > 1) {
        r.params.screen[0] = -frame;
        r.params.screen[1] = frame;
        r.params.screen[2] = -1;
        r.params.screen[3] = 1;
    } else {
        r.params.screen[0] = -1;
        r.params.screen[1] = 1;
        r.params.screen[2] = -1 / frame;
        r.params.screen[3] = 1 / frame;
    }
    return r;
}

double angle_between(Vec3d a, Vec3d b) {
    return std::atan2(length(cross(a, b)), dot(a, b));
}

/// Camera-space coordinates of a world-space direction.
Vec3d to_camera(const Rig& r, Vec3 d) {
    Vec3d v(d);
    return {dot(v, r.right), dot(v, r.new_up), dot(v, r.dir)};
}

TEST(PerspectiveCamera, CentreRayIsTheViewingDirection) {
    Rig r = make_rig({400, 200});
    PerspectiveCamera cam(r.params, 50);
    Ray ray = cam.generate_ray({200, 100}, {0.5f, 0.5f});
    EXPECT_NEAR(ray.o.x, 1, 1e-5);
    EXPECT_NEAR(ray.o.y, 2, 1e-5);
    EXPECT_NEAR(ray.o.z, 3, 1e-5);
    EXPECT_NEAR(ray.d.x, 0.6, 1e-6);  // (4, 6, 3) - (1, 2, 3) = 5 (0.6, 0.8, 0)
    EXPECT_NEAR(ray.d.y, 0.8, 1e-6);
    EXPECT_NEAR(ray.d.z, 0, 1e-6);
    EXPECT_NEAR(length(ray.d), 1, 1e-6);
    Point3 p = cam.position();
    EXPECT_NEAR(p.x, 1, 1e-6);
    EXPECT_NEAR(p.y, 2, 1e-6);
    EXPECT_NEAR(p.z, 3, 1e-6);
}

TEST(PerspectiveCamera, FovAppliesToTheShorterImageAxis) {
    const double fov = 50, half = fov / 2 * kPiD / 180;
    for (Vec2i res : {Vec2i{400, 200}, Vec2i{200, 400}, Vec2i{300, 300}}) {
        Rig r = make_rig(res);
        PerspectiveCamera cam(r.params, Float(fov));
        double w = res.x, h = res.y;
        double aspect = std::max(w, h) / std::min(w, h);
        // Half-angles of the two axes: fov/2 for the shorter, atan(aspect tan(fov/2)) for
        // the longer one.
        double half_x = w <= h ? half : std::atan(aspect * std::tan(half));
        double half_y = h <= w ? half : std::atan(aspect * std::tan(half));
        auto ang = [&](double px, double py) {
            return angle_between(Vec3d(cam.generate_ray({Float(px), Float(py)}, {0, 0}).d), r.dir);
        };
        EXPECT_NEAR(ang(w / 2, 0), half_y, 1e-6) << res.x << "x" << res.y << " top";
        EXPECT_NEAR(ang(w / 2, h), half_y, 1e-6) << res.x << "x" << res.y << " bottom";
        EXPECT_NEAR(ang(0, h / 2), half_x, 1e-6) << res.x << "x" << res.y << " left";
        EXPECT_NEAR(ang(w, h / 2), half_x, 1e-6) << res.x << "x" << res.y << " right";
    }
}

TEST(PerspectiveCamera, RasterXIsCameraPlusXAndRasterYIsCameraMinusY) {
    Rig r = make_rig({400, 200});
    PerspectiveCamera cam(r.params, 50);
    // Right edge: camera +x; top edge (raster y = 0): camera +y.
    Vec3d right = to_camera(r, cam.generate_ray({400, 100}, {0, 0}).d);
    Vec3d left = to_camera(r, cam.generate_ray({0, 100}, {0, 0}).d);
    Vec3d top = to_camera(r, cam.generate_ray({200, 0}, {0, 0}).d);
    Vec3d bottom = to_camera(r, cam.generate_ray({200, 200}, {0, 0}).d);
    EXPECT_GT(right.x, 0.5);
    EXPECT_LT(left.x, -0.5);
    EXPECT_NEAR(right.y, 0, 1e-6);
    EXPECT_GT(top.y, 0.3);
    EXPECT_LT(bottom.y, -0.3);
    EXPECT_NEAR(top.x, 0, 1e-6);
}

TEST(PerspectiveCamera, PinholeProjectionOverTheWholeFilm) {
    // A pinhole camera: the ray through raster (px, py) has camera-space slopes
    // x/z = sx tan(fov/2), y/z = sy tan(fov/2), with (sx, sy) the screen-window point:
    // sx = x0 + (x1 - x0) px / W, sy = y1 - (y1 - y0) py / H (raster y runs down).
    // The third case has an asymmetric "screenwindow" (off-axis projection).
    for (int variant = 0; variant < 3; ++variant) {
        Vec2i res = variant == 0 ? Vec2i{64, 48} : (variant == 1 ? Vec2i{30, 90} : Vec2i{50, 40});
        Rig r = make_rig(res, {-2, 0.5, 7}, {3, -1, 2}, {0.2, 1, 0.1});
        if (variant == 2) {
            r.params.screen[0] = -0.5f;
            r.params.screen[1] = 1.5f;
            r.params.screen[2] = -1;
            r.params.screen[3] = 0.25f;
        }
        const double fov = 70;
        PerspectiveCamera cam(r.params, Float(fov));
        double t = std::tan(fov / 2 * kPiD / 180);
        const Float* s = r.params.screen;
        for (int j = 0; j <= 8; ++j) {
            for (int i = 0; i <= 8; ++i) {
                double px = res.x * i / 8.0, py = res.y * j / 8.0;
                Ray ray = cam.generate_ray({Float(px), Float(py)}, {0.3f, 0.9f});
                Vec3d d = to_camera(r, ray.d);
                double sx = s[0] + (s[1] - s[0]) * px / res.x;
                double sy = s[3] - (s[3] - s[2]) * py / res.y;
                ASSERT_GT(d.z, 0);
                EXPECT_NEAR(d.x / d.z, sx * t, 2e-6 * (1 + std::abs(sx * t)));
                EXPECT_NEAR(d.y / d.z, sy * t, 2e-6 * (1 + std::abs(sy * t)));
                EXPECT_NEAR(length(ray.d), 1, 1e-6);
                EXPECT_NEAR(distance(Vec3d(ray.o), r.pos), 0, 1e-5);
            }
        }
    }
}

TEST(PerspectiveCamera, ThinLensRaysForOneFilmPointConvergeAtTheFocalDistance) {
    Rig r = make_rig({320, 240}, {0.5, -1, 2}, {0.5, 4, 2.5}, {0, 0, 1});
    const Float lens_radius = 0.25f, focal = 6;
    CameraParams pinhole_params = r.params;
    r.params.lens_radius = lens_radius;
    r.params.focal_distance = focal;
    PerspectiveCamera thin(r.params, 45), pinhole(pinhole_params, 45);
    Pcg32 rng(5, 77);
    for (Point2 pf : {Point2{160, 120}, Point2{0, 0}, Point2{300.5f, 17.25f}, Point2{12, 230}}) {
        // The pinhole ray's point on the plane of focus (camera z = focal).
        Ray ph = pinhole.generate_ray(pf, {0.5f, 0.5f});
        Vec3d focus = Vec3d(ph.o) + Vec3d(ph.d) * (focal / dot(Vec3d(ph.d), r.dir));
        double sum_r2 = 0;
        Vec3d sum_o(0, 0, 0);
        const int n = 1024;
        for (int k = 0; k < n; ++k) {
            // Stratified lens samples (32 x 32 jittered).
            Point2 u{(Float(k % 32) + rng.next_float()) / 32, (Float(k / 32) + rng.next_float()) / 32};
            Ray ray = thin.generate_ray(pf, u);
            Vec3d o(ray.o), d(ray.d);
            Vec3d lens = o - r.pos;
            // Origins lie on the lens disk, in the plane z_camera = 0.
            EXPECT_NEAR(dot(lens, r.dir), 0, 1e-5);
            EXPECT_LE(length(lens), lens_radius * (1 + 1e-5));
            sum_r2 += length_squared(lens);
            sum_o += lens;
            // The ray reaches the plane of focus at the pinhole's point.
            double t = (focal - dot(lens, r.dir)) / dot(d, r.dir);
            Vec3d p = o + d * t;
            EXPECT_NEAR(distance(p, focus), 0, 2e-5 * focal) << "lens sample " << k;
        }
        // Uniform on the disk: mean position the centre, mean r^2 = R^2 / 2. Stratified
        // samples: the errors are far below these bounds (~1e-3 R^2 at 1024 samples).
        EXPECT_NEAR(length(sum_o / n), 0, 0.01 * lens_radius);
        EXPECT_NEAR(sum_r2 / n, 0.5 * sqr(lens_radius), 0.01 * sqr(lens_radius));
    }
}

TEST(OrthographicCamera, RaysAreParallelAndSpanTheScreenWindow) {
    Rig r = make_rig({200, 100}, {1, 2, 3}, {1, 2, -7}, {0, 1, 0});
    OrthographicCamera cam(r.params);
    const Float* s = r.params.screen;  // [-2, 2] x [-1, 1]
    for (int j = 0; j <= 4; ++j) {
        for (int i = 0; i <= 4; ++i) {
            double px = 200 * i / 4.0, py = 100 * j / 4.0;
            Ray ray = cam.generate_ray({Float(px), Float(py)}, {0.5f, 0.5f});
            // Parallel to the viewing direction.
            EXPECT_NEAR(ray.d.x, r.dir.x, 1e-6);
            EXPECT_NEAR(ray.d.y, r.dir.y, 1e-6);
            EXPECT_NEAR(ray.d.z, r.dir.z, 1e-6);
            // The origin is the screen-window point on the camera's z = 0 plane.
            Vec3d o = to_camera(r, Vec3(Vec3d(ray.o) - r.pos));
            double sx = s[0] + (s[1] - s[0]) * px / 200, sy = s[3] - (s[3] - s[2]) * py / 100;
            EXPECT_NEAR(o.x, sx, 1e-5);
            EXPECT_NEAR(o.y, sy, 1e-5);
            EXPECT_NEAR(o.z, 0, 1e-5);
        }
    }
    // Corners: raster (0, 0) is the top-left of the window, (W, H) the bottom-right.
    Vec3d tl = to_camera(r, Vec3(Vec3d(cam.generate_ray({0, 0}, {0, 0}).o) - r.pos));
    EXPECT_NEAR(tl.x, -2, 1e-5);
    EXPECT_NEAR(tl.y, 1, 1e-5);
    Vec3d br = to_camera(r, Vec3(Vec3d(cam.generate_ray({200, 100}, {0, 0}).o) - r.pos));
    EXPECT_NEAR(br.x, 2, 1e-5);
    EXPECT_NEAR(br.y, -1, 1e-5);
}

TEST(OrthographicCamera, ThinLensRaysConvergeAtTheFocalDistance) {
    Rig r = make_rig({100, 100}, {0, 0, 0}, {0, 0, 1}, {0, 1, 0});
    r.params.lens_radius = 0.1f;
    r.params.focal_distance = 3;
    OrthographicCamera cam(r.params);
    Pcg32 rng(9, 1);
    for (Point2 pf : {Point2{50, 50}, Point2{10, 90}}) {
        // Screen point of pf; the focus point is straight ahead of it at z = 3.
        double sx = -1 + 2 * pf.x / 100.0, sy = 1 - 2 * pf.y / 100.0;
        for (int k = 0; k < 256; ++k) {
            Ray ray = cam.generate_ray(pf, {rng.next_float(), rng.next_float()});
            EXPECT_NEAR(ray.o.z, 0, 1e-6);
            EXPECT_LE(std::hypot(ray.o.x - sx, ray.o.y - sy), 0.1 * (1 + 1e-5));
            double t = 3 / double(ray.d.z);
            EXPECT_NEAR(ray.o.x + ray.d.x * t, sx, 1e-5);
            EXPECT_NEAR(ray.o.y + ray.d.y * t, sy, 1e-5);
        }
    }
}

TEST(RasterFromScreen, MapsWindowCornersToRasterCorners) {
    Float s[4] = {-2, 2, -1, 1};
    Transform t = raster_from_screen(s, {400, 200});
    Vec3d tl = t.point(Vec3d(-2, 1, 0)), br = t.point(Vec3d(2, -1, 0)), c = t.point(Vec3d(0, 0, 0));
    EXPECT_NEAR(tl.x, 0, 1e-12);
    EXPECT_NEAR(tl.y, 0, 1e-12);
    EXPECT_NEAR(br.x, 400, 1e-12);
    EXPECT_NEAR(br.y, 200, 1e-12);
    EXPECT_NEAR(c.x, 200, 1e-12);
    EXPECT_NEAR(c.y, 100, 1e-12);
}

}  // namespace
}  // namespace sr

namespace sr {
namespace {

// Texture footprints (pbrt-v4's ray differentials and their camera approximation), against
// the geometry of a pinhole: fov 90 degrees on a square 100 x 100 film puts the film plane
// z = 1 at [-1, 1]^2, so one pixel is 0.02 there.
TEST(CameraFootprint, RayDifferentialsOnAFacingPlaneAreOnePixelAtItsDistance) {
    CameraParams cp;
    cp.resolution = Vec2i(100, 100);
    PerspectiveCamera cam(cp, 90);
    const Point2 pf(50, 50), lens(0.5f, 0.5f);
    const Ray r = cam.generate_ray(pf, lens);
    const Ray rx = cam.generate_ray(Point2(51, 50), lens), ry = cam.generate_ray(Point2(50, 51), lens);
    const Float d = 7;  // a plane z = 7 facing the camera, u = x, v = y
    SurfaceHit h;
    h.p = r.at(d / r.d.z);
    h.ng = Normal3(0, 0, -1);
    h.dpdu = Vec3(1, 0, 0);
    h.dpdv = Vec3(0, 1, 0);
    set_footprint_from_rays(h, r, rx, ry, 1);
    EXPECT_NEAR(length(h.dpdx), 0.02 * d, 1e-4 * d);
    EXPECT_NEAR(length(h.dpdy), 0.02 * d, 1e-4 * d);
    // Raster x runs along camera +x and raster y down (camera -y): dp/dx = (0.14, 0, 0).
    EXPECT_NEAR(h.dudx, 0.02 * d, 1e-4 * d);
    EXPECT_NEAR(h.dvdy, -0.02 * d, 1e-4 * d);
    EXPECT_NEAR(h.dvdx, 0, 1e-5);
    EXPECT_NEAR(h.dudy, 0, 1e-5);
    // pbrt-v4 scales the differentials by max(1/8, 1/sqrt(spp)): at 16 spp a quarter.
    set_footprint_from_rays(h, r, rx, ry, 0.25f);
    EXPECT_NEAR(h.dudx, 0.25 * 0.02 * d, 1e-4 * d);
    // Tilted 60 degrees about x, the plane stretches the footprint in y by 1 / cos 60 = 2.
    const Float c = std::cos(Float(kPiD / 3)), s = std::sin(Float(kPiD / 3));
    h.ng = Normal3(0, s, -c);  // facing the camera, turned about the x axis
    h.dpdu = Vec3(1, 0, 0);
    h.dpdv = Vec3(0, c, s);
    h.p = r.at(d);  // on the axis, distance d
    set_footprint_from_rays(h, r, rx, ry, 1);
    EXPECT_NEAR(length(h.dpdy), 2 * 0.02 * d, 2e-3 * d);
    EXPECT_NEAR(length(h.dpdx), 0.02 * d, 1e-4 * d);
}

TEST(CameraFootprint, TheApproximationUsesTheSmallestDifferentialOverTheFilm) {
    // pbrt-v4's approximation at vertices after a bounce: the ray differential smallest over
    // the film (at the corner of a pinhole's film, where a pixel subtends the least angle)
    // at the vertex's distance. At the corner (1, 1, 1) / sqrt 3 of the z = 1 film plane, a
    // step of 0.02 in x turns the unit direction by 0.02 |e_x - n n_x| / |p| = 0.02
    // sqrt(2/3) / sqrt 3; a plane facing the camera at distance d then moves by d times that.
    CameraParams cp;
    cp.resolution = Vec2i(100, 100);
    PerspectiveCamera cam(cp, 90);
    cam.find_min_differentials(cp.resolution);
    const Float d = 5, want = d * 0.02f * std::sqrt(2.0f / 3) / std::sqrt(3.0f);
    Vec3 dpdx, dpdy;
    cam.approximate_dp_dxy(Point3(0, 0, d), Normal3(0, 0, -1), 1, dpdx, dpdy);
    // A one-pixel step is not infinitesimal: the finite difference differs by ~1 %.
    EXPECT_NEAR(length(dpdx), want, 0.02 * want);
    EXPECT_NEAR(length(dpdy), want, 0.02 * want);
    EXPECT_NEAR(dot(dpdx, Vec3(0, 0, 1)), 0, 1e-6);  // in the facing plane
    cam.approximate_dp_dxy(Point3(0, 0, d), Normal3(0, 0, -1), 0.5f, dpdx, dpdy);
    EXPECT_NEAR(length(dpdx), 0.5f * want, 0.01 * want);
}

}  // namespace
}  // namespace sr
