#include "steradian/integrators/path/path.h"

#include "steradian/scene/scene.h"

namespace sr {

namespace {

/// Power heuristic with beta = 2 (Veach 1997, sec. 9.2.4), for one sample of each strategy.
inline Float power_heuristic(Float pf, Float pg) {
    Float f = pf * pf, g = pg * pg;
    if (std::isinf(f)) return 1;
    return f + g > 0 ? f / (f + g) : 0;
}

}  // namespace

SampledSpectrum path_li(const Scene& scene, Ray ray, SampledWavelengths& lambda, Sampler& sampler,
                        PathCounters& counters) {
    const IntegratorSettings& cfg = scene.integrator;
    const bool use_nee = cfg.strategy != LightStrategy::BsdfOnly;
    const bool use_bsdf_hits = cfg.strategy != LightStrategy::LightOnly;
    const MaterialContext mctx = scene.material_context();

    SampledSpectrum L(0), beta(1);
    bool specular_bounce = false;
    Float eta_scale = 1;
    Float prev_pdf_sa = 0;
    LightSampleContext prev_ctx;
    int depth = 0;
    int interface_crossings = 0;

    while (true) {
        SurfaceHit hit;
        ++counters.rays;
        bool found = scene.intersect(ray, hit);
        if (!found) {
            for (int li : scene.infinite_lights) {
                const auto& inf = std::get<UniformInfiniteLight>(scene.lights[li]);
                SampledSpectrum le = inf.le(ray.d, lambda);
                if (depth == 0 || specular_bounce) {
                    L += beta * le;
                } else if (use_bsdf_hits) {
                    Float w = 1;
                    if (use_nee) {
                        Float p_l = scene.light_sampler.pmf(li) * inf.pdf_li(prev_ctx, ray.d);
                        w = power_heuristic(prev_pdf_sa, p_l);
                    }
                    L += beta * le * w;
                }
            }
            break;
        }

        // Emission at the hit point.
        if (hit.light >= 0) {
            const auto& area = std::get<DiffuseAreaLight>(scene.lights[hit.light]);
            SampledSpectrum le = area.l(hit.ng, hit.wo, lambda);
            if (!le.is_zero()) {
                if (depth == 0 || specular_bounce) {
                    L += beta * le;
                } else if (use_bsdf_hits) {
                    Float w = 1;
                    if (use_nee) {
                        Float p_l = scene.light_sampler.pmf(hit.light) *
                                    area.pdf_li_point(prev_ctx, hit.p, hit.ng);
                        w = power_heuristic(prev_pdf_sa, p_l);
                    }
                    L += beta * le * w;
                }
            }
        }

        std::optional<Bsdf> bsdf;
        if (hit.material >= 0) bsdf = make_bsdf(scene.materials[hit.material], mctx, hit, lambda);
        if (!bsdf) {
            // Interface: continue straight through without counting a bounce (bounded, in
            // case a degenerate surface keeps returning the same hit).
            if (++interface_crossings > 256) break;
            ray = spawn_ray(hit, ray.d);
            continue;
        }

        if (depth++ == cfg.max_depth) break;

        LightSampleContext ctx{hit.p, hit.p_error, hit.ng};

        // Next-event estimation.
        if (use_nee && bsdf->has_non_specular() && !scene.light_sampler.empty()) {
            Float u_light = sampler.get_1d();
            Point2 u2 = sampler.get_2d();
            Float pmf;
            int li = scene.light_sampler.sample(u_light, pmf);
            if (li >= 0 && pmf > 0) {
                const Light& light = scene.lights[li];
                auto ls = sample_li(light, ctx, u2, lambda);
                if (ls && ls->pdf_sa > 0 && !ls->L.is_zero()) {
                    Bsdf::Eval ev = bsdf->evaluate(hit.wo, ls->wi);
                    SampledSpectrum f = ev.f * ev.abs_cos;
                    if (!f.is_zero()) {
                        Ray shadow;
                        if (ls->at_infinity)
                            shadow = spawn_ray(hit, ls->wi);
                        else if (ls->delta)
                            shadow = spawn_ray_to(hit, ls->p_light);
                        else
                            shadow = spawn_ray_between(hit, ls->p_light, ls->p_error, ls->n_light);
                        ++counters.rays;
                        if (!scene.occluded(shadow)) {
                            Float p_l = pmf * ls->pdf_sa;
                            Float w = (ls->delta || !use_bsdf_hits)
                                          ? 1
                                          : power_heuristic(p_l, ev.pdf_sa);
                            L += beta * f * ls->L * (w / p_l);
                        }
                    }
                }
            }
        }

        // BSDF sampling.
        Float uc = sampler.get_1d();
        Point2 u = sampler.get_2d();
        auto bs = bsdf->sample(hit.wo, uc, u);
        if (!bs) break;
        beta *= bs->f * (absdot(bs->wi, hit.ns) / bs->pdf_sa);
        specular_bounce = bs->is_specular();
        prev_pdf_sa = bs->pdf_sa;
        prev_ctx = ctx;
        if (bs->is_transmission()) eta_scale *= sqr(bs->eta);
        ray = spawn_ray(hit, bs->wi);

        // Russian roulette (unbiased: survivors are reweighted by 1 / (1 - q)).
        SampledSpectrum rr_beta = beta * eta_scale;
        Float m = rr_beta.max_value();
        if (m < 1 && depth > 1) {
            Float q = std::max(Float(0), 1 - m);
            if (sampler.get_1d() < q) break;
            beta /= 1 - q;
        }
        if (beta.is_zero()) break;
    }
    return L;
}

}  // namespace sr
