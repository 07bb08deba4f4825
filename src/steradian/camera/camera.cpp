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

void camera_ray_frame(Vec3 z, Vec3& x, Vec3& y) {
    Vec3 a = std::abs(z.x) < Float(0.999) ? Vec3(1, 0, 0) : Vec3(0, 1, 0);
    x = normalize(a - z * dot(a, z));
    y = cross(z, x);
}

void Camera::find_min_differentials(Vec2i resolution) {
    // pbrt-v4 (cameras.cpp, FindMinimumDifferentials) scans 512 film positions along the
    // diagonal with the lens sample at the lens centre; so do we.
    constexpr int kN = 512;
    Float best_px = kInfinity, best_py = kInfinity, best_dx = kInfinity, best_dy = kInfinity;
    const Point2 lens(0.5f, 0.5f);
    for (int i = 0; i < kN; ++i) {
        const Float f = Float(i) / (kN - 1);
        const Point2 pf(f * Float(resolution.x), f * Float(resolution.y));
        const Ray r = generate_ray(pf, lens);
        const Ray rx = generate_ray(Point2(pf.x + 1, pf.y), lens);
        const Ray ry = generate_ray(Point2(pf.x, pf.y + 1), lens);
        const Vec3 d = normalize(m_camera_from_world.vector(r.d));
        const Point3 o = m_camera_from_world.point(r.o);
        const Vec3 dox = m_camera_from_world.point(rx.o) - o;
        const Vec3 doy = m_camera_from_world.point(ry.o) - o;
        if (length(dox) < best_px) best_px = length(dox), m_min.pos_x = dox;
        if (length(doy) < best_py) best_py = length(doy), m_min.pos_y = doy;
        Vec3 fx, fy;
        camera_ray_frame(d, fx, fy);
        auto local = [&](Vec3 w) {
            w = normalize(m_camera_from_world.vector(w));
            return Vec3(dot(w, fx), dot(w, fy), dot(w, d)) - Vec3(0, 0, 1);
        };
        const Vec3 ddx = local(rx.d), ddy = local(ry.d);
        if (length(ddx) < best_dx) best_dx = length(ddx), m_min.dir_x = ddx;
        if (length(ddy) < best_dy) best_dy = length(ddy), m_min.dir_y = ddy;
    }
}

void Camera::approximate_dp_dxy(Point3 p, Normal3 n, Float scale, Vec3& dpdx, Vec3& dpdy) const {
    dpdx = dpdy = Vec3(0, 0, 0);
    const Vec3 pc = m_camera_from_world.point(p) - Point3(0, 0, 0);
    const Float dist = length(pc);
    if (!(dist > 0)) return;
    // The frame around the view direction to p: the camera's minimum differential rays
    // start at the origin (plus their position offsets) along z; p is at (0, 0, dist).
    const Vec3 z = pc / dist;
    Vec3 fx, fy;
    camera_ray_frame(z, fx, fy);
    const Vec3 nw = normalize(m_camera_from_world.normal(Vec3(n.x, n.y, n.z)));
    const Vec3 nl(dot(nw, fx), dot(nw, fy), dot(nw, z));
    auto offset = [&](Vec3 pos, Vec3 dir) {
        // Where the ray (pos, (0,0,1) + dir) meets the tangent plane nl . x = nl.z dist.
        const Vec3 d = Vec3(0, 0, 1) + dir;
        const Float den = dot(nl, d);
        if (den == 0) return Vec3(0, 0, 0);
        const Float t = (nl.z * dist - dot(nl, pos)) / den;
        const Vec3 hit = pos + d * t - Vec3(0, 0, dist);
        const Vec3 cam = fx * hit.x + fy * hit.y + z * hit.z;
        return m_world_from_camera.vector(cam) * scale;
    };
    // Position offsets of the minimum differentials are in camera space; in the local
    // frame they are (for the cameras here, which keep them in the film plane) rotated too.
    auto to_local = [&](Vec3 v) { return Vec3(dot(v, fx), dot(v, fy), dot(v, z)); };
    dpdx = offset(to_local(m_min.pos_x), m_min.dir_x);
    dpdy = offset(to_local(m_min.pos_y), m_min.dir_y);
    if (!std::isfinite(length_squared(dpdx)) || !std::isfinite(length_squared(dpdy)))
        dpdx = dpdy = Vec3(0, 0, 0);
}

PerspectiveCamera::PerspectiveCamera(const CameraParams& params, Float fov_deg) : m_p(params) {
    set_frame(m_p.world_from_camera);
    Transform screen_from_camera = Transform::perspective(fov_deg, 1e-2, 1000);
    m_camera_from_raster =
        screen_from_camera.inverse() * raster_from_screen(m_p.screen, m_p.resolution).inverse();
    // The film's area at distance 1: its corners' camera-space directions scaled to z = 1.
    {
        const Vec3d a = m_camera_from_raster.point(Vec3d(0, 0, 0));
        const Vec3d b = m_camera_from_raster.point(
            Vec3d(double(m_p.resolution.x), double(m_p.resolution.y), 0));
        m_film_area = Float(std::abs((a.x / a.z - b.x / b.z) * (a.y / a.z - b.y / b.z)));
    }
    // At raster z = 0 the perspective divide is a constant (the near plane), so the map from
    // raster (x, y) to a camera-space direction is affine; keep it and world-from-camera in
    // float for the per-sample path.
    Vec3d o = m_camera_from_raster.point(Vec3d(0, 0, 0));
    Vec3d ex = m_camera_from_raster.point(Vec3d(1, 0, 0)) - o;
    Vec3d ey = m_camera_from_raster.point(Vec3d(0, 1, 0)) - o;
    for (int i = 0; i < 3; ++i) {
        m_raster[i][0] = Float(ex[i]);
        m_raster[i][1] = Float(ey[i]);
        m_raster[i][2] = 0;
        m_raster[i][3] = Float(o[i]);
        for (int j = 0; j < 4; ++j) m_world[i][j] = Float(m_p.world_from_camera.matrix().m[i][j]);
    }
}

Ray PerspectiveCamera::generate_ray(Point2 p_film, Point2 u_lens) const {
    Vec3 pc(m_raster[0][0] * p_film.x + m_raster[0][1] * p_film.y + m_raster[0][3],
            m_raster[1][0] * p_film.x + m_raster[1][1] * p_film.y + m_raster[1][3],
            m_raster[2][0] * p_film.x + m_raster[2][1] * p_film.y + m_raster[2][3]);
    // Directions stay unnormalised until the world-space one (one square root and division
    // per camera ray): the focus point pc (focal_distance / pc.z) does not depend on pc's
    // length either.
    Vec3 dir = pc;
    Point3 o(0, 0, 0);
    if (m_p.lens_radius > 0) {
        Point2 pl = sample_uniform_disk_concentric(u_lens) * m_p.lens_radius;
        Float ft = m_p.focal_distance / dir.z;
        Point3 p_focus = dir * ft;
        o = Point3(pl.x, pl.y, 0);
        dir = p_focus - o;
    }
    const auto& w = m_world;
    Point3 ow(w[0][0] * o.x + w[0][1] * o.y + w[0][2] * o.z + w[0][3],
              w[1][0] * o.x + w[1][1] * o.y + w[1][2] * o.z + w[1][3],
              w[2][0] * o.x + w[2][1] * o.y + w[2][2] * o.z + w[2][3]);
    Vec3 dw(w[0][0] * dir.x + w[0][1] * dir.y + w[0][2] * dir.z,
            w[1][0] * dir.x + w[1][1] * dir.y + w[1][2] * dir.z,
            w[2][0] * dir.x + w[2][1] * dir.y + w[2][2] * dir.z);
    return Ray{ow, normalize(dw), kInfinity};
}

Float Camera::we(const Ray&, Point2*) const { return 0; }
void Camera::pdf_we(const Ray&, Float& pdf_pos, Float& pdf_dir) const { pdf_pos = pdf_dir = 0; }
std::optional<CameraWiSample> Camera::sample_wi(Point3, Point2) const { return std::nullopt; }

Float PerspectiveCamera::project(const Ray& ray, Point2* p_raster) const {
    const Vec3 d = normalize(Vec3(camera_from_world().vector(ray.d)));
    const Float cos_theta = d.z;
    if (!(cos_theta > 0)) return 0;
    if (p_raster) {
        // The ray's image: the point where it crosses the plane of focus (any point of a
        // pinhole's ray), projected through the lens centre onto the film.
        const Point3 o = camera_from_world().point(ray.o);
        const Float z = m_p.lens_radius > 0 ? m_p.focal_distance : 1;
        const Point3 focus = o + d * (z / cos_theta);
        const Vec3d r = m_camera_from_raster.inverse().point(Vec3d(focus.x, focus.y, focus.z));
        *p_raster = Point2(Float(r.x), Float(r.y));
    }
    return cos_theta;
}

Float PerspectiveCamera::we(const Ray& ray, Point2* p_raster) const {
    const Float c = project(ray, p_raster);
    if (c <= 0) return 0;
    const Float lens_area = m_p.lens_radius > 0 ? kPi * sqr(m_p.lens_radius) : 1;
    return 1 / (m_film_area * lens_area * sqr(sqr(c)));
}

void PerspectiveCamera::pdf_we(const Ray& ray, Float& pdf_pos, Float& pdf_dir) const {
    const Float c = project(ray, nullptr);
    if (c <= 0) {
        pdf_pos = pdf_dir = 0;
        return;
    }
    pdf_pos = m_p.lens_radius > 0 ? 1 / (kPi * sqr(m_p.lens_radius)) : 1;
    pdf_dir = 1 / (m_film_area * c * c * c);
}

std::optional<CameraWiSample> PerspectiveCamera::sample_wi(Point3 p_ref, Point2 u) const {
    const Point2 pl = sample_uniform_disk_concentric(u) * m_p.lens_radius;
    CameraWiSample s;
    s.p_lens = Point3(m_p.world_from_camera.point(Vec3d(pl.x, pl.y, 0)));
    s.n_lens = forward();
    Vec3 wi = s.p_lens - p_ref;
    const Float dist = length(wi);
    if (!(dist > 0)) return std::nullopt;
    wi = wi / dist;
    const Float lens_area = m_p.lens_radius > 0 ? kPi * sqr(m_p.lens_radius) : 1;
    const Float cos_lens = absdot(s.n_lens, wi);
    if (!(cos_lens > 0)) return std::nullopt;
    s.pdf = dist * dist / (cos_lens * lens_area);
    s.wi = wi;
    s.we = we(Ray{s.p_lens, -wi, kInfinity}, &s.p_raster);
    if (!(s.we > 0)) return std::nullopt;
    return s;
}

Point3 PerspectiveCamera::position() const { return m_p.world_from_camera.point(Point3(0, 0, 0)); }

OrthographicCamera::OrthographicCamera(const CameraParams& params) : m_p(params) {
    set_frame(m_p.world_from_camera);
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
