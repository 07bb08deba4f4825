#pragma once
/// Cameras (a cold, open set: virtual classes). Film positions are in raster space:
/// x right, y down, pixel (i, j) covering [i, i+1) x [j, j+1); the full image spans the
/// screen window (pbrt-v4 conventions).
#include <memory>
#include <optional>

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

/// A point sampled on the camera's lens as seen from a scene point (pbrt-v4's
/// CameraWiSample), for light paths that connect to the camera.
struct CameraWiSample {
    Float we = 0;        ///< importance We of the ray from p_lens towards the scene point
    Vec3 wi;             ///< unit, from the scene point towards p_lens
    Float pdf = 0;       ///< solid-angle density at the scene point of choosing p_lens
    Point2 p_raster;     ///< where the ray meets the film (raster space, not bounds-checked)
    Point3 p_lens;       ///< world space
    Normal3 n_lens;      ///< the camera's viewing direction (the lens normal)
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

    /// Importance (pbrt-v4's PerspectiveCamera::We, Veach 1997 sec. 8.1): for the cameras
    /// that have it (has_importance()), We(ray) of a ray leaving the lens at ray.o in unit
    /// direction ray.d: 1 / (A lensArea cos^4 theta), A the film's area at distance 1 (the
    /// full resolution), so that the importance integrated over the whole film is 1. The
    /// raster position is where the ray's image lies (not bounds-checked: the caller clips it
    /// to the area its samples cover); 0 behind the camera.
    virtual bool has_importance() const { return false; }
    virtual Float we(const Ray& ray, Point2* p_raster) const;
    /// Densities of generate_ray() producing `ray` with film positions uniform over the film:
    /// position 1 / lensArea (1 for a pinhole), direction 1 / (A cos^3 theta) (solid angle).
    virtual void pdf_we(const Ray& ray, Float& pdf_pos, Float& pdf_dir) const;
    /// Samples a lens point uniformly (the pinhole itself without a lens) as seen from p_ref.
    virtual std::optional<CameraWiSample> sample_wi(Point3 p_ref, Point2 u) const;
    /// The world-space viewing direction (camera +z).
    Vec3 forward() const { return normalize(m_world_from_camera.vector(Vec3(0, 0, 1))); }

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
    const Transform& camera_from_world() const { return m_camera_from_world; }
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
    bool has_importance() const override { return true; }
    Float we(const Ray& ray, Point2* p_raster) const override;
    void pdf_we(const Ray& ray, Float& pdf_pos, Float& pdf_dir) const override;
    std::optional<CameraWiSample> sample_wi(Point3 p_ref, Point2 u) const override;

private:
    /// cos theta of a world direction with the viewing direction, and its raster position.
    Float project(const Ray& ray, Point2* p_raster) const;
    CameraParams m_p;
    Transform m_camera_from_raster;
    Float m_film_area = 1;  ///< A: the film's area at distance 1 in camera space
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
