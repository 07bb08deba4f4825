#pragma once
/// Cameras (a cold, open set: virtual classes). Film positions are in raster space:
/// x right, y down, pixel (i, j) covering [i, i+1) x [j, j+1); the full image spans the
/// screen window (pbrt-v4 conventions).
#include <memory>

#include "steradian/core/transform.h"

namespace sr {

struct CameraParams {
    Transform world_from_camera;
    Vec2i resolution{1280, 720};
    /// Screen window [x0, x1] x [y0, y1]; default derived from the frame aspect ratio.
    Float screen[4] = {-1, 1, -1, 1};
    Float lens_radius = 0;
    Float focal_distance = 1e6f;
};

/// The change of a camera ray from one pixel to the next in x and in y, in camera space,
/// as the smallest over the film (pbrt-v4's "minimum differentials", which it uses to give
/// every path vertex a texture footprint).
struct CameraMinDifferentials {
    Vec3 pos_x{0, 0, 0}, pos_y{0, 0, 0};  ///< origin offsets
    /// Direction offsets in the frame whose z is the ray's unit direction (x and y along the
    /// camera's x and y axes made perpendicular to it).
    Vec3 dir_x{0, 0, 0}, dir_y{0, 0, 0};
};

class Camera {
public:
    virtual ~Camera() = default;
    /// World-space ray through raster position p_film with lens sample u_lens in [0,1)^2.
    /// The importance weight is 1 for both camera models.
    virtual Ray generate_ray(Point2 p_film, Point2 u_lens) const = 0;
    /// World-space camera position (lens centre).
    virtual Point3 position() const = 0;
    /// Whether generate_ray() uses its lens sample (a thin lens); a pinhole ignores it.
    virtual bool uses_lens_sample() const = 0;

    /// Texture footprint of a surface point (p, unit normal n) seen by this camera at a
    /// vertex the camera's own ray differentials do not reach (after a bounce): the offsets
    /// dp/dx, dp/dy in the tangent plane that rays one pixel apart in x and y, with the
    /// smallest differentials over the film (find_min_differentials), would give at p's
    /// distance, times `scale`. After pbrt-v4's Approximate_dp_dxy (the same construction,
    /// the frame's rotation about the view direction fixed by the camera's axes).
    void approximate_dp_dxy(Point3 p, Normal3 n, Float scale, Vec3& dpdx, Vec3& dpdy) const;
    /// Computes the smallest ray differentials over the film (along its diagonal, at the
    /// lens centre), for approximate_dp_dxy. Called once after construction.
    void find_min_differentials(Vec2i resolution);
    const CameraMinDifferentials& min_differentials() const { return m_min; }

protected:
    /// Derived constructors give the camera's frame.
    void set_frame(const Transform& world_from_camera) {
        m_world_from_camera = world_from_camera;
        m_camera_from_world = world_from_camera.inverse();
    }

private:
    Transform m_world_from_camera, m_camera_from_world;
    CameraMinDifferentials m_min;
};

/// The orthonormal frame the camera's differentials are expressed in, around the unit
/// direction z (in camera space): x is the camera's x axis made perpendicular to z (or, for
/// z along x, y's), y = z x x.
void camera_ray_frame(Vec3 z, Vec3& x, Vec3& y);

class PerspectiveCamera final : public Camera {
public:
    /// fov_deg: the full field of view of the shorter image axis, as in pbrt-v4.
    PerspectiveCamera(const CameraParams& params, Float fov_deg);
    Ray generate_ray(Point2 p_film, Point2 u_lens) const override;
    Point3 position() const override;
    bool uses_lens_sample() const override { return m_p.lens_radius > 0; }

private:
    CameraParams m_p;
    Transform m_camera_from_raster;
    Float m_raster[3][4];  ///< camera-from-raster (affine part), in float for speed
    Float m_world[3][4];   ///< world-from-camera, in float
};

class OrthographicCamera final : public Camera {
public:
    explicit OrthographicCamera(const CameraParams& params);
    Ray generate_ray(Point2 p_film, Point2 u_lens) const override;
    Point3 position() const override;
    bool uses_lens_sample() const override { return m_p.lens_radius > 0; }

private:
    CameraParams m_p;
    Transform m_camera_from_raster;
};

/// pbrt-v4's raster-from-screen transform for a screen window and resolution.
Transform raster_from_screen(const Float screen[4], Vec2i resolution);

}  // namespace sr
