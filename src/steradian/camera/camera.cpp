#include "steradian/camera/camera.h"

#include "steradian/sampling/warp.h"

namespace sr {

Transform raster_from_screen(const Float s[4], Vec2i res) {
    // Screen window -> NDC [0,1]^2 (y flipped) -> raster.
    Transform ndc_from_screen =
        Transform::scale({1.0 / (double(s[1]) - s[0]), 1.0 / (double(s[3]) - s[2]), 1}) *
        Transform::translate({-double(s[0]), -double(s[3]), 0});
    return Transform::scale({double(res.x), -double(res.y), 1}) * ndc_from_screen;
}

PerspectiveCamera::PerspectiveCamera(const CameraParams& params, Float fov_deg) : m_p(params) {
    Transform screen_from_camera = Transform::perspective(fov_deg, 1e-2, 1000);
    m_camera_from_raster =
        screen_from_camera.inverse() * raster_from_screen(m_p.screen, m_p.resolution).inverse();
}

Ray PerspectiveCamera::generate_ray(Point2 p_film, Point2 u_lens) const {
    Vec3d pc = m_camera_from_raster.point(Vec3d(p_film.x, p_film.y, 0));
    Vec3 dir = normalize(Vec3(pc));
    Point3 o(0, 0, 0);
    if (m_p.lens_radius > 0) {
        Point2 pl = sample_uniform_disk_concentric(u_lens) * m_p.lens_radius;
        Float ft = m_p.focal_distance / dir.z;
        Point3 p_focus = dir * ft;
        o = Point3(pl.x, pl.y, 0);
        dir = normalize(p_focus - o);
    }
    const Transform& w = m_p.world_from_camera;
    return Ray{w.point(o), normalize(w.vector(dir)), kInfinity};
}

Point3 PerspectiveCamera::position() const { return m_p.world_from_camera.point(Point3(0, 0, 0)); }

OrthographicCamera::OrthographicCamera(const CameraParams& params) : m_p(params) {
    Transform screen_from_camera = Transform::orthographic(0, 1);
    m_camera_from_raster =
        screen_from_camera.inverse() * raster_from_screen(m_p.screen, m_p.resolution).inverse();
}

Ray OrthographicCamera::generate_ray(Point2 p_film, Point2 u_lens) const {
    Point3 o(m_camera_from_raster.point(Vec3d(p_film.x, p_film.y, 0)));
    Vec3 dir(0, 0, 1);
    if (m_p.lens_radius > 0) {
        Point2 pl = sample_uniform_disk_concentric(u_lens) * m_p.lens_radius;
        Float ft = m_p.focal_distance / dir.z;
        Point3 p_focus = o + dir * ft;
        o = Point3(o.x + pl.x, o.y + pl.y, o.z);
        dir = normalize(p_focus - o);
    }
    const Transform& w = m_p.world_from_camera;
    return Ray{w.point(o), normalize(w.vector(dir)), kInfinity};
}

Point3 OrthographicCamera::position() const {
    return m_p.world_from_camera.point(Point3(0, 0, 0));
}

}  // namespace sr
