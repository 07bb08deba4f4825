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
};

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
