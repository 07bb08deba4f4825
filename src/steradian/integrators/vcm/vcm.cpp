#include "steradian/integrators/vcm/vcm.h"

#include <algorithm>
#include <array>
#include <chrono>
#include <cmath>
#include <thread>
#include <vector>

#include <tbb/blocked_range.h>
#include <tbb/enumerable_thread_specific.h>
#include <tbb/global_control.h>
#include <tbb/parallel_for.h>
#include <tbb/task_arena.h>

#include "steradian/core/error.h"
#include "steradian/integrators/bdpt/bdpt.h"
#include "steradian/integrators/distributed.h"
#include "steradian/integrators/integrator.h"
#include "steradian/integrators/iterations.h"
#include "steradian/integrators/path/medium_transport.h"
#include "steradian/integrators/progress.h"
#include "steradian/media/medium.h"
#include "steradian/sampling/hash.h"
#include "steradian/sampling/padded_sobol_sampler.h"
#include "steradian/scene/scene.h"

namespace sr {

namespace {

using Clock = std::chrono::steady_clock;

/// Light paths a task of the light pass traces (the unit of its ordered splat reduction).
constexpr int64_t kLightChunk = 256;
/// The most memory the stored light vertices of one iteration may take.
constexpr double kMaxVertexBytes = 4.0 * (1 << 30);

/// The power heuristic (exponent 2) applied to a density ratio: Georgiev's Mis().
inline Float mis(Float x) { return x * x; }

/// A stored vertex of a light path (SmallVCM's PathVertex): where it is, the path's
/// throughput up to it (not including its BSDF), its BSDF and the MIS quantities of the
/// light subpath that reached it (tech. report, eqs. 31-36; with the cosines and distances
/// of the vertex itself applied).
struct LightVertex {
    Point3 p;
    Vec3 p_error;
    Normal3 ng;  ///< zero at a medium vertex
    Vec3 wo;     ///< unit, towards the previous vertex of the light path
    SampledSpectrum beta{0};
    Float dvcm = 0, dvc = 0, dvm = 0;
    uint8_t length = 0;        ///< segments from the light
    bool terminated = false;   ///< the path's secondary wavelengths were terminated
    bool in_medium = false;    ///< a scattering in a medium (phase function g), not a surface
    Float g = 0;
    /// The media on the two sides (a surface's MediumInterface where it is a transition,
    /// else the medium the path was in; a medium vertex's medium on both; -1: vacuum).
    int medium_in = -1, medium_out = -1;
    Bsdf bsdf;  ///< surfaces only
};

/// What scatters at a vertex: a BSDF, or (bsdf null) a medium's Henyey-Greenstein phase
/// function, which has no cosine factor and is its own sampling density.
struct Scatter {
    const Bsdf* bsdf = nullptr;
    Float g = 0;
    SampledSpectrum f(Vec3 wo, Vec3 wi, TransportMode mode) const {
        return bsdf ? bsdf->f(wo, wi, mode) : SampledSpectrum(hg_phase(dot(wo, wi), g));
    }
    Float pdf(Vec3 wo, Vec3 wi, TransportMode mode) const {
        return bsdf ? bsdf->pdf(wo, wi, mode) : hg_phase(dot(wo, wi), g);
    }
    /// f and the density of sampling wi from wo (radiance transport).
    Bsdf::Eval evaluate(Vec3 wo, Vec3 wi) const {
        if (bsdf) return bsdf->evaluate(wo, wi);
        const Float p = hg_phase(dot(wo, wi), g);
        return {SampledSpectrum(p), p, 1};
    }
    /// The shading cosine of the scattering integral (1 in a medium).
    Float cos_shading(Vec3 w) const { return bsdf ? absdot(w, bsdf->frame().n) : 1; }
};

/// The geometric cosine of a density conversion at a vertex of normal ng (1 in a medium).
inline Float cos_geom(Normal3 ng, Vec3 w) {
    return ng.x != 0 || ng.y != 0 || ng.z != 0 ? absdot(ng, w) : 1;
}

/// The medium a path leaving a vertex (normal ng, media in/out) in direction w is in.
inline int medium_towards(Normal3 ng, int medium_in, int medium_out, Vec3 w) {
    return dot(w, ng) < 0 ? medium_in : medium_out;
}

/// A camera path's vertex, for the strategies made at it.
struct CameraVertex {
    Point3 p;
    Vec3 p_error;
    Normal3 ng;  ///< zero at a medium vertex
    Vec3 wo;     ///< unit, towards the previous vertex
    int medium_in = -1, medium_out = -1;
    Scatter sc;
};

/// A light vertex's connection to the camera as a film position and sensor values.
struct Splat {
    Point2 p;
    std::array<double, 3> xyz;
};

/// The hash grid of the light vertices (SmallVCM's HashGrid): cells 2 r wide, each vertex
/// in the cell of its position, the cells hashed to a power-of-two count of buckets, each
/// bucket's vertices in index order (a counting sort). A query visits the buckets of the at
/// most 2 x 2 x 2 cells its sphere meets, each bucket once.
class VertexGrid {
public:
    void build(const std::vector<LightVertex>& v, const std::vector<uint32_t>& ids, Float r) {
        m_items.clear();
        m_start.assign(1, 0);
        m_size = 0;
        if (ids.empty()) return;
        m_lo = v[ids[0]].p;
        for (uint32_t i : ids) {
            const Point3 p = v[i].p;
            m_lo = Point3(std::min(m_lo.x, p.x), std::min(m_lo.y, p.y), std::min(m_lo.z, p.z));
        }
        m_inv_cell = 1 / (2 * double(r));
        m_size = 1;
        while (m_size < ids.size()) m_size <<= 1;
        std::vector<uint32_t> count(m_size + 1, 0);
        for (uint32_t i : ids) ++count[bucket_of(v[i].p) + 1];
        for (size_t b = 0; b < m_size; ++b) count[b + 1] += count[b];
        m_start = count;
        m_items.resize(ids.size());
        for (uint32_t i : ids) m_items[count[bucket_of(v[i].p)]++] = i;
    }

    /// Calls fn(vertex index) for every vertex whose cell may lie within r of p (the
    /// caller tests the distance), in a fixed order.
    template <typename Fn>
    void query(Point3 p, Float r, Fn&& fn) const {
        if (m_size == 0) return;
        int64_t lo[3], hi[3];
        const double c[3] = {double(p.x) - double(m_lo.x), double(p.y) - double(m_lo.y),
                             double(p.z) - double(m_lo.z)};
        for (int k = 0; k < 3; ++k) {
            lo[k] = cell((c[k] - double(r)) * m_inv_cell);
            hi[k] = cell((c[k] + double(r)) * m_inv_cell);
        }
        uint32_t buckets[27];
        int n = 0;
        for (int64_t z = lo[2]; z <= hi[2]; ++z)
            for (int64_t y = lo[1]; y <= hi[1]; ++y)
                for (int64_t x = lo[0]; x <= hi[0]; ++x)
                    if (n < 27) buckets[n++] = bucket(x, y, z);
        std::sort(buckets, buckets + n);
        n = int(std::unique(buckets, buckets + n) - buckets);
        for (int i = 0; i < n; ++i)
            for (uint32_t j = m_start[buckets[i]]; j < m_start[buckets[i] + 1]; ++j) fn(m_items[j]);
    }

private:
    static int64_t cell(double t) {
        return int64_t(std::clamp(std::floor(t), -double(int64_t(1) << 40), double(int64_t(1) << 40)));
    }
    uint32_t bucket(int64_t x, int64_t y, int64_t z) const {
        const uint64_t h =
            hash_combine(hash_combine(mix_bits(uint64_t(x)), uint64_t(y)), uint64_t(z));
        return uint32_t(h & (m_size - 1));
    }
    uint32_t bucket_of(Point3 p) const {
        return bucket(cell((double(p.x) - double(m_lo.x)) * m_inv_cell),
                      cell((double(p.y) - double(m_lo.y)) * m_inv_cell),
                      cell((double(p.z) - double(m_lo.z)) * m_inv_cell));
    }

    Point3 m_lo;
    double m_inv_cell = 1;
    size_t m_size = 0;
    std::vector<uint32_t> m_start, m_items;
};

struct ThreadState {
    std::unique_ptr<Sampler> cam_sampler, light_sampler;
    PathCounters counters;
    uint64_t nonfinite = 0;
};

bool is_infinite_light(const Light& l) {
    return std::holds_alternative<DistantLight>(l) || std::holds_alternative<UniformInfiniteLight>(l) ||
           std::holds_alternative<ImageInfiniteLight>(l);
}

/// The complete solid-angle density of sample_li() of an infinite light choosing the
/// direction w (towards the light) at p.
Float infinite_pdf_li(const Light& l, Point3 p, Vec3 w) {
    if (const auto* u = std::get_if<UniformInfiniteLight>(&l)) return u->pdf_li({}, w);
    if (const auto* im = std::get_if<ImageInfiniteLight>(&l))
        return im->pdf_li(LightSampleContext{p, {0, 0, 0}, {0, 0, 0}}, w, false);
    return 0;
}

/// The estimator: settings of a render and the kernels of both passes.
class Vcm {
public:
    Vcm(const Scene& scene, const Film& film, const BidirContext& ctx, bool connect, bool merge)
        : m_scene(scene), m_film(film), m_ctx(ctx), m_mctx(scene.material_context()),
          m_connect(connect), m_merge(merge), m_media(!scene.media.empty()) {}

    /// Per iteration: the merge radius, the light paths' count and wavelengths.
    void start_iteration(Float radius, int64_t n_light, const SampledWavelengths& lambda) {
        m_radius = radius;
        m_n_light = n_light;
        // A light path connected to the camera is one of N samples of the whole film's
        // light tracing (importance is normalised to the full film): its splat is scaled by
        // the full film's pixels over N.
        const FilmParams& fp = m_film.params();
        m_lt_factor = Float(double(fp.resolution.x) * double(fp.resolution.y) / double(n_light));
        m_lambda = lambda;
        m_tr_key = hash(lambda[0], lambda[1], lambda[2], lambda[3]);
        const double eta = kPi * double(radius) * double(radius) * double(n_light);
        // Georgiev's mMisVmWeightFactor and mMisVcWeightFactor, the latter kept on when
        // connections are off: it also relates merging to the camera paths that hit
        // emitters, which are always on (the connections' own terms are switched off by
        // m_vc where they occur).
        m_vm_factor = m_merge ? Float(eta * eta) : 0;
        m_vc_factor = Float(1 / (eta * eta));
        m_vc = m_connect ? 1 : 0;
        m_merge_norm = 1 / eta;
    }

    /// Light path `index`: its stored vertices in out[0, count) and, with connections on,
    /// its connections to the camera in `splats` (in vertex order).
    void light_path(Sampler& sampler, PathCounters& counters, LightVertex* out, uint8_t& count,
                    std::vector<Splat>& splats, uint64_t& nonfinite) const {
        count = 0;
        const Float ul = sampler.get_pixel_1d();
        const Point2 u_pos = sampler.get_pixel_2d();
        const Point2 u_dir = sampler.get_2d();
        const int max_depth = m_ctx.max_depth;
        if (max_depth < 1 || m_scene.light_sampler.empty()) return;
        Float pmf = 0;
        const int li = m_scene.light_sampler.sample(ul, pmf);
        if (li < 0 || !(pmf > 0)) return;
        const Light& light = m_scene.lights[size_t(li)];
        SampledWavelengths lambda = m_lambda;
        auto les = sample_le(light, u_pos, u_dir, lambda);
        if (!les || !(les->pdf_pos > 0) || !(les->pdf_dir > 0) || les->L.is_zero()) return;
        const bool delta_pos = light_delta_position(light), delta_dir = light_delta_direction(light);
        const bool infinite = is_infinite_light(light);
        const bool on_surface = les->n.x != 0 || les->n.y != 0 || les->n.z != 0;
        const Float cos0 = on_surface ? absdot(les->n, les->ray.d) : 1;
        const Float emission = pmf * les->pdf_pos * les->pdf_dir;
        SampledSpectrum beta = les->L * (cos0 / emission);
        // The origin's dVC (eq. 32: cos / emission density; zero for a delta light, which
        // no path from the camera can reach) and dVM = dVC / eta.
        const Float dvc0 = delta_pos || delta_dir ? 0 : mis(cos0 / emission);
        Float dvcm = 0, dvc = 0, dvm = 0;
        Ray ray = les->ray;
        Point3 prev = les->p;
        int length = 0, crossings = 0;
        // The medium the light's ray starts in (Scene::light_media; vacuum at infinity).
        int medium = -1;
        if (!infinite && size_t(li) < m_scene.light_media.size())
            medium = medium_towards(les->n, m_scene.light_media[size_t(li)].inside,
                                    m_scene.light_media[size_t(li)].outside, les->ray.d);
        while (true) {
            SurfaceHit hit;
            std::optional<Bsdf> bsdf;
            Point3 p_scatter;
            Float g = 0;
            const Next next = next_vertex(ray, medium, crossings, hit, bsdf, p_scatter, g, sampler,
                                          lambda, beta, counters);
            if (next == Next::End || next == Next::Escaped) break;
            const bool scattered = next == Next::Medium;
            ++length;
            // The vertex: a surface, or a scattering in the medium (no normal, no cosine).
            const Point3 p = scattered ? p_scatter : hit.p;
            const Normal3 ng = scattered ? Normal3(0, 0, 0) : hit.ng;
            const Vec3 wo = scattered ? -normalize(ray.d) : hit.wo;
            const Float cos_in = scattered ? 1 : absdot(hit.ng, hit.wo);
            if (!(cos_in > 0)) break;
            if (length == 1) {
                // dVCM at the first vertex: the density with which a light sample taken
                // here picks the light's point over the density of the emitted ray (both in
                // area measure here; the light's choice cancels).
                const Float d2 = length_squared(p - prev);
                Float nee_over_emit = 0;
                if (delta_pos)
                    nee_over_emit = d2 / (les->pdf_dir * cos_in);
                else if (delta_dir)
                    nee_over_emit = 1 / (les->pdf_pos * cos_in);
                else if (infinite)
                    nee_over_emit = infinite_pdf_li(light, p, -les->ray.d) /
                                    (les->pdf_pos * les->pdf_dir * cos_in);
                else if (const auto* area = std::get_if<DiffuseAreaLight>(&light))
                    nee_over_emit =
                        area->pdf_li_point(LightSampleContext{p, scattered ? Vec3(0, 0, 0) : hit.p_error, ng},
                                           les->p, les->n) *
                        cos0 / (les->pdf_pos * les->pdf_dir * cos_in);
                dvcm = mis(nee_over_emit);
                dvc = dvc0 / mis(cos_in);
                dvm = dvc * m_vc_factor;
            } else {
                const Float d2 = length_squared(p - prev);
                dvcm *= mis(d2) / mis(cos_in);
                dvc /= mis(cos_in);
                dvm /= mis(cos_in);
            }
            // Medium vertices are stored too (connectible), but never merged.
            const bool stored = scattered || bsdf->has_non_specular();
            // The camera connection's numbers, drawn whether or not it is made.
            const Point2 u_cam = m_connect ? sampler.get_2d() : Point2(0.5f, 0.5f);
            if (stored) {
                LightVertex& v = out[count++];
                v.p = p;
                v.p_error = scattered ? Vec3(0, 0, 0) : hit.p_error;
                v.ng = ng;
                v.wo = wo;
                v.beta = beta;
                v.dvcm = dvcm;
                v.dvc = dvc;
                v.dvm = dvm;
                v.length = uint8_t(length);
                v.terminated = lambda.secondary_terminated();
                v.in_medium = scattered;
                v.g = g;
                if (scattered) {
                    v.medium_in = v.medium_out = medium;
                } else {
                    v.medium_in = medium_after(m_scene, hit, -hit.ng, medium);
                    v.medium_out = medium_after(m_scene, hit, hit.ng, medium);
                    v.bsdf = *bsdf;
                }
                if (m_connect) connect_to_camera(v, u_cam, lambda, counters, splats, nonfinite);
            }
            if (length >= max_depth) break;
            const Float uc = sampler.get_1d();
            const Point2 u = sampler.get_2d();
            prev = p;
            if (scattered) {
                // The phase function is sampled exactly: beta is unchanged, and the reverse
                // density is the same value (it is symmetric).
                const PhaseSample ps = sample_hg(wo, g, u);
                if (!(ps.p > 0)) break;
                update_mis(ps.p, ps.p, 1, false, false, dvcm, dvc, dvm);
                ray = Ray{p, ps.wi, kInfinity};
                continue;
            }
            auto bs = bsdf->sample(hit.wo, uc, u, TransportMode::Importance);
            if (!bs) break;
            const Float cos_out = absdot(hit.ng, bs->wi);
            beta *= bs->f * (absdot(bs->wi, bsdf->frame().n) / bs->pdf_sa);
            if (beta.is_zero() || beta.has_nonfinite()) break;
            update_mis(bs->pdf_sa, bsdf->pdf(bs->wi, hit.wo, TransportMode::Radiance), cos_out,
                       bs->is_specular(), true, dvcm, dvc, dvm);
            medium = medium_after(m_scene, hit, bs->wi, medium);
            ray = spawn_ray(hit, bs->wi);
        }
    }

    /// The camera path of one pixel sample: its estimate (s = 0, s = 1, connections to
    /// `light` (its own light path's vertices), merges with the grid's vertices).
    SampledSpectrum camera_path(const Ray& camera_ray, Sampler& sampler, PathCounters& counters,
                                const LightVertex* light, int n_light,
                                const std::vector<LightVertex>& all, const VertexGrid& grid,
                                SampledWavelengths& lambda_out) const {
        SampledWavelengths lambda = m_lambda;
        SampledSpectrum L(0), L_term(0);  // with the full / the terminated wavelengths
        auto add = [&](const SampledSpectrum& c, bool other_terminated) {
            if (other_terminated || lambda.secondary_terminated())
                L_term += c;
            else
                L += c;
        };
        auto finish = [&] {
            // Contributions with the terminated wavelengths carry the hero alone, whose pdf
            // terminate_secondary() divided by their count (the others' pdfs are zero):
            // expressed at the full wavelengths, the hero's value times that count.
            lambda_out = m_lambda;
            SampledSpectrum out = L;
            out[0] += L_term[0] * Float(kSpectrumSamples);
            return out;
        };
        Float pdf_pos = 0, pdf_dir = 0;
        m_scene.camera->pdf_we(camera_ray, pdf_pos, pdf_dir);
        if (!(pdf_dir > 0)) return finish();
        SampledSpectrum beta(1);
        // Eq. 31 with the light paths' count: a connection of a light path to the camera
        // (t = 1) is a strategy of N samples whose density per pixel is the full film's
        // pixel count times pdf_we's.
        Float dvcm = mis(1 / (m_lt_factor * pdf_dir)), dvc = 0, dvm = 0;
        const Float r2 = m_radius * m_radius;
        const int max_depth = m_ctx.max_depth;
        Ray ray = camera_ray;
        Point3 prev = camera_ray.o;
        LightSampleContext prev_ctx{camera_ray.o, {0, 0, 0}, {0, 0, 0}};
        int length = 0, crossings = 0;
        int medium = m_scene.camera_medium;
        while (true) {
            SurfaceHit hit;
            std::optional<Bsdf> bsdf;
            Point3 p_scatter;
            Float g = 0;
            const Next next = next_vertex(ray, medium, crossings, hit, bsdf, p_scatter, g, sampler,
                                          lambda, beta, counters);
            if (next == Next::End) break;
            const bool scattered = next == Next::Medium;
            if (next == Next::Escaped) {
                for (int li : m_scene.infinite_lights) {
                    const Light& l = m_scene.lights[size_t(li)];
                    Float pdf_sa = 0;
                    const SampledSpectrum le = infinite_le(l, ray, lambda, &pdf_sa, false);
                    if (le.is_zero()) continue;
                    Float w = 1;
                    if (length > 0) {
                        const Float pmf = m_scene.light_sampler.pmf(li);
                        Float ppos = 0, pdir = 0;
                        pdf_le(l, ray.o, Normal3(0, 0, 0), -ray.d, ppos, pdir);
                        const Float wc = m_vc * mis(pmf * pdf_sa) * dvcm + mis(pmf * ppos * pdir) * dvc;
                        w = 1 / (1 + wc);
                    }
                    add(beta * le * w, false);
                }
                break;
            }
            ++length;
            CameraVertex cv;
            if (scattered) {
                cv.p = p_scatter;
                cv.p_error = Vec3(0, 0, 0);
                cv.ng = Normal3(0, 0, 0);
                cv.wo = -normalize(ray.d);
                cv.medium_in = cv.medium_out = medium;
                cv.sc = Scatter{nullptr, g};
            } else {
                cv.p = hit.p;
                cv.p_error = hit.p_error;
                cv.ng = hit.ng;
                cv.wo = hit.wo;
                if (m_media) {
                    cv.medium_in = medium_after(m_scene, hit, -hit.ng, medium);
                    cv.medium_out = medium_after(m_scene, hit, hit.ng, medium);
                }
                cv.sc = Scatter{&*bsdf, 0};
            }
            const Float cos_in = scattered ? 1 : absdot(hit.ng, hit.wo);
            if (!(cos_in > 0)) break;
            const Float d2 = length_squared(cv.p - prev);
            dvcm *= mis(d2) / mis(cos_in);
            dvc /= mis(cos_in);
            dvm /= mis(cos_in);

            // s = 0: an emitter found by the camera path.
            if (!scattered && hit.light >= 0) {
                const Light& l = m_scene.lights[size_t(hit.light)];
                const SampledSpectrum le = light_emitted(l, hit.p, hit.ng, hit.wo, lambda);
                if (!le.is_zero()) {
                    Float w = 1;
                    if (length > 1) {
                        const Float pmf = m_scene.light_sampler.pmf(hit.light);
                        Float ppos = 0, pdir = 0;
                        pdf_le(l, hit.p, hit.ng, hit.wo, ppos, pdir);
                        Float nee_sa = 0;
                        if (const auto* area = std::get_if<DiffuseAreaLight>(&l))
                            nee_sa = area->pdf_li_point(prev_ctx, hit.p, hit.ng);
                        const Float direct_a = pmf * nee_sa * cos_in / d2;
                        const Float wc = m_vc * mis(direct_a) * dvcm + mis(pmf * ppos * pdir) * dvc;
                        w = 1 / (1 + wc);
                    }
                    add(beta * le * w, false);
                }
            }
            if (length > max_depth) break;

            // Medium vertices connect (light samples, connections) but do not merge.
            const bool non_specular = scattered || bsdf->has_non_specular();
            const Float ul = sampler.get_1d();
            const Point2 u_light = sampler.get_2d();
            if (non_specular && m_connect) {
                // s = 1: a light sample.
                if (length < max_depth + 1)
                    add(sample_light(cv, beta, dvcm, dvc, ul, u_light, lambda, counters), false);
                // Vertex connection with this pixel's light path.
                for (int j = 0; j < n_light; ++j) {
                    const LightVertex& v = light[j];
                    if (int(v.length) + length > max_depth) continue;
                    const SampledSpectrum c = connect(cv, beta, dvcm, dvc, v, lambda, counters);
                    if (!c.is_zero()) add(c, v.terminated);
                }
            }
            if (!scattered && non_specular && m_merge) {
                // Vertex merging with every (surface) light vertex within the radius.
                SampledSpectrum sum(0), sum_term(0);
                grid.query(hit.p, m_radius, [&](uint32_t i) {
                    const LightVertex& v = all[i];
                    if (int(v.length) + length > max_depth + 1) return;
                    if (length_squared(v.p - hit.p) > r2) return;
                    const Bsdf::Eval e = bsdf->evaluate(hit.wo, v.wo);
                    if (e.f.is_zero()) return;
                    const Float rev = bsdf->pdf(v.wo, hit.wo, TransportMode::Importance);
                    // Eqs. 38-39.
                    const Float wl = m_vc * v.dvcm * m_vc_factor + v.dvm * mis(e.pdf_sa);
                    const Float wc = m_vc * dvcm * m_vc_factor + dvm * mis(rev);
                    const SampledSpectrum c = e.f * v.beta * (1 / (1 + wl + wc));
                    if (v.terminated)
                        sum_term += c;
                    else
                        sum += c;
                });
                if (!sum.is_zero()) add(beta * sum * m_merge_norm, false);
                if (!sum_term.is_zero()) add(beta * sum_term * m_merge_norm, true);
            }

            // Extend the path.
            const Float uc = sampler.get_1d();
            const Point2 u = sampler.get_2d();
            if (length > max_depth) break;
            prev = cv.p;
            prev_ctx = LightSampleContext{cv.p, cv.p_error, cv.ng};
            if (scattered) {
                // Sampled exactly: beta is unchanged, the reverse density the same value.
                const PhaseSample ps = sample_hg(cv.wo, g, u);
                if (!(ps.p > 0)) break;
                update_mis(ps.p, ps.p, 1, false, false, dvcm, dvc, dvm);
                ray = Ray{cv.p, ps.wi, kInfinity};
                continue;
            }
            auto bs = bsdf->sample(hit.wo, uc, u, TransportMode::Radiance);
            if (!bs) break;
            const Float cos_out = absdot(hit.ng, bs->wi);
            beta *= bs->f * (absdot(bs->wi, bsdf->frame().n) / bs->pdf_sa);
            if (beta.is_zero() || beta.has_nonfinite()) break;
            update_mis(bs->pdf_sa, bsdf->pdf(bs->wi, hit.wo, TransportMode::Importance), cos_out,
                       bs->is_specular(), true, dvcm, dvc, dvm);
            medium = medium_after(m_scene, hit, bs->wi, medium);
            ray = spawn_ray(hit, bs->wi);
        }
        return finish();
    }

private:
    /// Eqs. 34-36 of the report (SmallVCM's SampleScattering): the MIS quantities after a
    /// vertex sampled its next direction with solid-angle density pdf_sa (rev: the density of
    /// the reverse direction, in the other subpath's transport mode; cos_out: the geometric
    /// cosine there, 1 in a medium). `mergeable`: whether the vertex is one at which paths
    /// are merged (a surface); a medium vertex is connectible but not merged, so the merging
    /// terms of the vertex itself (eta in dVC, 1 in dVM) are left out, as a specular vertex
    /// leaves out every term of its own.
    void update_mis(Float pdf_sa, Float rev, Float cos_out, bool specular, bool mergeable,
                    Float& dvcm, Float& dvc, Float& dvm) const {
        if (specular) {
            // The densities of both directions are the lobe's probability: their ratio is 1.
            dvcm = 0;
            dvc *= mis(cos_out);
            dvm *= mis(cos_out);
            return;
        }
        const Float g = mis(cos_out / pdf_sa);
        dvc = g * (dvc * mis(rev) + m_vc * dvcm + (mergeable ? m_vm_factor : 0));
        dvm = g * (dvm * mis(rev) + m_vc * dvcm * m_vc_factor + (mergeable ? 1 : 0));
        dvcm = mis(1 / pdf_sa);
    }

    /// Where a walk's next vertex lies: none (absorbed in a medium, or too many interfaces),
    /// none because the ray leaves the scene, a scattering in a medium, or a surface.
    enum class Next { End, Escaped, Medium, Surface };

    /// Follows `ray` (in `medium`) to the walk's next vertex, passing through interfaces
    /// (surfaces without a material; `medium` and `crossings` updated): in a medium, delta
    /// tracking may end the walk or scatter at p_scatter (asymmetry g) before the next
    /// surface; else `hit` is that surface and `bsdf` its BSDF. Both walks (light and camera)
    /// step with it.
    Next next_vertex(Ray& ray, int& medium, int& crossings, SurfaceHit& hit,
                     std::optional<Bsdf>& bsdf, Point3& p_scatter, Float& g, Sampler& sampler,
                     SampledWavelengths& lambda, SampledSpectrum& beta,
                     PathCounters& counters) const {
        while (true) {
            hit = SurfaceHit{};
            ++counters.rays;
            const bool found = m_scene.intersect(ray, hit);
            if (medium >= 0) {
                const FreeFlight fl = fly(ray, medium, found ? hit.t : kInfinity, sampler, lambda,
                                          beta, p_scatter, g);
                if (fl == FreeFlight::Absorbed) return Next::End;
                if (fl == FreeFlight::Scattered) return Next::Medium;
            }
            if (!found) return Next::Escaped;
            if (hit.material >= 0)
                bsdf = make_bsdf(m_scene.materials[size_t(hit.material)], m_mctx, hit, lambda);
            if (bsdf) return Next::Surface;
            if (++crossings > 256) return Next::End;
            medium = medium_after(m_scene, hit, ray.d, medium);
            ray = spawn_ray(hit, ray.d);
        }
    }

    /// A free flight along `ray` (in `medium`) up to t_max (medium_transport.h's
    /// free_flight), with two sampler dimensions: the first flight and the key of the stream
    /// of the rest.
    FreeFlight fly(const Ray& ray, int medium, Float t_max, Sampler& sampler,
                   const SampledWavelengths& lambda, SampledSpectrum& beta, Point3& p,
                   Float& g) const {
        const Float u = sampler.get_1d();
        const Float uk = sampler.get_1d();
        return free_flight(m_scene, medium, ray, t_max, u, uk, lambda, beta, p, g);
    }

    /// The transmittance along a shadow ray starting in `medium` (pbrt-v4's Integrator::Tr
    /// by ratio tracking, as bdpt's connections): zero if a surface with a material blocks
    /// it. Without media, visibility alone.
    SampledSpectrum transmittance(const Ray& ray, int medium, bool to_point,
                                  const SampledWavelengths& lambda, PathCounters& counters) const {
        if (!m_media) {
            ++counters.rays;
            return SampledSpectrum(m_scene.occluded(ray) ? 0 : 1);
        }
        SampledSpectrum r_l(1), r_u(1);
        const SampledSpectrum t = shadow_transmittance(m_scene, ray, medium, to_point, lambda, r_l,
                                                       r_u, m_tr_key, counters);
        if (t.is_zero()) return t;
        const SampledSpectrum w = t / r_l.average();
        return w.has_nonfinite() ? SampledSpectrum(0) : w;
    }

    /// The transmittance between points a (in medium_a towards b) and b.
    SampledSpectrum tr(Point3 a, Vec3 a_err, Normal3 a_n, int medium_a, Point3 b, Vec3 b_err,
                       Normal3 b_n, const SampledWavelengths& lambda, PathCounters& counters) const {
        const Point3 o = offset_ray_origin(a, a_err, a_n, b - a);
        const Point3 t = offset_ray_origin(b, b_err, b_n, o - b);
        return transmittance(Ray{o, t - o, 1 - Float(1e-4)}, medium_a, true, lambda, counters);
    }

    static Scatter scatter_of(const LightVertex& v) {
        return v.in_medium ? Scatter{nullptr, v.g} : Scatter{&v.bsdf, 0};
    }

    /// t = 1: light vertex v connected to the camera (eq. 44 and SmallVCM's
    /// ConnectToCamera), its splat appended to `splats`.
    void connect_to_camera(const LightVertex& v, Point2 u, const SampledWavelengths& lambda,
                           PathCounters& counters, std::vector<Splat>& splats,
                           uint64_t& nonfinite) const {
        auto cs = m_scene.camera->sample_wi(v.p, u);
        if (!cs || !(cs->pdf > 0) || !m_ctx.inside(cs->p_raster)) return;
        const Scatter sc = scatter_of(v);
        const SampledSpectrum f = sc.f(v.wo, cs->wi, TransportMode::Importance);
        if (f.is_zero()) return;
        SampledSpectrum c = v.beta * f * (sc.cos_shading(cs->wi) * cs->we / cs->pdf * m_lt_factor);
        if (c.is_zero()) return;
        Float cam_pos = 0, cam_dir = 0;
        m_scene.camera->pdf_we(Ray{cs->p_lens, -cs->wi, kInfinity}, cam_pos, cam_dir);
        const Float d2 = length_squared(cs->p_lens - v.p);
        // The density (per pixel, area at v) of a camera path reaching v, over N.
        const Float cam_a = m_lt_factor * cam_dir * cos_geom(v.ng, cs->wi) / d2;
        const Float rev = sc.pdf(cs->wi, v.wo, TransportMode::Radiance);
        const Float vm = v.in_medium ? 0 : m_vm_factor;  // merging at v
        const Float wl = mis(cam_a) * (vm + v.dvcm + v.dvc * mis(rev));
        c *= 1 / (1 + wl);
        c *= tr(v.p, v.p_error, v.ng, medium_towards(v.ng, v.medium_in, v.medium_out, cs->wi),
                cs->p_lens, {0, 0, 0}, cs->n_lens, lambda, counters);
        if (c.is_zero()) return;
        SampledWavelengths lw = lambda;
        if (v.terminated) lw.terminate_secondary();
        std::array<double, 3> xyz{0, 0, 0};
        bool finite = !c.has_nonfinite();
        if (finite) {
            xyz = m_film.to_sensor(c, lw);
            finite = finite3(xyz);
        }
        if (!finite) {
            ++nonfinite;
            return;
        }
        if (xyz[0] == 0 && xyz[1] == 0 && xyz[2] == 0) return;
        splats.push_back({cs->p_raster, xyz});
    }

    /// s = 1 (eqs. 40-41, SmallVCM's DirectIllumination).
    SampledSpectrum sample_light(const CameraVertex& cv, const SampledSpectrum& beta, Float dvcm,
                                 Float dvc, Float ul, Point2 u, const SampledWavelengths& lambda,
                                 PathCounters& counters) const {
        if (m_scene.light_sampler.empty()) return SampledSpectrum(0);
        Float pmf = 0;
        const int li = m_scene.light_sampler.sample(ul, pmf);
        if (li < 0 || !(pmf > 0)) return SampledSpectrum(0);
        const Light& light = m_scene.lights[size_t(li)];
        auto ls = sample_li(light, LightSampleContext{cv.p, cv.p_error, cv.ng}, u, lambda, false);
        if (!ls || ls->L.is_zero() || !(ls->pdf_sa > 0)) return SampledSpectrum(0);
        const Bsdf::Eval e = cv.sc.evaluate(cv.wo, ls->wi);
        if (e.f.is_zero()) return SampledSpectrum(0);
        const Float cos_shading = cv.sc.cos_shading(ls->wi);
        SampledSpectrum c = beta * e.f * ls->L * (cos_shading / (pmf * ls->pdf_sa));
        if (c.is_zero()) return c;
        const bool delta_pos = light_delta_position(light), delta_dir = light_delta_direction(light);
        const Float cos_x = cos_geom(cv.ng, ls->wi);
        // The density of the light path's emission making this segment, over the light
        // sample's (both at this vertex; the light's choice cancels).
        Float ppos = 0, pdir = 0;
        pdf_le(light, ls->p_light, ls->n_light, -ls->wi, ppos, pdir);
        Float emit_over_nee = 0;
        if (delta_pos) {
            emit_over_nee = pdir * cos_x / length_squared(ls->p_light - cv.p);
        } else if (delta_dir) {
            emit_over_nee = ppos * cos_x;
        } else if (ls->at_infinity) {
            emit_over_nee = ppos * pdir * cos_x / ls->pdf_sa;
        } else {
            const Float cos_l = absdot(ls->n_light, ls->wi);
            emit_over_nee = cos_l > 0 ? ppos * pdir * cos_x / (ls->pdf_sa * cos_l) : 0;
        }
        const Float bsdf_dir = delta_pos || delta_dir ? 0 : e.pdf_sa;
        const Float rev = cv.sc.pdf(ls->wi, cv.wo, TransportMode::Importance);
        const Float vm = cv.sc.bsdf ? m_vm_factor : 0;  // merging at this vertex
        const Float wl = mis(bsdf_dir / (pmf * ls->pdf_sa));
        const Float wc = mis(emit_over_nee) * (vm + dvcm + dvc * mis(rev));
        c *= 1 / (1 + wl + wc);
        const int medium = medium_towards(cv.ng, cv.medium_in, cv.medium_out, ls->wi);
        if (ls->at_infinity) {
            const Point3 o = offset_ray_origin(cv.p, cv.p_error, cv.ng, ls->wi);
            return c * transmittance(Ray{o, ls->wi, kInfinity}, medium, false, lambda, counters);
        }
        return c * tr(cv.p, cv.p_error, cv.ng, medium, ls->p_light, ls->p_error, ls->n_light, lambda,
                      counters);
    }

    /// Vertex connection (eqs. 42-43, SmallVCM's ConnectVertices).
    SampledSpectrum connect(const CameraVertex& cv, const SampledSpectrum& beta, Float dvcm,
                            Float dvc, const LightVertex& v, const SampledWavelengths& lambda,
                            PathCounters& counters) const {
        Vec3 d = v.p - cv.p;
        const Float d2 = length_squared(d);
        if (!(d2 > 0)) return SampledSpectrum(0);
        d = d / std::sqrt(d2);
        const Bsdf::Eval ec = cv.sc.evaluate(cv.wo, d);
        if (ec.f.is_zero()) return SampledSpectrum(0);
        const Scatter vs = scatter_of(v);
        const SampledSpectrum fl = vs.f(v.wo, -d, TransportMode::Importance);
        if (fl.is_zero()) return SampledSpectrum(0);
        const Float g = cv.sc.cos_shading(d) * vs.cos_shading(d) / d2;
        SampledSpectrum c = beta * ec.f * fl * v.beta * g;
        if (c.is_zero()) return c;
        const Float cam_rev = cv.sc.pdf(d, cv.wo, TransportMode::Importance);
        const Float light_dir = vs.pdf(v.wo, -d, TransportMode::Importance);
        const Float light_rev = vs.pdf(-d, v.wo, TransportMode::Radiance);
        const Float cam_dir_a = ec.pdf_sa * cos_geom(v.ng, d) / d2;
        const Float light_dir_a = light_dir * cos_geom(cv.ng, d) / d2;
        // Merging at either end of the connection, where it is a surface.
        const Float vm_light = v.in_medium ? 0 : m_vm_factor, vm_cam = cv.sc.bsdf ? m_vm_factor : 0;
        const Float wl = mis(cam_dir_a) * (vm_light + v.dvcm + v.dvc * mis(light_rev));
        const Float wc = mis(light_dir_a) * (vm_cam + dvcm + dvc * mis(cam_rev));
        c *= 1 / (1 + wl + wc);
        return c * tr(cv.p, cv.p_error, cv.ng, medium_towards(cv.ng, cv.medium_in, cv.medium_out, d),
                      v.p, v.p_error, v.ng, lambda, counters);
    }
    const Scene& m_scene;
    const Film& m_film;
    const BidirContext& m_ctx;
    const MaterialContext m_mctx;
    bool m_connect, m_merge;
    Float m_radius = 1;
    int64_t m_n_light = 1;
    Float m_lt_factor = 1;
    SampledWavelengths m_lambda;
    Float m_vm_factor = 0, m_vc_factor = 0, m_vc = 1, m_merge_norm = 0;
    const bool m_media;  ///< the scene has media: connections track transmittance
    uint64_t m_tr_key = 0;  ///< keys the ratio-tracking streams of an iteration's connections
};

/// Rotates the iterations' wavelengths (pass_wavelength_sample) apart from the other
/// iterative integrators'.
constexpr uint64_t kWavelengthSalt = 0x56434d5f4c414d42ULL;

/// Film rows per item of a distributed camera pass.
constexpr int kBandRows = 4;

/// One camera sample's result: sensor values and filter weight (film.add's arguments).
struct PixelSample {
    std::array<double, 3> xyz{0, 0, 0};
    Float weight = 0;
};

/// What an iteration needs, shared by the single process, the coordinator and the workers of
/// a distributed render (each process traces every light path of an iteration itself: the
/// merging grid needs all of them, and they are pure functions of (iteration, path, seed)).
class VcmRun {
public:
    VcmRun(const Scene& scene, const Film& film, uint64_t seed, int iterations, int threads)
        : m_scene(scene), m_film(film), m_fp(film.params()), m_iterations(iterations),
          m_threads(threads), m_arena(threads), m_ctx(scene),
          m_vcm(scene, film, m_ctx, scene.integrator.vcm.connect, scene.integrator.vcm.merge) {
        const VcmParams& vp = scene.integrator.vcm;
        w = m_fp.width(), h = m_fp.height();
        n_pixels = int64_t(w) * int64_t(h);
        stride = std::max(1, scene.integrator.max_depth);
        n_light = vp.light_paths > 0 ? int64_t(vp.light_paths) : n_pixels;
        if (double(n_light) * stride * sizeof(LightVertex) > kMaxVertexBytes || n_light > INT32_MAX)
            throw Error(fmt::format("Integrator \"vcm\": the light vertices of one iteration ({} "
                                    "light paths of up to {} vertices, {} bytes each) would take "
                                    "more than {} GiB; lower \"lightpathsperiteration\" (or the "
                                    "resolution) or \"maxdepth\"",
                                    n_light, stride, sizeof(LightVertex),
                                    kMaxVertexBytes / double(1 << 30)));
        cam_seed = scene.sampler.seed + seed;
        const uint64_t light_seed = uint64_t(int64_t(vp.seed)) + seed;
        // The initial radius: the scene's, or SmallVCM's default of 0.003 times the radius
        // of the scene's bounding sphere.
        r1 = vp.radius;
        if (!(r1 > 0)) r1 = Float(0.003 * 0.5 * double(length(scene.bounds.hi - scene.bounds.lo)));
        if (!(r1 > 0) || !std::isfinite(r1)) r1 = 1e-3f;
        std::shared_ptr<Sampler> cam_proto(
            scene.sampler.type == "stratified"
                ? make_stratified_sampler(scene.sampler.x_samples, scene.sampler.y_samples,
                                          scene.sampler.jitter, cam_seed)
                : make_sampler(scene.sampler.type, iterations, m_fp.resolution, cam_seed));
        // Light path k of iteration i: sample k of the pseudo-pixel (i, -1) (camera pixels
        // have y >= 0) of an Owen-scrambled Sobol sampler with N samples per pixel.
        auto light_proto = std::make_shared<PaddedSobolSampler>(int(n_light), light_seed);
        states = std::make_unique<tbb::enumerable_thread_specific<ThreadState>>([cam_proto, light_proto] {
            ThreadState t;
            t.cam_sampler = cam_proto->clone();
            t.light_sampler = light_proto->clone();
            return t;
        });
        vertices.resize(size_t(n_light) * size_t(stride));
        counts.assign(size_t(n_light), 0);
    }

    tbb::task_arena& arena() { return m_arena; }

    /// Starts iteration `iter` (from 0): its radius, wavelengths and the estimator's settings.
    void start(int iter) {
        m_iter = iter;
        // r_i = r_1 i^((alpha - 1) / 2), i from 1 (Knaus and Zwicker 2011; Georgiev et al.
        // 2012, sec. 5).
        radius = Float(double(r1) *
                       std::pow(double(iter + 1), (double(m_scene.integrator.vcm.alpha) - 1) / 2));
        lambda = m_film.sample_wavelengths(
            pass_wavelength_sample(uint64_t(iter), cam_seed, kWavelengthSalt));
        m_vcm.start_iteration(radius, n_light, lambda);
    }

    /// The light pass, in slabs of chunks whose splats are given to `splat` (sensor values at
    /// a film position) in chunk order, then the grid of the stored surface vertices.
    template <typename SplatFn>
    void light_pass(Progress* progress, uint64_t& nonfinite, SplatFn&& splat) {
        const int64_t n_chunks = (n_light + kLightChunk - 1) / kLightChunk;
        const int64_t slab = std::max<int64_t>(16, 8 * m_threads);
        chunk_splats.resize(static_cast<size_t>(slab));
        chunk_nonfinite.assign(static_cast<size_t>(slab), 0);
        const int iter = m_iter;
        for (int64_t c0 = 0; c0 < n_chunks; c0 += slab) {
            const int64_t c1 = std::min(n_chunks, c0 + slab);
            m_arena.execute([&] {
                tbb::parallel_for(
                    tbb::blocked_range<int64_t>(c0, c1, 1),
                    [&](const tbb::blocked_range<int64_t>& r) {
                        ThreadState& ts = states->local();
                        for (int64_t c = r.begin(); c < r.end(); ++c) {
                            std::vector<Splat>& out = chunk_splats[size_t(c - c0)];
                            uint64_t& bad = chunk_nonfinite[size_t(c - c0)];
                            out.clear();
                            bad = 0;
                            const int64_t k0 = c * kLightChunk;
                            const int64_t k1 = std::min(n_light, k0 + kLightChunk);
                            for (int64_t k = k0; k < k1; ++k) {
                                ts.light_sampler->start_pixel_sample(Vec2i(iter, -1), int(k));
                                m_vcm.light_path(*ts.light_sampler, ts.counters,
                                                 vertices.data() + size_t(k) * size_t(stride),
                                                 counts[size_t(k)], out, bad);
                            }
                            if (progress) progress->add(uint64_t(k1 - k0));
                        }
                    },
                    tbb::simple_partitioner());
            });
            for (int64_t c = c0; c < c1; ++c) {
                nonfinite += chunk_nonfinite[size_t(c - c0)];
                for (const Splat& s : chunk_splats[size_t(c - c0)]) splat(s);
            }
        }
        // The light vertices' grid.
        stored.clear();
        if (m_scene.integrator.vcm.merge)
            for (int64_t k = 0; k < n_light; ++k)
                for (int j = 0; j < counts[size_t(k)]; ++j) {
                    const size_t i = size_t(k) * size_t(stride) + size_t(j);
                    if (!vertices[i].in_medium) stored.push_back(uint32_t(i));  // surfaces only
                }
        grid.build(vertices, stored, radius);
    }

    /// The camera sample of the crop window's pixel (xx, yy) in the current iteration.
    PixelSample camera_sample(ThreadState& ts, int xx, int yy) const {
        const Filter& filter = *m_scene.filter;
        Sampler& sampler = *ts.cam_sampler;
        const Vec2i pixel(m_fp.x0 + xx, m_fp.y0 + yy);
        // The light path this camera path connects to.
        const size_t k = (size_t(yy) * size_t(w) + size_t(xx)) % size_t(n_light);
        sampler.start_pixel_sample(pixel, m_iter);
        const FilterSample fs = filter.sample(sampler.get_pixel_2d());
        const Point2 u_lens = sampler.get_2d();
        const Point2 p_film(Float(pixel.x) + 0.5f + fs.offset.x, Float(pixel.y) + 0.5f + fs.offset.y);
        const Ray ray = m_scene.camera->generate_ray(
            p_film, m_scene.camera->uses_lens_sample() ? u_lens : Point2(0.5f, 0.5f));
        SampledWavelengths lw = lambda;
        const SampledSpectrum L = m_vcm.camera_path(ray, sampler, ts.counters,
                                                    vertices.data() + k * size_t(stride),
                                                    counts[k], vertices, grid, lw);
        PixelSample out;
        out.weight = fs.weight;
        bool finite = !L.has_nonfinite();
        if (finite) {
            out.xyz = m_film.to_sensor(L, lw);
            finite = finite3(out.xyz);
        }
        if (!finite) {
            ++ts.nonfinite;
            out.xyz = {0, 0, 0};
        }
        return out;
    }

    int iterations() const { return m_iterations; }

    int w = 0, h = 0;
    int64_t n_pixels = 0, n_light = 0;
    int stride = 1;
    uint64_t cam_seed = 0;
    Float r1 = 1e-3f, radius = 1e-3f;
    SampledWavelengths lambda;
    std::unique_ptr<tbb::enumerable_thread_specific<ThreadState>> states;

private:
    const Scene& m_scene;
    const Film& m_film;
    const FilmParams& m_fp;
    int m_iterations;
    int m_threads;
    tbb::task_arena m_arena;
    BidirContext m_ctx;
    Vcm m_vcm;
    int m_iter = 0;
    std::vector<LightVertex> vertices;
    std::vector<uint8_t> counts;
    std::vector<uint32_t> stored;
    VertexGrid grid;
    std::vector<std::vector<Splat>> chunk_splats;
    std::vector<uint64_t> chunk_nonfinite;
};

/// The header of a distributed camera pass: the render's seed and iteration count, and the
/// iteration.
struct BandHeader {
    uint64_t seed;
    int32_t iterations, iter;
};

}  // namespace

RenderStats render_vcm(const Scene& scene, Film& film, const RenderOptions& opt) {
    const char* kName = "Integrator \"vcm\"";
    check_bidir_scene(scene, "vcm");
    if (film.has_aux()) throw Error(fmt::format("{}: only the \"rgb\" film is supported yet", kName));
    if (opt.checkpoint || opt.resume)
        throw Error(fmt::format("{}: checkpoints are not supported yet", kName));
    WorkCoordinator* const coord =
        opt.distribute && opt.distribute->workers() > 0 ? opt.distribute : nullptr;
    const int iterations = render_samples_per_pixel(scene, opt);
    const int threads = opt.threads > 0 ? opt.threads : int(std::thread::hardware_concurrency());
    tbb::global_control gc(tbb::global_control::max_allowed_parallelism, size_t(threads));
    VcmRun run(scene, film, opt.seed, iterations, threads);
    tbb::task_arena& arena = run.arena();
    const FilmParams& fp = film.params();
    const int w = run.w, h = run.h;

    std::vector<PixelSum> sums = film.make_buffer();
    std::vector<double> splat_sums = film.splat_buffer();
    uint64_t nonfinite = 0, remote_rays = 0, remote_nonfinite = 0;

    RenderStats stats;
    const auto t0 = Clock::now();
    const double cpu0 = process_cpu_seconds();
    auto elapsed = [&] { return std::chrono::duration<double>(Clock::now() - t0).count(); };
    Progress progress(opt.progress, uint64_t(iterations) * uint64_t(run.n_light + run.n_pixels));
    const Filter& filter = *scene.filter;
    auto camera_rows = [&](int y0, int y1) {
        ThreadState& ts = run.states->local();
        for (int yy = y0; yy < y1; ++yy)
            for (int xx = 0; xx < w; ++xx) {
                const PixelSample ps = run.camera_sample(ts, xx, yy);
                film.add(sums, fp.x0 + xx, fp.y0 + yy, ps.xyz, ps.weight);
            }
        progress.add(uint64_t(y1 - y0) * uint64_t(w));
    };

    int done = 0;
    while (done < iterations) {
        const double iter_t0 = elapsed();
        const int iter = done;
        run.start(iter);
        // ---- light pass (every process traces it; this one adds the splats) ---------------
        run.light_pass(&progress, nonfinite,
                       [&](const Splat& s) { film.add_splat(splat_sums, s.p, s.xyz, filter); });
        // ---- camera pass -------------------------------------------------------------------
        if (!coord) {
            arena.execute([&] {
                tbb::parallel_for(tbb::blocked_range<int>(0, h, 1),
                                  [&](const tbb::blocked_range<int>& r) {
                                      camera_rows(r.begin(), r.end());
                                  });
            });
        } else {
            // Distributed: bands of rows are the items; a worker returns each pixel's
            // sensor values and filter weight, which are added here as this process adds its
            // own (a pixel has one sample an iteration: the order of pixels is immaterial).
            WorkCoordinator::Phase ph;
            ph.kind = kVcmItems;
            ByteWriter hw(ph.header);
            hw.put(BandHeader{opt.seed, int32_t(iterations), int32_t(iter)});
            ph.items = size_t((h + kBandRows - 1) / kBandRows);
            ph.input = [](size_t, ByteWriter&) {};
            ph.output = [&](size_t i, ByteReader& br) {
                const int y0 = int(i) * kBandRows, y1 = std::min(h, y0 + kBandRows);
                for (int yy = y0; yy < y1; ++yy)
                    for (int xx = 0; xx < w; ++xx) {
                        const auto xyz = br.get<std::array<double, 3>>();
                        const Float weight = br.get<Float>();
                        film.add(sums, fp.x0 + xx, fp.y0 + yy, xyz, weight);
                    }
                remote_rays += br.get<uint64_t>();
                remote_nonfinite += br.get<uint64_t>();
                progress.add(uint64_t(y1 - y0) * uint64_t(w));
            };
            ph.local = [&](const std::function<std::optional<size_t>()>& claim,
                           const std::function<void(size_t)>&) {
                run_local_share(arena, threads, claim, [] { return false; }, [&](size_t i) {
                    const int y0 = int(i) * kBandRows;
                    camera_rows(y0, std::min(h, y0 + kBandRows));
                });
            };
            ph.abandon = [] { return false; };  // an iteration always completes
            coord->run(ph);
        }
        ++done;

        if (stop_before_next_iteration(opt, done, iterations, elapsed(), elapsed() - iter_t0,
                                       stats))
            break;
    }
    progress.finish();

    film.set_sums(std::move(sums));
    film.set_splat_sums(std::move(splat_sums));
    film.set_splat_scale(1 / (double(done) * filter.integral()));

    stats.spp = done;
    stats.wall_seconds = elapsed();
    stats.cpu_seconds = process_cpu_seconds() - cpu0;
    stats.camera_paths = uint64_t(done) * uint64_t(run.n_pixels);
    stats.nonfinite = nonfinite + remote_nonfinite;
    stats.rays = remote_rays;
    for (const ThreadState& t : *run.states) {
        stats.rays += t.counters.rays;
        stats.nonfinite += t.nonfinite;
    }
    stats.peak_rss_bytes = peak_rss_bytes();
    return stats;
}

JobHandler vcm_job_handler(const Scene& scene, int threads) {
    // A worker's state, made on the first job of a render (seed and iteration count) and kept
    // while they stay: the iteration's light paths and grid, traced once per iteration.
    struct Worker {
        Film film;
        int threads;
        std::unique_ptr<VcmRun> run;
        BandHeader key{0, -1, -1};
        int iter = -1;
        Worker(const Scene& s, int n)
            : film(s.film), threads(n > 0 ? n : int(std::thread::hardware_concurrency())) {}
    };
    auto wk = std::make_shared<Worker>(scene, threads);
    return [&scene, wk](ByteReader& header, size_t count, ByteReader& inputs, ByteWriter& outputs) {
        Worker& W = *wk;
        const BandHeader hd = header.get<BandHeader>();
        if (scene.integrator.type != "vcm")
            throw Error(fmt::format("distributed: a vcm job, and the scene's integrator is \"{}\"",
                                    scene.integrator.type));
        if (hd.iterations <= 0 || hd.iter < 0 || hd.iter >= hd.iterations)
            throw Error(fmt::format("distributed: vcm iteration {} of {}", hd.iter, hd.iterations));
        if (!W.run || W.key.seed != hd.seed || W.key.iterations != hd.iterations) {
            W.run = std::make_unique<VcmRun>(scene, W.film, hd.seed, hd.iterations, W.threads);
            W.key = hd;
            W.iter = -1;
        }
        VcmRun& run = *W.run;
        if (W.iter != hd.iter) {
            run.start(hd.iter);
            uint64_t ignored = 0;
            run.light_pass(nullptr, ignored, [](const Splat&) {});
            W.iter = hd.iter;
        }
        std::vector<size_t> items(count);
        for (size_t j = 0; j < count; ++j) {
            const uint64_t item = inputs.get<uint64_t>();
            if (item >= uint64_t((run.h + kBandRows - 1) / kBandRows))
                throw Error("distributed: a vcm band outside the film");
            items[j] = size_t(item);
        }
        std::vector<std::vector<PixelSample>> out(count);
        std::vector<PathCounters> counters(count);
        std::vector<uint64_t> bad(count, 0);
        tbb::global_control gc(tbb::global_control::max_allowed_parallelism, size_t(W.threads));
        run.arena().execute([&] {
            tbb::parallel_for(size_t(0), count, [&](size_t j) {
                ThreadState& ts = run.states->local();
                const uint64_t rays0 = ts.counters.rays, bad0 = ts.nonfinite;
                const int y0 = int(items[j]) * kBandRows, y1 = std::min(run.h, y0 + kBandRows);
                for (int yy = y0; yy < y1; ++yy)
                    for (int xx = 0; xx < run.w; ++xx) out[j].push_back(run.camera_sample(ts, xx, yy));
                counters[j].rays = ts.counters.rays - rays0;
                bad[j] = ts.nonfinite - bad0;
            }, tbb::simple_partitioner());
        });
        for (size_t j = 0; j < count; ++j) {
            outputs.put(uint64_t(items[j]));
            for (const PixelSample& ps : out[j]) {
                outputs.put(ps.xyz);
                outputs.put(ps.weight);
            }
            outputs.put(uint64_t(counters[j].rays));
            outputs.put(bad[j]);
        }
    };
}

}  // namespace sr
