#include "steradian/integrators/path/volpath.h"

#include <climits>

#include "steradian/bsdf/normalized_fresnel.h"
#include "steradian/integrators/path/medium_transport.h"
#include "steradian/material/subsurface.h"
#include "steradian/media/medium.h"
#include "steradian/sampling/hash.h"
#include "steradian/sampling/rng.h"
#include "steradian/scene/scene.h"

namespace sr {

namespace {

/// The path's medium while it random-walks inside a subsurface material: the homogeneous
/// medium of that material at the entry point (VolPath::m_walk), held by the path itself
/// rather than by the scene's list of media.
constexpr int kWalkMedium = -2;
/// The most real scattering events of one random walk. pbrt-v4 counts a whole subsurface hop
/// as one bounce of "maxdepth", so the walk's events do not count against it (a head rendered
/// with maxdepth 2 would otherwise be dark); this bound only stops walks in media of albedo
/// very close to 1 in bodies many mean free paths across, which then lose that energy.
constexpr int kMaxWalkScatterings = 1024;

/// The path's state. All weights follow pbrt-v4's volpath formulation: beta is the
/// throughput divided by the hero wavelength's path pdf, and r_u, r_l are the ratios of every
/// wavelength's unidirectional (and light-sampling) path pdf to the hero wavelength's; a
/// contribution divided by the average of r_u (+ r_l) is then the one-sample MIS estimate over
/// the four wavelengths and the two strategies (Miller, Georgiev and Jarosz 2019).
class VolPath {
  public:
    VolPath(const Scene& scene, SampledWavelengths& lambda, Sampler& sampler,
            PathCounters& counters, const PathLimits& limits)
        : m_scene(scene),
          m_lambda(lambda),
          m_sampler(sampler),
          m_counters(counters),
          m_min_vertices(limits.min_vertices),
          m_max_depth(limits.max_depth == PathLimits::kSceneDepth ? scene.integrator.max_depth
                      : limits.max_depth < 0                      ? INT_MAX
                                                                  : limits.max_depth),
          // pbrt-v4 counts a medium's emission after k vertices only where k < maxdepth; a
          // caller's own limit counts it where k <= max_depth, as a surface's emission.
          m_emission_depth(limits.max_depth == PathLimits::kSceneDepth ? m_max_depth - 1
                                                                       : m_max_depth),
          m_mctx(scene.material_context()) {}

    SampledSpectrum L{0};

    void trace(Ray ray, int medium, bool found, SurfaceHit& hit) {
        int crossings = 0;
        while (true) {
            if (medium >= 0 || medium == kWalkMedium) {
                m_current_medium = medium;
                bool scattered = false, terminated = false;
                Float t_max = found ? hit.t : kInfinity;
                const uint64_t h0 = uint64_t(m_sampler.get_1d() * 0x1p32f);
                const uint64_t h1 = uint64_t(m_sampler.get_1d() * 0x1p32f);
                Pcg32 rng = tracking_rng(h0, h1);
                const Float u = m_sampler.get_1d();
                const Vec3 wo = -normalize(ray.d);
                Ray next;
                auto on_collision = [&](Point3 p, const MediumProperties& mp,
                                        SampledSpectrum sigma_maj, SampledSpectrum tm) {
                    return collision(p, mp, sigma_maj, tm, wo, rng, scattered, terminated, next);
                };
                SampledSpectrum t_maj = medium == kWalkMedium
                                            ? sample_walk(ray, t_max, u, rng, on_collision)
                                            : sample_t_maj(m_scene.media[size_t(medium)], ray,
                                                           t_max, u, rng, m_lambda, on_collision);
                if (terminated || m_beta.is_zero() || m_r_u.is_zero()) return;
                if (scattered) {
                    ray = next;
                    ++m_counters.rays;
                    found = m_scene.intersect(ray, hit);
                    continue;
                }
                m_beta *= t_maj / t_maj[0];
                m_r_u *= t_maj / t_maj[0];
                m_r_l *= t_maj / t_maj[0];
                if (m_beta.has_nonfinite() || m_r_u.has_nonfinite()) return;
            }
            if (medium == kWalkMedium) {
                // The walk reached a surface: it leaves the object there. A walk whose ray
                // meets nothing (an open mesh) ends the path with what it has gathered.
                if (!found) return;
                if (hit.material < 0) {  // an interface inside the object: walk on through it
                    if (++crossings > 256) return;
                    ray = spawn_ray(hit, ray.d);
                    ++m_counters.rays;
                    found = m_scene.intersect(ray, hit);
                    continue;
                }
                if (reflect_inside(ray, hit)) {  // Fresnel reflection back into the object
                    if (++m_walk.scatterings > kMaxWalkScatterings) return;
                    ++m_counters.rays;
                    found = m_scene.intersect(ray, hit);
                    continue;
                }
                if (!leave_walk(ray, hit, medium)) return;
                ++m_counters.rays;
                found = m_scene.intersect(ray, hit);
                continue;
            }
            if (!found) {
                escaped(ray);
                return;
            }
            if (hit.light >= 0) emitted(hit);
            std::optional<Bsdf> bsdf =
                hit.material >= 0
                    ? make_bsdf(m_scene.materials[hit.material], m_mctx, hit, m_lambda)
                    : std::nullopt;
            // pbrt-v4's "regularize": after a non-specular bounce (or a medium scattering),
            // near-specular lobes widen.
            if (bsdf && m_any_non_specular && m_scene.integrator.regularize) bsdf->regularize();
            if (!bsdf) {
                // An interface: the ray goes on, into the medium on the far side.
                if (++crossings > 256) return;
                medium = medium_after(hit, ray.d, medium);
                ray = spawn_ray(hit, ray.d);
                ++m_counters.rays;
                found = m_scene.intersect(ray, hit);
                continue;
            }
            if (!scatter(hit, *bsdf, medium, ray)) return;
            ++m_counters.rays;
            found = m_scene.intersect(ray, hit);
        }
    }

    /// A surface scattering vertex: light sampling and BSDF sampling at `hit` (in `medium`
    /// on the side the path arrived from). False: the path ends; else `ray` is the next
    /// segment, which starts in the updated `medium`.
    bool scatter(const SurfaceHit& hit, const Bsdf& bsdf, int& medium, Ray& ray) {
        if (m_depth++ >= m_max_depth) return false;
        if (bsdf.has_non_specular() && !m_scene.light_sampler.empty()) {
            SampledSpectrum c = sample_light(SurfaceVertex{&hit, &bsdf}, medium);
            if (counted()) L += c;
        } else {
            m_sampler.skip_1d();
            m_sampler.skip_2d();
        }
        m_prev_ctx = LightSampleContext{hit.p, hit.p_error, hit.ng};
        Float uc = m_sampler.get_1d();
        Point2 u2 = m_sampler.get_2d();
        auto bs = bsdf.sample(hit.wo, uc, u2);
        if (!bs || !(bs->pdf_sa > 0)) return false;
        m_beta *= bs->f * (absdot(bs->wi, hit.ns) / bs->pdf_sa);
        m_r_l = m_r_u / bs->pdf_sa;
        m_specular_bounce = bs->is_specular();
        m_any_non_specular |= !m_specular_bounce;
        if (bs->is_transmission()) m_eta_scale *= sqr(bs->eta);
        const int outside = medium;
        medium = medium_after(hit, bs->wi, medium);
        if (bs->is_transmission() && hit.material >= 0)
            if (const SubsurfaceMaterial* ss =
                    subsurface_at(m_scene.materials[hit.material], m_mctx, hit))
                medium = enter_walk(*ss, hit, outside);
        ray = spawn_ray(hit, bs->wi);
        if (m_beta.is_zero()) return false;
        return russian_roulette();
    }

  private:
    /// A surface scattering vertex for sample_light (null bsdf: a medium vertex).
    struct SurfaceVertex {
        const SurfaceHit* hit = nullptr;
        const Bsdf* bsdf = nullptr;
    };

    /// The medium a ray leaving `hit` in direction w is in (medium_transport.h).
    int medium_after(const SurfaceHit& hit, Vec3 w, int current) const {
        return sr::medium_after(m_scene, hit, w, current);
    }

    /// A tentative collision of delta tracking: absorption, real scattering or null
    /// scattering, chosen with the hero wavelength's probabilities.
    bool collision(Point3 p, const MediumProperties& mp, SampledSpectrum sigma_maj,
                   SampledSpectrum t_maj, Vec3 wo, Pcg32& rng, bool& scattered, bool& terminated,
                   Ray& next) {
        if (m_beta.is_zero()) {
            terminated = true;
            return false;
        }
        // Emission of the medium (absorption-weighted), at every tentative collision.
        if (m_depth <= m_emission_depth && counted() && !mp.le.is_zero()) {
            Float pdf = sigma_maj[0] * t_maj[0];
            SampledSpectrum betap = m_beta * t_maj / pdf;
            SampledSpectrum r_e = m_r_u * sigma_maj * t_maj / pdf;
            if (!r_e.is_zero()) L += betap * mp.sigma_a * mp.le / r_e.average();
        }
        const Float p_absorb = mp.sigma_a[0] / sigma_maj[0];
        const Float p_scatter = mp.sigma_s[0] / sigma_maj[0];
        const Float um = rng.next_float();
        if (um < p_absorb) {
            terminated = true;
            return false;
        }
        const bool walk = m_current_medium == kWalkMedium;
        if (um < p_absorb + p_scatter) {
            if (walk ? ++m_walk.scatterings > kMaxWalkScatterings : m_depth++ >= m_max_depth) {
                terminated = true;
                return false;
            }
            Float pdf = t_maj[0] * mp.sigma_s[0];
            m_beta *= t_maj * mp.sigma_s / pdf;
            m_r_u *= t_maj * mp.sigma_s / pdf;
            if (m_beta.is_zero() || m_r_u.is_zero()) {
                terminated = true;
                return false;
            }
            m_medium_g = mp.g;
            m_medium_p = p;
            m_medium_wo = wo;
            // No light sampling inside a subsurface walk: a shadow ray could not cross its
            // dielectric boundary (the exit vertex samples the lights instead).
            if (!walk) {
                SampledSpectrum c = sample_light(SurfaceVertex{}, m_current_medium);
                if (counted()) L += c;
            }
            PhaseSample ps = sample_hg(wo, mp.g, m_sampler.get_2d());
            if (!(ps.p > 0)) {
                terminated = true;
                return false;
            }
            // The phase function is sampled exactly: beta is unchanged (p / pdf = 1).
            m_r_l = m_r_u / ps.p;
            m_prev_ctx = LightSampleContext{p, Vec3(0, 0, 0), Normal3(0, 0, 0)};
            m_specular_bounce = false;
            m_any_non_specular = true;
            scattered = true;
            next = Ray{p, ps.wi, kInfinity};
            return false;
        }
        // Null scattering: continue along the ray.
        SampledSpectrum sigma_n = sigma_maj - mp.sigma_a - mp.sigma_s;
        for (int i = 0; i < kSpectrumSamples; ++i) sigma_n[i] = std::max(sigma_n[i], Float(0));
        Float pdf = t_maj[0] * sigma_n[0];
        if (!(pdf > 0)) {
            m_beta = SampledSpectrum(0);
            return false;
        }
        m_beta *= t_maj * sigma_n / pdf;
        m_r_u *= t_maj * sigma_n / pdf;
        m_r_l *= t_maj * sigma_maj / pdf;
        return !m_beta.is_zero() && !m_r_u.is_zero();
    }

    // ---- subsurface scattering ------------------------------------------------------------
    // A subsurface material is rendered as pbrt-v4 renders it at its boundary, with a random
    // walk in between instead of pbrt-v4's tabulated BSSRDF: the hit's BSDF is the material's
    // dielectric (material.cpp); a refraction into the object starts a walk in the
    // homogeneous medium of the material's coefficients at that entry point (free flights and
    // collisions as in any medium, with this kernel's spectral MIS, but no light sampling
    // inside); where the walk reaches the boundary, the path leaves with pbrt-v4's exit lobe
    // (bsdf/normalized_fresnel.h), at which lights are sampled with MIS and the next direction
    // is drawn. The random walk transports light inside exactly for any shape and albedo
    // (no diffusion profile); pbrt-v4's entry and exit lobes keep the image comparable with
    // pbrt-v4's and let point lights, which a walk could never hit, light the object.

    /// The walk's medium: the coefficients at the entry point, the boundary's eta and the
    /// exit lobe's normalisation, and the medium the path returns to.
    struct Walk {
        MediumProperties props;
        Float eta = 1, exit_c = 1;
        int outside = -1;
        int scatterings = 0;
    };

    /// Starts a walk inside material m, entered at hit from medium `outside`; returns the
    /// path's new medium (kWalkMedium).
    int enter_walk(const SubsurfaceMaterial& m, const SurfaceHit& hit, int outside) {
        SubsurfaceCoefficients c = subsurface_coefficients(m, m_mctx, hit, m_lambda);
        m_walk.props.sigma_a = c.sigma_a;
        m_walk.props.sigma_s = c.sigma_s;
        m_walk.props.le = SampledSpectrum(0);
        m_walk.props.g = m.g;
        m_walk.eta = m.eta;
        m_walk.exit_c = m.exit_c;
        m_walk.outside = outside;
        m_walk.scatterings = 0;
        return kWalkMedium;
    }

    /// sample_t_maj (media/medium.h) for the walk's medium: homogeneous, its coefficients
    /// already at the path's wavelengths, so one majorant segment with sigma_maj = sigma_t
    /// (every tentative collision is a real one).
    template <typename F>
    SampledSpectrum sample_walk(Ray ray, Float t_max, Float u, Pcg32& rng, F&& callback) const {
        const Float len = length(ray.d);
        t_max = std::min(t_max * len, std::numeric_limits<Float>::max());
        ray.d = ray.d / len;
        const SampledSpectrum sigma_t = m_walk.props.sigma_a + m_walk.props.sigma_s;
        Float t0 = 0;
        if (sigma_t[0] > 0) {
            while (true) {
                Float t = t0 - std::log1p(-std::min(u, Float(0x1.fffffep-1))) / sigma_t[0];
                u = rng.next_float();
                if (!(t < t_max)) break;
                if (!callback(ray.at(t), m_walk.props, sigma_t, exp(sigma_t * -(t - t0))))
                    return SampledSpectrum(1);
                t0 = t;
            }
        }
        return exp(sigma_t * -(t_max - t0));
    }

    /// The walk, arriving along `ray` at the boundary `hit` from inside, is reflected back in
    /// with the boundary's Fresnel reflectance for its angle of incidence (relative IOR
    /// 1 / eta, total internal reflection included), specularly about the geometric normal:
    /// then `ray` is the reflected ray and the result true (the weight F / F is 1). Otherwise
    /// the light crosses the boundary (leave_walk). Without this, every walk reaching the
    /// boundary would leave, and an object of eta 1.5 would reflect about twice the light it
    /// should (diffuse light inside is 60 % reflected back at eta 1.5).
    bool reflect_inside(Ray& ray, const SurfaceHit& hit) {
        const Float u = m_sampler.get_1d();
        if (m_walk.eta == 1) return false;
        const Vec3 d = normalize(ray.d);
        const Vec3 n(hit.ng.x, hit.ng.y, hit.ng.z);
        const Float cos_i = absdot(d, n);
        if (!(u < fr_dielectric(cos_i, 1 / m_walk.eta))) return false;
        ray = spawn_ray(hit, d - 2 * dot(d, n) * n);
        return true;
    }

    /// The walk, arriving along `ray`, leaves the object at `hit`: lights are sampled from
    /// the exit lobe there, and the path goes on outwards along a direction drawn from it.
    /// As pbrt-v4, the exit vertex does not count against maxdepth. False: the path ends.
    bool leave_walk(Ray& ray, SurfaceHit& hit, int& medium) {
        // Outwards: the side of the surface the walk's ray was heading for; the lobe's frame
        // has the shading normal turned to that side (pbrt-v4 uses wo = ns at the exit).
        const bool out_along_ng = dot(ray.d, hit.ng) > 0;
        const Normal3 n = out_along_ng == (dot(hit.ns, hit.ng) > 0) ? hit.ns : -hit.ns;
        hit.wo = Vec3(n.x, n.y, n.z);
        const Bsdf bsdf(Frame::from_z(n), hit.ng, NormalizedFresnelLobe{m_walk.eta, m_walk.exit_c});
        if (!m_scene.light_sampler.empty()) {
            SampledSpectrum c = sample_light(SurfaceVertex{&hit, &bsdf}, m_walk.outside);
            if (counted()) L += c;
        } else {
            m_sampler.skip_1d();
            m_sampler.skip_2d();
        }
        m_prev_ctx = LightSampleContext{hit.p, hit.p_error, hit.ng};
        m_sampler.skip_1d();  // the lobe does not read uc
        const Point2 u2 = m_sampler.get_2d();
        auto bs = bsdf.sample(hit.wo, 0, u2);
        if (!bs || !(bs->pdf_sa > 0)) return false;
        // A direction outwards of the shading normal but inwards of the surface itself
        // (interpolated normals) would re-enter the object as if from outside: it ends here.
        if ((dot(bs->wi, hit.ng) > 0) != out_along_ng) return false;
        m_beta *= bs->f * (absdot(bs->wi, n) / bs->pdf_sa);
        m_r_l = m_r_u / bs->pdf_sa;
        m_specular_bounce = false;
        m_any_non_specular = true;
        // The lobe carries eta^2 (Radiance mode), undoing the entry's 1 / eta^2.
        m_eta_scale /= sqr(m_walk.eta);
        medium = medium_after(hit, bs->wi, m_walk.outside);
        ray = spawn_ray(hit, bs->wi);
        if (m_beta.is_zero() || m_beta.has_nonfinite()) return false;
        return russian_roulette();
    }

    /// A contribution after m_depth scattering vertices belongs to the estimate (the
    /// caller's PathLimits::min_vertices).
    bool counted() const { return m_depth >= m_min_vertices; }

    bool russian_roulette() {
        SampledSpectrum rr = m_beta * m_eta_scale / m_r_u.average();
        Float u = m_sampler.get_1d();
        Float m = rr.max_value();
        if (m < 1 && m_depth > 1) {
            Float q = std::max(Float(0), 1 - m);
            if (u < q) return false;
            m_beta /= 1 - q;
        }
        return true;
    }

    void escaped(const Ray& ray) {
        if (!counted()) return;
        const Vec3 d = normalize(ray.d);
        const bool mis = !(m_depth == 0 || m_specular_bounce);
        for (int li : m_scene.infinite_lights) {
            Float pdf = 0;
            SampledSpectrum le =
                infinite_le(m_scene.lights[size_t(li)], Ray{ray.o, d, kInfinity}, m_lambda,
                            mis ? &pdf : nullptr, true);
            if (le.is_zero()) continue;
            if (!mis) {
                L += m_beta * le / m_r_u.average();
            } else {
                SampledSpectrum r_l = m_r_l * (m_scene.light_sampler.pmf(li) * pdf);
                L += m_beta * le / (m_r_u + r_l).average();
            }
        }
    }

    void emitted(const SurfaceHit& hit) {
        if (!counted()) return;
        const auto& area = std::get<DiffuseAreaLight>(m_scene.lights[size_t(hit.light)]);
        if (area.alpha && area.masked(hit.p)) return;
        SampledSpectrum le = area.l(hit.ng, hit.wo, m_lambda);
        if (le.is_zero()) return;
        if (m_depth == 0 || m_specular_bounce) {
            L += m_beta * le / m_r_u.average();
            return;
        }
        Float p_l =
            m_scene.light_sampler.pmf(hit.light) * area.pdf_li_point(m_prev_ctx, hit.p, hit.ng);
        SampledSpectrum r_l = m_r_l * p_l;
        L += m_beta * le / (m_r_u + r_l).average();
    }

    /// Next-event estimation from a surface vertex (v.hit, v.bsdf) or from the medium vertex
    /// m_medium_p (v.hit null), with the transmittance of the shadow ray through interfaces
    /// and media by ratio tracking.
    SampledSpectrum sample_light(const SurfaceVertex& v, int medium) {
        const Float u_light = m_sampler.get_1d();
        const Point2 u2 = m_sampler.get_2d();
        Float pmf;
        int li = m_scene.light_sampler.sample(u_light, pmf);
        if (li < 0 || pmf <= 0) return SampledSpectrum(0);
        const LightSampleContext ctx =
            v.hit ? LightSampleContext{v.hit->p, v.hit->p_error, v.hit->ng}
                  : LightSampleContext{m_medium_p, Vec3(0, 0, 0), Normal3(0, 0, 0)};
        auto ls = sample_li(m_scene.lights[size_t(li)], ctx, u2, m_lambda, true);
        if (!ls || !(ls->pdf_sa > 0) || ls->L.is_zero()) return SampledSpectrum(0);
        SampledSpectrum f_hat;
        Float scatter_pdf;
        Ray shadow;
        int shadow_medium = medium;
        if (v.hit) {
            Bsdf::Eval ev = v.bsdf->evaluate(v.hit->wo, ls->wi);
            f_hat = ev.f * ev.abs_cos;
            scatter_pdf = ev.pdf_sa;
            if (f_hat.is_zero()) return SampledSpectrum(0);
            shadow_medium = medium_after(*v.hit, ls->wi, medium);
            if (ls->at_infinity)
                shadow = spawn_ray(*v.hit, ls->wi);
            else if (ls->delta)
                shadow = spawn_ray_to(*v.hit, ls->p_light);
            else
                shadow = spawn_ray_between(*v.hit, ls->p_light, ls->p_error, ls->n_light);
        } else {
            Float p = hg_phase(dot(m_medium_wo, ls->wi), m_medium_g);
            f_hat = SampledSpectrum(p);
            scatter_pdf = p;
            shadow = ls->at_infinity ? Ray{m_medium_p, ls->wi, kInfinity}
                                     : Ray{m_medium_p, ls->p_light - m_medium_p, 1 - Float(1e-4)};
        }
        SampledSpectrum r_l(1), r_u(1);
        // The ratio-tracking stream is keyed by the light sample's random numbers as well as the
        // ray: two samples of one shadow ray (a meter's fixed point and a point light) must not
        // share their collisions.
        SampledSpectrum tr = transmittance(shadow, shadow_medium, !ls->at_infinity, r_l, r_u,
                                           hash(u_light, u2.x, u2.y));
        if (tr.is_zero()) return SampledSpectrum(0);
        r_l *= m_r_u * (pmf * ls->pdf_sa);
        r_u *= m_r_u * scatter_pdf;
        SampledSpectrum c = m_beta * f_hat * tr * ls->L;
        return ls->delta ? c / r_l.average() : c / (r_l + r_u).average();
    }

    /// Transmittance along a shadow ray that starts in `medium` (shadow_transmittance of
    /// medium_transport.h).
    SampledSpectrum transmittance(const Ray& ray, int medium, bool to_point, SampledSpectrum& r_l,
                                  SampledSpectrum& r_u, uint64_t key) {
        return shadow_transmittance(m_scene, ray, medium, to_point, m_lambda, r_l, r_u, key,
                                    m_counters);
    }

    const Scene& m_scene;
    SampledWavelengths& m_lambda;
    Sampler& m_sampler;
    PathCounters& m_counters;
    const int m_min_vertices;
    const int m_max_depth;
    const int m_emission_depth;  ///< a medium's emission after k vertices counts if k <= this
    const MaterialContext m_mctx;

    SampledSpectrum m_beta{1}, m_r_u{1}, m_r_l{1};
    bool m_specular_bounce = false;
    bool m_any_non_specular = false;  ///< pbrt-v4's anyNonSpecularBounces (regularize)
    Float m_eta_scale = 1;
    LightSampleContext m_prev_ctx;
    int m_depth = 0;
    // The medium vertex being scattered at (collision() to sample_light()).
    int m_current_medium = -1;
    Point3 m_medium_p;
    Vec3 m_medium_wo;
    Float m_medium_g = 0;
    Walk m_walk;  ///< the subsurface walk the path is in (medium kWalkMedium)
};

}  // namespace

SampledSpectrum volpath_li(const Scene& scene, const Ray& ray, int medium, bool found,
                           SurfaceHit& hit, SampledWavelengths& lambda, Sampler& sampler,
                           PathCounters& counters, const PathLimits& limits) {
    VolPath path(scene, lambda, sampler, counters, limits);
    path.trace(ray, medium, found, hit);
    return path.L;
}

SampledSpectrum volpath_lo(const Scene& scene, const SurfaceHit& vertex, const Bsdf& bsdf,
                           int medium, SampledWavelengths& lambda, Sampler& sampler,
                           PathCounters& counters, const PathLimits& limits) {
    VolPath path(scene, lambda, sampler, counters, limits);
    Ray ray;
    if (path.scatter(vertex, bsdf, medium, ray)) {
        SurfaceHit hit;
        ++counters.rays;
        const bool found = scene.intersect(ray, hit);
        path.trace(ray, medium, found, hit);
    }
    return path.L;
}

}  // namespace sr
