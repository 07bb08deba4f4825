#include "steradian/integrators/path/path.h"
#include "steradian/integrators/path/visible_point.h"

#include <climits>

#include "steradian/integrators/path/volpath.h"
#include "steradian/scene/scene.h"

namespace sr {

namespace {

/// Power heuristic with beta = 2 (Veach 1997, sec. 9.2.4), for one sample of each strategy.
inline Float power_heuristic(Float pf, Float pg) {
    Float f = pf * pf, g = pg * pg;
    if (std::isinf(f)) return 1;
    return f + g > 0 ? f / (f + g) : 0;
}

/// power_heuristic(pf, pg) / pf with one division instead of two (the light sample's MIS
/// weight over its pdf; the two divisions in a row sat on the light sample's chain).
inline Float power_heuristic_over_pdf(Float pf, Float pg) {
    Float f = pf * pf, g = pg * pg;
    if (std::isinf(f)) return 1 / pf;
    return f + g > 0 ? pf / (f + g) : 0;
}

/// One path's state. `depth` counts the scattering vertices so far; a contribution made of
/// emission found after k vertices, or of a light sampled at the k-th vertex, has k vertices
/// and is counted only if k >= min_vertices.
class PathState {
public:
    PathState(const Scene& scene, SampledWavelengths& lambda, Sampler& sampler,
              PathCounters& counters, const PathLimits& limits)
        : m_scene(scene), m_cfg(scene.integrator), m_lambda(lambda), m_sampler(sampler),
          m_counters(counters), m_min_vertices(limits.min_vertices),
          m_max_depth(limits.max_depth == PathLimits::kSceneDepth ? scene.integrator.max_depth
                      : limits.max_depth < 0                      ? INT_MAX
                                                                  : limits.max_depth),
          m_use_nee(m_cfg.strategy != LightStrategy::BsdfOnly),
          m_use_bsdf_hits(m_cfg.strategy != LightStrategy::LightOnly &&
                          !limits.light_sample_only),
          m_mctx(scene.material_context()) {}

    SampledSpectrum L{0};

    /// Leaves the first vertex's light sample in `d`, its shadow ray untested (path_li_from).
    void defer_first_shadow(DeferredShadowRay* d) { m_first_shadow = d; }
    /// Gives the vertices texture footprints at this scale; the first hit has its own.
    void use_footprints(Float scale) {
        m_footprint_scale = scale;
        m_first_footprint = scale > 0;
    }
    /// Records the first surface that scatters in `v` (path_li_from).
    void record_visible(VisibleSurface* v) { m_visible = v; }
    /// Ends the path at SPPM's visible point, recorded in `vp` (path_li_visible_point).
    void stop_at_visible_point(VisiblePoint* vp) { m_vp = vp; }

    /// The light sample of a first vertex alone (PathLimits::light_sample_only).
    void sample_light_only(const SurfaceHit& hit, const Bsdf& bsdf) {
        if (m_depth++ == m_max_depth) return;
        m_prev_ctx = LightSampleContext{hit.p, hit.p_error, hit.ng};
        if (m_use_nee && bsdf.has_non_specular() && !m_scene.light_sampler.empty())
            sample_light(hit, bsdf, m_prev_ctx);
    }

    /// Follows `ray` until the path ends.
    void trace(Ray ray) {
        // One hit record for the whole path: Scene::intersect writes every field of it, and a
        // fresh one per segment cost a 136-byte zero fill (rep stos) each time.
        SurfaceHit hit;
        ++m_counters.rays;
        trace(ray, m_scene.intersect(ray, hit), hit);
    }

    /// Follows `ray`, whose first intersection is `hit` if `found`, until the path ends
    /// (`hit` is the path's hit record).
    void trace(Ray ray, bool found, SurfaceHit& hit) {
        while (true) {
            if (!found) {
                escaped(ray);
                return;
            }
            if (hit.light >= 0) emitted(hit);
            if (m_footprint_scale > 0) {
                if (!m_first_footprint && hit.material >= 0) {
                    m_scene.camera->approximate_dp_dxy(hit.p, hit.ng, m_footprint_scale,
                                                       hit.dpdx, hit.dpdy);
                    set_uv_differentials(hit);
                }
                m_first_footprint = false;
            }
            // Initialised from make_bsdf's result itself (assigning it copied it once more).
            std::optional<Bsdf> bsdf =
                hit.material >= 0
                    ? make_bsdf(m_scene.materials[hit.material], m_mctx, hit, m_lambda)
                    : std::nullopt;
            if (m_visible && bsdf && m_depth == 0) visible(hit, *bsdf);
            // pbrt-v4's "regularize": after a non-specular bounce, near-specular lobes widen.
            if (bsdf && m_any_non_specular && m_cfg.regularize) bsdf->regularize();
            if (!bsdf) {
                // Interface: continue straight through without counting a bounce (bounded,
                // in case a degenerate surface keeps returning the same hit).
                if (++m_interface_crossings > 256) return;
                ray = spawn_ray(hit, ray.d);
            } else if (m_vp && m_vp->set) {
                return;  // SPPM: the emission the visible point's BSDF sample found is in
            } else if (!scatter(hit, *bsdf, ray)) {
                return;
            }
            ++m_counters.rays;
            found = m_scene.intersect(ray, hit);
        }
    }

    /// Light sampling and BSDF sampling at a scattering vertex. Returns false when the path
    /// ends here, else true with the continuation ray in `next` (written in place: a returned
    /// std::optional<Ray> was copied out through the stack, stalling the loads).
    bool scatter(const SurfaceHit& hit, const Bsdf& bsdf, Ray& next) {
        if (m_depth++ == m_max_depth) return false;
        // The vertex's context, kept for the MIS weight of emission the BSDF sample finds.
        m_prev_ctx = LightSampleContext{hit.p, hit.p_error, hit.ng};
        if (m_use_nee && bsdf.has_non_specular() && !m_scene.light_sampler.empty())
            sample_light(hit, bsdf, m_prev_ctx);
        // SPPM's visible point: the first diffuse vertex, or a glossy one at the last depth
        // (pbrt-v4's SPPM camera pass); the path goes on for the emission its BSDF sample
        // finds, and ends at the next surface.
        if (m_vp && !m_vp->set) {
            const uint8_t fl = bsdf.flags();
            if ((fl & kLobeDiffuse) || ((fl & kLobeGlossy) && m_depth == m_max_depth)) {
                m_vp->set = true;
                m_vp->p = hit.p;
                m_vp->wo = hit.wo;
                m_vp->beta = m_beta;
                m_vp->bsdf = bsdf;
                m_vp->secondary_terminated = m_lambda.secondary_terminated();
            }
        }

        // The lobe-choice dimension is consumed either way; a single-lobe BSDF skips
        // computing it (the same dimensions, and so the same image, for less work).
        Float uc = 0;
        if (bsdf.uses_uc())
            uc = m_sampler.get_1d();
        else
            m_sampler.skip_1d();
        Point2 u = m_sampler.get_2d();
        auto bs = bsdf.sample(hit.wo, uc, u);
        if (!bs) return false;
        // The lobe's closed form of |cos| / pdf where it has one (a division less on the
        // path's chain); the shading normal is the frame's z, so |cos| = |wi . ns|.
        m_beta *= bs->f * (bs->cos_over_pdf > 0 ? bs->cos_over_pdf
                                                 : absdot(bs->wi, hit.ns) / bs->pdf_sa);
        m_specular_bounce = bs->is_specular();
        m_any_non_specular |= !m_specular_bounce;
        m_prev_pdf_sa = bs->pdf_sa;
        if (bs->is_transmission()) m_eta_scale *= sqr(bs->eta);
        next = spawn_ray(hit, bs->wi);

        // Russian roulette (unbiased: survivors are reweighted by 1 / (1 - q)).
        SampledSpectrum rr_beta = m_beta * m_eta_scale;
        Float m = rr_beta.max_value();
        if (m_depth > 1 && m < 1) {
            Float q = std::max(Float(0), 1 - m);
            if (m_sampler.get_1d() < q) return false;
            m_beta /= 1 - q;
        }
        return !m_beta.is_zero();
    }

private:
    bool counted() const { return m_depth >= m_min_vertices; }

    /// pbrt-v4's VisibleSurface of the first scattering vertex (its dpdx, dpdy are the
    /// renderer's): the normals facing wo, and the BSDF's directional albedo estimated from 16
    /// fixed stratified samples (exact for a Lambertian lobe, whose every cosine-weighted
    /// sample weighs its reflectance).
    void visible(const SurfaceHit& hit, const Bsdf& bsdf) {
        VisibleSurface& v = *m_visible;
        v.set = true;
        v.p = hit.p;
        v.n = face_forward(hit.ng, hit.wo);
        v.ns = face_forward(bsdf.frame().n, hit.wo);
        v.uv = hit.uv;
        // The footprint the renderer gave the camera ray's hit (zero behind an interface
        // unless textures use footprints).
        v.dpdx = hit.dpdx;
        v.dpdy = hit.dpdy;
        v.albedo = SampledSpectrum(0);
        constexpr int kRho = 16;
        for (int i = 0; i < kRho; ++i) {
            // The 4 x 4 stratum centres, with the lobe choice by the bit-reversed index.
            const int r = ((i & 1) << 3) | ((i & 2) << 1) | ((i & 4) >> 1) | ((i & 8) >> 3);
            const Point2 u((Float(i % 4) + 0.5f) / 4, (Float(i / 4) + 0.5f) / 4);
            auto bs = bsdf.sample(hit.wo, (Float(r) + 0.5f) / kRho, u);
            if (!bs || !(bs->pdf_sa > 0 || bs->cos_over_pdf > 0)) continue;
            v.albedo +=
                bs->f * (bs->cos_over_pdf > 0 ? bs->cos_over_pdf
                                              : absdot(bs->wi, bsdf.frame().n) / bs->pdf_sa);
        }
        v.albedo *= Float(1) / kRho;
        m_visible = nullptr;
    }

    /// Weight of emission reached by the last BSDF sample against light sampling.
    Float hit_weight(Float p_light) const {
        if (m_depth == 0 || m_specular_bounce) return 1;
        if (!m_use_bsdf_hits) return 0;
        return m_use_nee ? power_heuristic(m_prev_pdf_sa, p_light) : 1;
    }

    void escaped(const Ray& ray) {
        if (!counted()) return;
        for (int li : m_scene.infinite_lights) {
            // With the density of the light sample this direction could have been (the
            // compensated one of an image light, as sample_light draws it).
            const bool mis = !(m_depth == 0 || m_specular_bounce || !m_use_nee);
            Float pdf = 0;
            const SampledSpectrum le = infinite_le(m_scene.lights[li], ray, m_lambda,
                                                   mis ? &pdf : nullptr, m_use_bsdf_hits);
            Float w = hit_weight(mis ? m_scene.light_sampler.pmf(li) * pdf : 0);
            if (w > 0) L += m_beta * le * w;
        }
    }

    void emitted(const SurfaceHit& hit) {
        if (!counted()) return;
        const auto& area = std::get<DiffuseAreaLight>(m_scene.lights[hit.light]);
        if (area.alpha && area.masked(hit.p)) return;
        SampledSpectrum le = area.l(hit.ng, hit.wo, m_lambda);
        if (le.is_zero()) return;
        Float p_l = (m_depth == 0 || m_specular_bounce || !m_use_nee)
                        ? 0
                        : m_scene.light_sampler.pmf(hit.light) *
                              area.pdf_li_point(m_prev_ctx, hit.p, hit.ng);
        Float w = hit_weight(p_l);
        if (w > 0) L += m_beta * le * w;
    }

    void sample_light(const SurfaceHit& hit, const Bsdf& bsdf, const LightSampleContext& ctx) {
        // The sample dimensions are consumed whether or not the contribution counts, so
        // the components of a meter reading use the same random numbers.
        Float u_light = m_sampler.get_1d();
        Point2 u2 = m_sampler.get_2d();
        if (!counted()) return;
        Float pmf;
        int li = m_scene.light_sampler.sample(u_light, pmf);
        if (li < 0 || pmf <= 0) return;
        // An image light may sample only where it is brighter than average when BSDF
        // samples, combined by MIS, cover the rest (pbrt-v4's allowIncompletePDF).
        auto ls = sample_li(m_scene.lights[li], ctx, u2, m_lambda, m_use_bsdf_hits);
        if (!ls || ls->pdf_sa <= 0 || ls->L.is_zero()) return;
        Bsdf::Eval ev = bsdf.evaluate(hit.wo, ls->wi);
        SampledSpectrum f = ev.f * ev.abs_cos;
        if (f.is_zero()) return;
        Ray shadow;
        if (ls->at_infinity)
            shadow = spawn_ray(hit, ls->wi);
        else if (ls->delta)
            shadow = spawn_ray_to(hit, ls->p_light);
        else
            shadow = spawn_ray_between(hit, ls->p_light, ls->p_error, ls->n_light);
        ++m_counters.rays;
        const bool defer = m_first_shadow && m_depth == 1;
        if (!defer && m_scene.occluded(shadow)) return;
        Float p_l = pmf * ls->pdf_sa;
        Float w_over_p = (ls->delta || !m_use_bsdf_hits) ? 1 / p_l
                                                         : power_heuristic_over_pdf(p_l, ev.pdf_sa);
        SampledSpectrum c = m_beta * f * ls->L * w_over_p;
        if (defer) {
            m_first_shadow->pending = true;
            m_first_shadow->ray = shadow;
            m_first_shadow->contribution = c;
        } else {
            L += c;
        }
    }

    const Scene& m_scene;
    const IntegratorSettings& m_cfg;
    SampledWavelengths& m_lambda;
    Sampler& m_sampler;
    PathCounters& m_counters;
    const int m_min_vertices;
    const int m_max_depth;
    const bool m_use_nee, m_use_bsdf_hits;
    const MaterialContext m_mctx;

    SampledSpectrum m_beta{1};
    bool m_specular_bounce = false;
    bool m_any_non_specular = false;  ///< pbrt-v4's anyNonSpecularBounces (regularize)
    Float m_eta_scale = 1;
    Float m_prev_pdf_sa = 0;
    LightSampleContext m_prev_ctx;
    int m_depth = 0;
    int m_interface_crossings = 0;
    DeferredShadowRay* m_first_shadow = nullptr;
    Float m_footprint_scale = 0;
    bool m_first_footprint = false;  ///< the current hit is the camera ray's, footprint set
    VisibleSurface* m_visible = nullptr;
    VisiblePoint* m_vp = nullptr;
};

}  // namespace

SampledSpectrum path_li(const Scene& scene, Ray ray, SampledWavelengths& lambda, Sampler& sampler,
                        PathCounters& counters, const PathLimits& limits, int medium) {
    if (scene.integrator.volumetric) {
        SurfaceHit hit;
        ++counters.rays;
        bool found = scene.intersect(ray, hit);
        return volpath_li(scene, ray, medium == kCameraMedium ? scene.camera_medium : medium,
                          found, hit, lambda, sampler, counters, limits);
    }
    PathState path(scene, lambda, sampler, counters, limits);
    path.trace(ray);
    return path.L;
}

SampledSpectrum path_li_from(const Scene& scene, const Ray& ray, bool found, SurfaceHit& hit,
                             SampledWavelengths& lambda, Sampler& sampler,
                             PathCounters& counters, DeferredShadowRay* first_shadow,
                             VisibleSurface* visible, Float footprint_scale) {
    if (first_shadow) first_shadow->pending = false;
    if (scene.integrator.volumetric) {
        ++counters.rays;
        return volpath_li(scene, ray, scene.camera_medium, found, hit, lambda, sampler, counters);
    }
    PathState path(scene, lambda, sampler, counters, PathLimits{});
    path.defer_first_shadow(first_shadow);
    path.use_footprints(footprint_scale);
    if (visible) visible->set = false;
    path.record_visible(visible);
    ++counters.rays;
    path.trace(ray, found, hit);
    return path.L;
}

SampledSpectrum path_li_visible_point(const Scene& scene, const Ray& ray,
                                      SampledWavelengths& lambda, Sampler& sampler,
                                      PathCounters& counters, VisiblePoint& vp) {
    vp.set = false;
    vp.bsdf.reset();
    PathState path(scene, lambda, sampler, counters, PathLimits{});
    path.stop_at_visible_point(&vp);
    path.trace(ray);
    return path.L;
}

SampledSpectrum path_lo(const Scene& scene, const SurfaceHit& vertex, const Bsdf& bsdf,
                        SampledWavelengths& lambda, Sampler& sampler, PathCounters& counters,
                        const PathLimits& limits, int medium) {
    if (scene.integrator.volumetric)
        return volpath_lo(scene, vertex, bsdf, medium, lambda, sampler, counters, limits);
    PathState path(scene, lambda, sampler, counters, limits);
    if (limits.light_sample_only) {
        path.sample_light_only(vertex, bsdf);
        return path.L;
    }
    Ray ray;
    if (path.scatter(vertex, bsdf, ray)) path.trace(ray);
    return path.L;
}

}  // namespace sr
