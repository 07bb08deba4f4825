#include "steradian/integrators/direct_light.h"

#include <cmath>
#include <queue>

#include "steradian/geometry/hit.h"
#include "steradian/integrators/measure.h"
#include "steradian/scene/scene.h"

namespace sr {

namespace {

const Spectrum* light_spectrum(const Light& light) {
    if (const auto* l = std::get_if<PointLight>(&light)) return &l->intensity;
    if (const auto* l = std::get_if<SpotLight>(&light)) return &l->intensity;
    if (const auto* l = std::get_if<DistantLight>(&light)) return &l->radiance;
    if (const auto* l = std::get_if<GoniometricLight>(&light)) return &l->spectrum;
    if (const auto* l = std::get_if<DiffuseAreaLight>(&light))
        return l->goniometric ? &l->goniometric->spectrum : &l->radiance;
    return nullptr;
}

/// Gauss-Legendre nodes and weights on [0, 1].
constexpr double kG2x[2] = {0.5 - 0.28867513459481288225, 0.5 + 0.28867513459481288225};
constexpr double kG2w[2] = {0.5, 0.5};
constexpr double kG3x[3] = {0.5 - 0.38729833462074168852, 0.5, 0.5 + 0.38729833462074168852};
constexpr double kG3w[3] = {5.0 / 18, 8.0 / 18, 5.0 / 18};

constexpr double kRoundingFloor = 1e-6;

struct Cell {
    uint32_t light;
    float u0, v0, h;
    double q, err;
    bool operator<(const Cell& o) const { return err < o.err; }
};

}  // namespace

bool direct_light_deterministic(const Scene& scene) {
    if (!scene.media.empty()) return false;
    for (const Light& l : scene.lights) {
        if (std::holds_alternative<PointLight>(l) || std::holds_alternative<SpotLight>(l) ||
            std::holds_alternative<DistantLight>(l) || std::holds_alternative<GoniometricLight>(l))
            continue;
        const auto* a = std::get_if<DiffuseAreaLight>(&l);
        if (!a || a->alpha || !(a->triangle || a->sphere || a->disk)) return false;
    }
    return true;
}

bool scene_may_scatter(const Scene& scene) {
    if (!scene.media.empty()) return true;
    for (const ShapeEntry& s : scene.shapes) {
        if (s.material < 0) continue;
        const Material& m = scene.materials[size_t(s.material)];
        if (std::holds_alternative<InterfaceMaterial>(m)) continue;
        const auto* d = std::get_if<DiffuseMaterial>(&m);
        if (!d || d->reflectance < 0) return true;
        const auto* t =
            std::get_if<ConstantSpectrumTexture>(&scene.spectrum_textures[size_t(d->reflectance)]);
        if (!t || !(t->value.max_value() <= 0)) return true;
    }
    return false;
}

DirectLightQuadrature::DirectLightQuadrature(const Scene& scene, const Meter& meter)
    : m_scene(scene), m_meter(meter) {
    const size_t n = scene.lights.size();
    m_spectral.assign(n, 0);
    m_probe.assign(n, 0);
    m_probe_s.assign(n, 0);
    for (size_t i = 0; i < n; ++i) {
        const Spectrum* s = light_spectrum(scene.lights[i]);
        if (!s) continue;
        // The integral over 360..830 nm that the sampled wavelengths estimate, by the
        // trapezoid rule at every nm. (The scene's photometric normalisation sums at every
        // nm, spectrum_to_photometric; ybar's end values, 4e-6 and 1e-6, make the two differ
        // by 2e-8 relative, so a normalised lamp spectrum's photopic factor is 1.)
        double sum = 0;
        float best = 0, best_lambda = 0;
        for (int k = int(kLambdaMin); k <= int(kLambdaMax); ++k) {
            const Float lambda = Float(k);
            const Float v = (*s)(lambda);
            const double end = (k == int(kLambdaMin) || k == int(kLambdaMax)) ? 0.5 : 1.0;
            sum += end * double(v) * double(meter.spectral_weight(lambda));
            if (v > best) {
                best = v;
                best_lambda = lambda;
            }
        }
        m_spectral[i] = sum;
        m_probe[i] = best_lambda;
        m_probe_s[i] = best;
    }
}

namespace {

/// What the integrand of one area light needs, for one receiving point.
struct Prim {
    const DiffuseAreaLight* al = nullptr;
    double spectral = 0, inv_s = 0;
    SampledWavelengths probe;
    Transform obj_from_world;
    bool cone = false;  ///< a full sphere seen from outside: over the cone it subtends
    Point3 centre;
    double radius = 0, one_minus_cos_max = 0;
    Frame cone_frame;
};

struct Integrand {
    const Scene& scene;
    const SurfaceHit& recv;
    Point3 p;
    Vec3 nr;
    DirectEstimate& est;

    /// Radiance leaving x towards the receiver (wi: receiver -> x) if x is visible, else 0.
    double emitted(const Prim& pr, Point3 x, Vec3 x_err, Normal3 nx, Vec3 wi) const {
        const double g = double(pr.al->l(nx, -wi, pr.probe)[0]) * pr.inv_s;
        if (!(g > 0)) return 0;
        ++est.rays;
        if (scene.occluded(spawn_ray_between(recv, x, x_err, nx))) return 0;
        return g;
    }

    /// The illuminance integrand over the primitive's unit square (without the spectral
    /// factor).
    double operator()(const Prim& pr, double u, double v) const {
        ++est.nodes;
        const DiffuseAreaLight& al = *pr.al;
        if (pr.cone) {
            // dw = (1 - cos theta_max) 2 pi du dv; E = integral L cos theta_r dw.
            const double cos_t = 1 - u * pr.one_minus_cos_max;
            const double sin_t = std::sqrt(std::max(0.0, 1 - cos_t * cos_t));
            const double phi = 2 * kPi * v;
            const Vec3 dir = pr.cone_frame.to_world(
                Vec3(Float(sin_t * std::cos(phi)), Float(sin_t * std::sin(phi)), Float(cos_t)));
            const double cos_r = dot(nr, dir);
            if (!(cos_r > 0)) return 0;
            const Vec3 dc = pr.centre - p;
            const double b = dot(dc, dir);
            const double disc =
                std::max(0.0, pr.radius * pr.radius - (double(length_squared(dc)) - b * b));
            const Point3 x = p + dir * Float(b - std::sqrt(disc));
            SurfaceHit h;
            al.sphere->fill_hit(pr.obj_from_world.point(x), h);
            return emitted(pr, h.p, h.p_error, h.ng, dir) * cos_r * pr.one_minus_cos_max * 2 * kPi;
        }
        Point3 x;
        Vec3 x_err;
        Normal3 nx;
        double jac;
        if (al.triangle) {
            // Collapsed square: b0 = 1 - u, b1 = u (1 - v), b2 = u v; dA = 2 A u du dv.
            const ShapeSample ss =
                al.triangle->point_at(Float(1 - u), Float(u * (1 - v)), Float(u * v));
            x = ss.p;
            x_err = ss.p_error;
            nx = ss.n;
            jac = 2 * double(al.area) * u;
        } else {
            SurfaceHit h;
            if (al.disk) {
                // r = r_i + (R - r_i) u, phi = phi_max v; dA = r dr dphi (object space,
                // scaled to the world area).
                const Disk& d = *al.disk;
                const double r = d.inner_radius + (d.radius - d.inner_radius) * u;
                const double phi = d.phi_max * v;
                d.fill_hit(Point3(Float(r * std::cos(phi)), Float(r * std::sin(phi)), d.height), h);
                const double obj_area =
                    0.5 * d.phi_max * (sqr(double(d.radius)) - sqr(double(d.inner_radius)));
                jac = r * (d.radius - d.inner_radius) * d.phi_max * (double(d.area()) / obj_area);
            } else {
                // z = z_min + (z_max - z_min) u, phi = phi_max v; dA = r dz dphi.
                const Sphere& s = *al.sphere;
                const double z = s.z_min + (s.z_max - s.z_min) * u;
                const double rho = std::sqrt(std::max(0.0, sqr(double(s.radius)) - z * z));
                const double phi = s.phi_max * v;
                s.fill_hit(Point3(Float(rho * std::cos(phi)), Float(rho * std::sin(phi)), Float(z)),
                           h);
                jac = double(s.area());
            }
            x = h.p;
            x_err = h.p_error;
            nx = h.ng;
        }
        const Vec3 d = x - p;
        const double dist2 = length_squared(d);
        if (!(dist2 > 0)) return 0;
        const Vec3 wi = d / Float(std::sqrt(dist2));
        const double cos_r = dot(nr, wi);
        const double cos_e = std::abs(dot(nx, wi));
        if (!(cos_r > 0) || !(cos_e > 0)) return 0;
        return emitted(pr, x, x_err, nx, wi) * cos_r * cos_e / dist2 * jac;
    }
};

}  // namespace

DirectEstimate DirectLightQuadrature::irradiance(size_t point, double rel_tol, double abs_tol,
                                                 uint64_t max_nodes) const {
    DirectEstimate est;
    const Point3 p = m_meter.points[point];
    const Vec3 nr = m_meter.directions[point];
    const SurfaceHit recv = meter_receiver(p, nr);
    const LightSampleContext ctx{recv.p, recv.p_error, Normal3(nr)};

    double delta_sum = 0;
    std::vector<Prim> prims;
    for (size_t li = 0; li < m_scene.lights.size(); ++li) {
        if (!(m_spectral[li] != 0) || !(m_probe_s[li] > 0)) continue;
        const Light& light = m_scene.lights[li];
        Prim pr;
        pr.probe.lambda.fill(m_probe[li]);
        pr.probe.pdf.fill(1);
        pr.inv_s = 1.0 / double(m_probe_s[li]);
        pr.spectral = m_spectral[li];
        pr.al = std::get_if<DiffuseAreaLight>(&light);
        if (!pr.al) {
            // A delta light: one direction, one shadow ray, no quadrature error.
            ++est.nodes;
            std::optional<LightLiSample> s = sample_li(light, ctx, Point2(0.5f, 0.5f), pr.probe);
            if (!s) continue;
            const double cos_r = dot(nr, s->wi);
            const double g = double(s->L[0]) * pr.inv_s;
            if (!(cos_r > 0) || !(g > 0)) continue;
            ++est.rays;
            if (m_scene.occluded(spawn_ray_to(recv, s->p_light))) continue;
            delta_sum += g * cos_r * pr.spectral;
            continue;
        }
        // An area light: cull what is wholly behind the receiver or faces away from it.
        const DiffuseAreaLight& al = *pr.al;
        if (al.triangle) {
            const Triangle& t = *al.triangle;
            if (dot(nr, t.p0 - p) <= 0 && dot(nr, t.p1 - p) <= 0 && dot(nr, t.p2 - p) <= 0)
                continue;
            const bool one_sided = al.goniometric ? al.goniometric->body != LuminousBody::Flat
                                                  : !al.two_sided;
            if (one_sided && t.behind(p)) continue;
        }
        if (al.sphere || al.disk)
            pr.obj_from_world =
                (al.sphere ? al.sphere->world_from_object : al.disk->world_from_object).inverse();
        if (al.sphere && al.sphere->full()) {
            pr.centre = al.sphere->world_from_object.point(Point3(0, 0, 0));
            pr.radius = std::sqrt(double(al.sphere->area()) / (4 * kPi));
            const Vec3 dc = pr.centre - p;
            const double dist = length(dc);
            if (dist > pr.radius * (1 + 1e-4)) {
                pr.cone = true;
                const double s2 = sqr(pr.radius / dist);
                pr.one_minus_cos_max = s2 / (1 + std::sqrt(1 - s2));
                pr.cone_frame = Frame::from_z(dc / Float(dist));
            }
        }
        prims.push_back(pr);
    }

    // Global adaptive quadrature over every area light's cells at once: the 3x3
    // Gauss-Legendre value of each cell, the difference from the 2x2 value its error
    // estimate; the cell of largest estimate is split in four until the estimates sum to
    // the tolerance.
    const Integrand f{m_scene, recv, p, nr, est};
    auto eval = [&](Cell& c) {
        const Prim& pr = prims[c.light];
        double q2 = 0, q3 = 0;
        for (int i = 0; i < 2; ++i)
            for (int j = 0; j < 2; ++j)
                q2 += kG2w[i] * kG2w[j] * f(pr, c.u0 + c.h * kG2x[i], c.v0 + c.h * kG2x[j]);
        for (int i = 0; i < 3; ++i)
            for (int j = 0; j < 3; ++j)
                q3 += kG3w[i] * kG3w[j] * f(pr, c.u0 + c.h * kG3x[i], c.v0 + c.h * kG3x[j]);
        const double a = double(c.h) * double(c.h) * pr.spectral;
        c.q = q3 * a;
        c.err = std::abs(q3 - q2) * std::abs(a);
    };
    std::priority_queue<Cell> cells;
    double q_sum = delta_sum, err_sum = 0;
    for (size_t i = 0; i < prims.size(); ++i) {
        Cell c{uint32_t(i), 0, 0, 1, 0, 0};
        eval(c);
        q_sum += c.q;
        err_sum += c.err;
        cells.push(c);
    }
    // The quadrature's share of the tolerance leaves room for the rounding floor (below).
    const double target = std::max(rel_tol - kRoundingFloor, rel_tol / 2);
    while (!cells.empty() && err_sum > std::max(target * std::abs(q_sum), abs_tol) &&
           est.nodes < max_nodes) {
        const Cell c = cells.top();
        cells.pop();
        q_sum -= c.q;
        err_sum -= c.err;
        const float h2 = c.h / 2;
        for (int k = 0; k < 4; ++k) {
            Cell ch{c.light, c.u0 + float(k & 1) * h2, c.v0 + float(k >> 1) * h2, h2, 0, 0};
            eval(ch);
            q_sum += ch.q;
            err_sum += ch.err;
            cells.push(ch);
        }
    }
    // Sum the cells afresh (the running sums drift by rounding).
    q_sum = delta_sum;
    err_sum = 0;
    for (; !cells.empty(); cells.pop()) {
        q_sum += cells.top().q;
        err_sum += cells.top().err;
    }
    est.exact = prims.empty();
    est.value = q_sum;
    // The geometry is single precision (Float): positions and directions carry relative
    // rounding errors of about 1e-7 each, which bound any area light's integral to about
    // 1e-6 relative, however small the quadrature's own estimate.
    est.error = prims.empty() ? 0 : err_sum + kRoundingFloor * std::abs(q_sum - delta_sum);
    est.converged = est.error <= std::max(rel_tol * std::abs(q_sum), abs_tol);
    return est;
}

}  // namespace sr
