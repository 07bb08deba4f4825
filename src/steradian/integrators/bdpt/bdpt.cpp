#include "steradian/integrators/bdpt/bdpt.h"

#include <algorithm>

#include "steradian/core/error.h"
#include "steradian/integrators/path/medium_transport.h"
#include "steradian/media/medium.h"
#include "steradian/sampling/hash.h"
#include "steradian/scene/scene.h"

namespace sr {

namespace {

enum class VertexType : uint8_t { Camera, Light, Surface, Medium };

/// A subpath vertex (Veach 1997, sec. 10.2; pbrt's Vertex). pdf_fwd is the density (per
/// unit area at this vertex, per solid angle for a vertex at infinity) with which its own
/// subpath generated it; pdf_rev the density with which the other direction would have.
struct Vertex {
    VertexType type = VertexType::Surface;
    bool delta = false;     ///< a specular scattering: no other strategy can meet it
    bool infinite = false;  ///< a light vertex at infinity (escaped ray, infinite light)
    /// Light vertices: the light's index (-1: an escaped camera ray, all infinite lights);
    /// surfaces: the emitter's index (hit.light).
    int light = -1;
    SampledSpectrum beta{0};
    Point3 p;
    Vec3 p_error{0, 0, 0};
    Normal3 ng{0, 0, 0};  ///< zero for a point (pinhole, point light, escaped direction)
    Normal3 ns{0, 0, 0};
    Float pdf_fwd = 0, pdf_rev = 0;
    /// The media on the two sides (-1: vacuum): a surface's MediumInterface where it is a
    /// transition, else the medium the path was in, on both sides; a medium vertex's medium;
    /// the camera's; a light's (Scene::light_media). A path leaving the vertex in direction
    /// w is in medium_out if dot(w, ng) >= 0 (or the vertex is a point), else medium_in.
    int medium_in = -1, medium_out = -1;
    Float g = 0;  ///< medium vertices: the Henyey-Greenstein asymmetry of the phase function
    /// Surfaces: the hit (hit.wo: towards the previous vertex). Medium vertices: only hit.wo.
    SurfaceHit hit;
    std::optional<Bsdf> bsdf;

    bool on_surface() const { return ng.x != 0 || ng.y != 0 || ng.z != 0; }
    int medium_towards(Vec3 w) const {
        return on_surface() && dot(w, ng) < 0 ? medium_in : medium_out;
    }
};

Float remap0(Float f) { return f != 0 ? f : 1; }

}  // namespace

struct BdptScratch {
    std::vector<Vertex> camera, light;
    Vertex sampled;
};
void BdptScratchDeleter::operator()(BdptScratch* p) const { delete p; }
BdptScratchPtr make_bdpt_scratch() { return BdptScratchPtr(new BdptScratch); }

BidirContext::BidirContext(const Scene& s) : scene(s) {
    const FilmParams& fp = s.film;
    const Vec2 r = s.filter ? s.filter->radius() : Vec2(0.5f, 0.5f);
    // pbrt-v4's Film::SampleBounds: film positions of camera samples (pixel centres plus
    // filter offsets).
    bounds[0] = Float(fp.x0) + 0.5f - r.x;
    bounds[1] = Float(fp.y0) + 0.5f - r.y;
    bounds[2] = Float(fp.x1) - 0.5f + r.x;
    bounds[3] = Float(fp.y1) - 0.5f + r.y;
    crop_factor = Float(double(fp.resolution.x) * fp.resolution.y /
                        (double(fp.width()) * fp.height()));
    max_depth = s.integrator.max_depth;
    regularize = s.integrator.regularize;
    // The infinite lights' disk: the radius every one of them was built with.
    scene_center = Point3((s.bounds.lo.x + s.bounds.hi.x) / 2, (s.bounds.lo.y + s.bounds.hi.y) / 2,
                          (s.bounds.lo.z + s.bounds.hi.z) / 2);
    scene_radius = std::max(Float(1e-3f), length(s.bounds.hi - s.bounds.lo) / 2);
    for (const Light& l : s.lights) {
        if (const auto* d = std::get_if<DistantLight>(&l)) {
            scene_center = d->scene_center, scene_radius = d->scene_radius;
            break;
        }
        if (const auto* u = std::get_if<UniformInfiniteLight>(&l)) {
            scene_center = u->scene_center, scene_radius = u->scene_radius;
            break;
        }
        if (const auto* im = std::get_if<ImageInfiniteLight>(&l)) {
            scene_center = im->scene_center, scene_radius = im->scene_radius;
            break;
        }
    }
}

void check_bidir_scene(const Scene& scene, const char* integrator) {
    if (!scene.camera || !scene.camera->has_importance())
        throw Error(fmt::format("Integrator \"{}\": only the \"perspective\" camera is supported "
                                "(as in pbrt-v4)",
                                integrator));
    // Media are traced as pbrt-v4's bdpt traces them; but pbrt-v4's bdpt ignores a medium's
    // emission and a subsurface material's interior, which would leave a wrong image here.
    for (const Medium& m : scene.media)
        if (is_emissive(m))
            throw Error(fmt::format("Integrator \"{}\": emissive participating media are not "
                                    "supported by the bidirectional integrators (pbrt-v4's bdpt "
                                    "ignores their emission; use \"volpath\")",
                                    integrator));
    for (const Material& m : scene.materials)
        if (std::holds_alternative<SubsurfaceMaterial>(m))
            throw Error(fmt::format("Integrator \"{}\": subsurface materials are not supported "
                                    "by the bidirectional integrators (use \"volpath\")",
                                    integrator));
    for (const Light& l : scene.lights)
        if (!light_can_emit(l))
            throw Error(fmt::format("Integrator \"{}\": an \"infinite\" light with a \"portal\" "
                                    "cannot emit light paths yet",
                                    integrator));
}

namespace {

class Bidir {
public:
    Bidir(const BidirContext& ctx, SampledWavelengths& lambda, Sampler& sampler,
          PathCounters& counters)
        : m_ctx(ctx), m_scene(ctx.scene), m_lambda(lambda), m_sampler(&sampler),
          m_counters(counters), m_mctx(ctx.scene.material_context()),
          m_media(!ctx.scene.media.empty()),
          m_tr_key(m_media ? hash(lambda[0], lambda[1], lambda[2], lambda[3]) : 0) {}

    // ---- vertex queries ------------------------------------------------------------------

    bool is_light(const Vertex& v) const {
        return v.type == VertexType::Light || (v.type == VertexType::Surface && v.light >= 0);
    }
    bool is_delta_light(const Vertex& v) const {
        return v.type == VertexType::Light && v.light >= 0 &&
               (light_delta_position(m_scene.lights[size_t(v.light)]) ||
                light_delta_direction(m_scene.lights[size_t(v.light)]));
    }
    bool connectible(const Vertex& v) const {
        switch (v.type) {
            case VertexType::Camera:
            case VertexType::Medium: return true;
            case VertexType::Light:
                return v.light < 0 || !light_delta_direction(m_scene.lights[size_t(v.light)]);
            case VertexType::Surface: return v.bsdf && v.bsdf->has_non_specular();
        }
        return false;
    }

    /// BSDF (phase function at a medium vertex) of `v` from its own incoming direction
    /// towards `next` (no cosine).
    SampledSpectrum f(const Vertex& v, const Vertex& next, TransportMode mode) const {
        const Vec3 wi = next.p - v.p;
        if (length_squared(wi) == 0) return SampledSpectrum(0);
        if (v.type == VertexType::Medium)
            return SampledSpectrum(hg_phase(dot(v.hit.wo, normalize(wi)), v.g));
        if (!v.bsdf) return SampledSpectrum(0);
        return v.bsdf->f(v.hit.wo, normalize(wi), mode);
    }

    /// A solid-angle density at v of choosing `next`'s direction, as a density at `next`.
    Float convert_density(const Vertex& v, Float pdf, const Vertex& next) const {
        if (next.infinite) return pdf;
        const Vec3 w = next.p - v.p;
        const Float d2 = length_squared(w);
        if (d2 == 0) return 0;
        const Float inv = 1 / d2;
        if (next.on_surface()) pdf *= absdot(next.ng, w * std::sqrt(inv));
        return pdf * inv;
    }

    /// Specular chains. A vertex x_i that a non-specular vertex v generates gets an area
    /// density from its own segment's geometry (convert_density: cos_i / d^2). When x_i is
    /// specular, the path runs on deterministically through the chain x_i .. x_j to the next
    /// non-specular vertex z, and what the strategies really differ by is the density of z:
    /// v's solid-angle density times the chain's Jacobian dw_v / dA_z = G / cos_v, where the
    /// chain's generalized geometric term G is the same from either end (when v and z are in
    /// media of one refractive index). A strategy that samples the chain from v's side and
    /// one that samples it from z's side thus compare p_v / cos_v with p_z / cos_z, G
    /// cancelling; the end segments' conversions leave instead a factor G(v, x_i) / G(x_j, z)
    /// between them, which can be wrong by orders of magnitude (a caustic point close under
    /// a glass sphere lit by a distant light weighs the camera's strategy as if it sampled
    /// those paths far better than light tracing does). So both densities generated into a
    /// chain are converted with one common term, that of the chain unfolded into a straight
    /// line of its length L (G = cos_v cos_z / L^2, exact for a plane mirror): the factor
    /// returned here turns cos_i / d^2 into cos_z / L^2. v, first and z are indices of at(),
    /// the chain running from v through first (its neighbour) to z, in steps of one.
    template <class At>
    static double chain_factor(At&& at, int v, int first, int z) {
        const Vertex& V = at(v);
        const Vertex& Z = at(z);
        if (V.infinite || Z.infinite) return 1;
        const int step = z > v ? 1 : -1;
        double L = 0;
        for (int k = v; k != z; k += step) L += double(length(at(k + step).p - at(k).p));
        const Vertex& F = at(first);
        const Vec3 wf = F.p - V.p, wz = Z.p - at(z - step).p;
        const double d = double(length(wf)), dz = double(length(wz));
        if (!(L > 0 && d > 0 && dz > 0)) return 1;
        const double cos_f = F.on_surface() ? double(absdot(F.ng, wf)) / d : 1;
        const double cos_z = Z.on_surface() ? double(absdot(Z.ng, wz)) / dz : 1;
        if (!(cos_f > 0 && cos_z > 0)) return 1;
        const double r = (cos_z / (L * L)) / (cos_f / (d * d));
        return std::isfinite(r) ? r : 1;
    }
    /// Calls f(i, j) for each maximal run x_i .. x_j of specular vertices of the path
    /// x_0 .. x_{n-1} (at(k)), whose ends x_0 and x_{n-1} are not specular.
    template <class At, class F>
    static void for_each_chain(int n, At&& at, F&& f) {
        for (int k = 1; k < n - 1; ++k) {
            if (!at(k).delta) continue;
            int j = k;
            while (j + 1 < n - 1 && at(j + 1).delta) ++j;
            f(k, j);
            k = j;
        }
    }

    /// Density (at `next`) with which a light vertex v emits towards next.
    Float pdf_light(const Vertex& v, const Vertex& next) const {
        Vec3 w = next.p - v.p;
        const Float d2 = length_squared(w);
        if (d2 == 0) return 0;
        w = w / std::sqrt(d2);
        Float pdf;
        if (v.infinite) {
            pdf = 1 / (kPi * sqr(m_ctx.scene_radius));
        } else {
            Float pos, dir;
            pdf_le(m_scene.lights[size_t(v.light)], v.p, v.ng, w, pos, dir);
            pdf = dir / d2;
        }
        if (next.on_surface()) pdf *= absdot(next.ng, w);
        return pdf;
    }

    /// Sum over the infinite lights of the light sampler's probability times the density of
    /// the direction `towards_light` (pbrt's InfiniteLightDensity).
    Float infinite_density(Vec3 towards_light) const {
        Float pdf = 0;
        for (int li : m_scene.infinite_lights) {
            const Light& l = m_scene.lights[size_t(li)];
            Float p = 0;
            if (std::holds_alternative<UniformInfiniteLight>(l))
                p = uniform_sphere_pdf();
            else if (const auto* im = std::get_if<ImageInfiniteLight>(&l))
                p = im->pdf_li(LightSampleContext{m_ctx.scene_center, {0, 0, 0}, {0, 0, 0}},
                               towards_light, false);
            pdf += m_scene.light_sampler.pmf(li) * p;
        }
        return pdf;
    }

    /// Density of a light subpath starting at light vertex v (towards `next`): the light's
    /// choice times its position density (its direction density for infinite lights).
    Float pdf_light_origin(const Vertex& v, const Vertex& next) const {
        Vec3 w = next.p - v.p;
        if (length_squared(w) == 0) return 0;
        w = normalize(w);
        if (v.infinite) return infinite_density(-w);
        Float pos, dir;
        pdf_le(m_scene.lights[size_t(v.light)], v.p, v.ng, w, pos, dir);
        return m_scene.light_sampler.pmf(v.light) * pos;
    }

    /// Density (at `next`) of v sampling next, v having been reached from prev.
    Float pdf(const Vertex& v, const Vertex* prev, const Vertex& next) const {
        if (v.type == VertexType::Light) return pdf_light(v, next);
        Vec3 wn = next.p - v.p;
        if (length_squared(wn) == 0) return 0;
        wn = normalize(wn);
        Float p = 0;
        if (v.type == VertexType::Camera) {
            Float pos;
            m_scene.camera->pdf_we(Ray{v.p, wn, kInfinity}, pos, p);
        } else {
            if (!prev || (!v.bsdf && v.type != VertexType::Medium)) return 0;
            Vec3 wp = prev->p - v.p;
            if (length_squared(wp) == 0) return 0;
            // (The phase function is sampled exactly: its density is its value.)
            p = v.type == VertexType::Medium ? hg_phase(dot(normalize(wp), wn), v.g)
                                             : v.bsdf->pdf(normalize(wp), wn);
        }
        return convert_density(v, p, next);
    }

    /// Emitted radiance of light vertex or emitting surface v towards `to`.
    SampledSpectrum le(const Vertex& v, const Vertex& to) const {
        if (!is_light(v)) return SampledSpectrum(0);
        Vec3 w = to.p - v.p;
        if (length_squared(w) == 0) return SampledSpectrum(0);
        w = normalize(w);
        if (v.infinite) {
            SampledSpectrum L(0);
            const Ray r{to.p, -w, kInfinity};
            for (int li : m_scene.infinite_lights)
                L += infinite_le(m_scene.lights[size_t(li)], r, m_lambda);
            return L;
        }
        return light_emitted(m_scene.lights[size_t(v.light)], v.p, v.ng, w, m_lambda);
    }

    /// Whether nothing blocks the segment between a and b.
    bool unoccluded(const Vertex& a, const Vertex& b) const {
        ++m_counters.rays;
        if (b.infinite || a.infinite) {
            const Vertex& fin = a.infinite ? b : a;
            const Vertex& inf = a.infinite ? a : b;
            const Vec3 d = normalize(inf.p - fin.p);
            return !m_scene.occluded(
                Ray{offset_ray_origin(fin.p, fin.p_error, fin.ng, d), d, kInfinity});
        }
        const Point3 o = offset_ray_origin(a.p, a.p_error, a.ng, b.p - a.p);
        const Point3 t = offset_ray_origin(b.p, b.p_error, b.ng, o - b.p);
        return !m_scene.occluded(Ray{o, t - o, 1 - Float(1e-4)});
    }

    /// The transmittance between a and b (pbrt-v4's Integrator::Tr): zero if a surface with
    /// a material is between them, else the product of ratio-tracking estimates through the
    /// media the segment crosses (starting in a's medium towards b, or b's if a is at
    /// infinity). Without media, visibility alone.
    SampledSpectrum tr(const Vertex& a, const Vertex& b) const {
        if (!m_media) return SampledSpectrum(unoccluded(a, b) ? 1 : 0);
        Ray ray;
        int medium;
        bool to_point = true;
        if (b.infinite || a.infinite) {
            const Vertex& fin = a.infinite ? b : a;
            const Vertex& inf = a.infinite ? a : b;
            const Vec3 d = normalize(inf.p - fin.p);
            ray = Ray{offset_ray_origin(fin.p, fin.p_error, fin.ng, d), d, kInfinity};
            medium = fin.medium_towards(d);
            to_point = false;
        } else {
            const Point3 o = offset_ray_origin(a.p, a.p_error, a.ng, b.p - a.p);
            const Point3 t = offset_ray_origin(b.p, b.p_error, b.ng, o - b.p);
            ray = Ray{o, t - o, 1 - Float(1e-4)};
            medium = a.medium_towards(b.p - a.p);
        }
        SampledSpectrum r_l(1), r_u(1);
        const SampledSpectrum t = shadow_transmittance(m_scene, ray, medium, to_point, m_lambda,
                                                       r_l, r_u, m_tr_key, m_counters);
        if (t.is_zero()) return t;
        const SampledSpectrum w = t / r_l.average();
        return w.has_nonfinite() ? SampledSpectrum(0) : w;
    }

    /// The generalised geometry term with visibility and transmittance (shading-normal
    /// cosines at surfaces; none at medium vertices and points).
    SampledSpectrum g(const Vertex& a, const Vertex& b) const {
        Vec3 d = a.p - b.p;
        Float gv = 1 / length_squared(d);
        d = d * std::sqrt(gv);
        if (a.on_surface()) gv *= absdot(a.ns, d);
        if (b.on_surface()) gv *= absdot(b.ns, d);
        if (!(gv > 0) || !std::isfinite(gv)) return SampledSpectrum(0);
        return tr(a, b) * gv;
    }

    // ---- subpaths --------------------------------------------------------------------------

    /// Extends `path` (whose last vertex exists) by a random walk from `ray`, which starts in
    /// `medium` (-1: vacuum). In a medium, free flights are sampled by delta tracking against
    /// its majorant (pbrt-v4's RandomWalk with SampleT_maj, as volpath's): a real scattering
    /// makes a medium vertex, whose phase function is sampled for the next direction.
    void random_walk(std::vector<Vertex>& path, Ray ray, SampledSpectrum beta, Float pdf_fwd,
                     int max_vertices, TransportMode mode, int medium) {
        if (max_vertices <= 0) return;
        int added = 0, crossings = 0;
        bool any_non_specular = false;
        while (true) {
            if (beta.is_zero()) break;
            SurfaceHit hit;
            ++m_counters.rays;
            const bool found = m_scene.intersect(ray, hit);
            if (medium >= 0) {
                // Two dimensions per medium segment: the first free flight, and the key of
                // the stream of the later ones and of the collisions' choices.
                const Float u = m_sampler->get_1d();
                const Float uk = m_sampler->get_1d();
                Point3 p_scatter;
                Float g_scatter = 0;
                const FreeFlight fl = free_flight(m_scene, medium, ray, found ? hit.t : kInfinity,
                                                  u, uk, m_lambda, beta, p_scatter, g_scatter);
                if (fl == FreeFlight::Absorbed) break;
                if (fl == FreeFlight::Scattered) {
                    Vertex v;
                    v.type = VertexType::Medium;
                    v.beta = beta;
                    v.p = p_scatter;
                    v.hit.wo = -normalize(ray.d);
                    v.g = g_scatter;
                    v.medium_in = v.medium_out = medium;
                    v.pdf_fwd = convert_density(path.back(), pdf_fwd, v);
                    path.push_back(std::move(v));
                    Vertex& cur = path.back();
                    if (++added >= max_vertices) break;
                    m_sampler->skip_1d();  // (three dimensions per vertex, as a surface's)
                    const PhaseSample ps = sample_hg(cur.hit.wo, cur.g, m_sampler->get_2d());
                    if (!(ps.p > 0)) break;
                    // Sampled exactly: beta is unchanged (p / pdf = 1), and the reverse
                    // density is the same value (the phase function is symmetric).
                    pdf_fwd = ps.p;
                    any_non_specular = true;
                    ray = Ray{cur.p, ps.wi, kInfinity};
                    Vertex& prev = path[path.size() - 2];
                    prev.pdf_rev = convert_density(cur, ps.p, prev);
                    continue;
                }
            }
            if (!found) {
                if (mode == TransportMode::Radiance) {
                    Vertex v;
                    v.type = VertexType::Light;
                    v.infinite = true;
                    v.light = -1;
                    v.beta = beta;
                    v.p = ray.o + ray.d;
                    v.pdf_fwd = pdf_fwd;
                    path.push_back(std::move(v));
                }
                break;
            }
            std::optional<Bsdf> bsdf =
                hit.material >= 0 ? make_bsdf(m_scene.materials[size_t(hit.material)], m_mctx, hit,
                                              m_lambda)
                                  : std::nullopt;
            if (!bsdf) {
                if (++crossings > 256) break;
                medium = medium_after(m_scene, hit, ray.d, medium);
                ray = spawn_ray(hit, ray.d);
                continue;
            }
            if (m_ctx.regularize && any_non_specular) bsdf->regularize();
            Vertex v;
            v.type = VertexType::Surface;
            v.beta = beta;
            v.p = hit.p;
            v.p_error = hit.p_error;
            v.ng = hit.ng;
            v.ns = bsdf->frame().n;
            v.light = hit.light;
            if (m_media) {
                v.medium_in = medium_after(m_scene, hit, -hit.ng, medium);
                v.medium_out = medium_after(m_scene, hit, hit.ng, medium);
            }
            v.hit = hit;
            v.bsdf = std::move(bsdf);
            v.pdf_fwd = convert_density(path.back(), pdf_fwd, v);
            path.push_back(std::move(v));
            Vertex& cur = path.back();
            if (++added >= max_vertices) break;
            const Float uc = m_sampler->get_1d();
            const Point2 u = m_sampler->get_2d();
            auto bs = cur.bsdf->sample(cur.hit.wo, uc, u, mode);
            if (!bs) break;
            pdf_fwd = bs->pdf_sa;
            any_non_specular |= !bs->is_specular();
            beta *= bs->f * (absdot(bs->wi, cur.ns) / bs->pdf_sa);
            Float pdf_rev = cur.bsdf->pdf(bs->wi, cur.hit.wo,
                                          mode == TransportMode::Radiance ? TransportMode::Importance
                                                                          : TransportMode::Radiance);
            if (bs->is_specular()) {
                cur.delta = true;
                pdf_rev = pdf_fwd = 0;
            }
            medium = cur.medium_towards(bs->wi);
            ray = spawn_ray(cur.hit, bs->wi);
            Vertex& prev = path[path.size() - 2];
            prev.pdf_rev = convert_density(cur, pdf_rev, prev);
        }
    }

    /// The camera subpath: the camera vertex and up to max_walk more.
    void camera_subpath(std::vector<Vertex>& path, const Ray& ray, int max_walk) {
        path.clear();
        Float pdf_pos = 0, pdf_dir = 0;
        m_scene.camera->pdf_we(ray, pdf_pos, pdf_dir);
        Vertex c;
        c.type = VertexType::Camera;
        c.beta = SampledSpectrum(1);
        c.p = ray.o;
        c.medium_in = c.medium_out = m_scene.camera_medium;
        path.push_back(std::move(c));
        if (!(pdf_dir > 0)) return;
        random_walk(path, ray, SampledSpectrum(1), pdf_dir, max_walk, TransportMode::Radiance,
                    m_scene.camera_medium);
    }

    /// A light vertex's media (Scene::light_media; vacuum at infinity).
    void set_light_media(Vertex& v, int li) const {
        if (v.infinite || size_t(li) >= m_scene.light_media.size()) return;
        v.medium_in = m_scene.light_media[size_t(li)].inside;
        v.medium_out = m_scene.light_media[size_t(li)].outside;
    }

    /// The light subpath: a light vertex and up to max_vertices - 1 more.
    void light_subpath(std::vector<Vertex>& path, int max_vertices) {
        path.clear();
        const Float ul = m_sampler->get_1d();
        const Point2 u_pos = m_sampler->get_2d();
        const Point2 u_dir = m_sampler->get_2d();
        if (max_vertices <= 0 || m_scene.light_sampler.empty()) return;
        Float pmf = 0;
        const int li = m_scene.light_sampler.sample(ul, pmf);
        if (li < 0 || !(pmf > 0)) return;
        const Light& light = m_scene.lights[size_t(li)];
        auto les = sample_le(light, u_pos, u_dir, m_lambda);
        if (!les) return;
        Vertex v;
        v.type = VertexType::Light;
        v.light = li;
        v.infinite = std::holds_alternative<DistantLight>(light) ||
                     std::holds_alternative<UniformInfiniteLight>(light) ||
                     std::holds_alternative<ImageInfiniteLight>(light);
        v.p = les->p;
        v.p_error = les->p_error;
        v.ng = v.ns = les->n;
        set_light_media(v, li);
        // (Read only by lightpath's s = 1, with the emission towards the lens.)
        v.beta = SampledSpectrum(1 / (pmf * les->pdf_pos));
        v.pdf_fwd = pmf * les->pdf_pos;
        path.push_back(std::move(v));
        const Float cos = path[0].on_surface() ? absdot(les->n, les->ray.d) : 1;
        const SampledSpectrum beta = les->L * (cos / (pmf * les->pdf_pos * les->pdf_dir));
        const int medium = path[0].medium_towards(les->ray.d);
        random_walk(path, les->ray, beta, les->pdf_dir, max_vertices - 1, TransportMode::Importance,
                    medium);
        if (path[0].infinite) {
            // The first surface's density is the disk's (its position), and the light
            // vertex's the direction's (pbrt-v3's correction for infinite lights).
            if (path.size() > 1) {
                path[1].pdf_fwd = les->pdf_pos;
                if (path[1].on_surface()) path[1].pdf_fwd *= absdot(les->ray.d, path[1].ng);
            }
            path[0].pdf_fwd = infinite_density(-les->ray.d);
        }
    }

    // ---- MIS -------------------------------------------------------------------------------

    /// The power-heuristic weight of strategy (s, t) by Veach's recursion (sec. 10.2.1): the
    /// ratios p_i / p_s of the other strategies that could make the same path follow from
    /// one vertex to the next, so the weight costs O(s + t). The connection vertices'
    /// reverse densities, which depend on the strategy, are set for the computation and
    /// restored after it.
    Float mis_weight(std::vector<Vertex>& L, std::vector<Vertex>& C, Vertex& sampled, int s,
                     int t) const {
        if (s + t == 2) return 1;
        if (s == 1) std::swap(L[0], sampled);
        if (t == 1) std::swap(C[0], sampled);
        Vertex* qs = s > 0 ? &L[size_t(s - 1)] : nullptr;
        Vertex* pt = t > 0 ? &C[size_t(t - 1)] : nullptr;
        Vertex* qsm = s > 1 ? &L[size_t(s - 2)] : nullptr;
        Vertex* ptm = t > 1 ? &C[size_t(t - 2)] : nullptr;
        // Saved for the restore.
        const Float pt_rev = pt ? pt->pdf_rev : 0, ptm_rev = ptm ? ptm->pdf_rev : 0;
        const Float qs_rev = qs ? qs->pdf_rev : 0, qsm_rev = qsm ? qsm->pdf_rev : 0;
        const bool pt_delta = pt ? pt->delta : false, qs_delta = qs ? qs->delta : false;

        if (pt) pt->delta = false;
        if (qs) qs->delta = false;
        if (pt) pt->pdf_rev = s > 0 ? pdf(*qs, qsm, *pt) : pdf_light_origin(*pt, *ptm);
        if (ptm) ptm->pdf_rev = s > 0 ? pdf(*pt, qs, *ptm) : pdf_light(*pt, *ptm);
        if (qs) qs->pdf_rev = pdf(*pt, ptm, *qs);
        if (qsm) qsm->pdf_rev = pdf(*qs, pt, *qsm);

        // The densities generated into specular chains (chain_factor), set for the
        // computation and restored after it.
        const int n = s + t;
        auto at = [&](int k) -> Vertex& {
            return k < s ? L[size_t(k)] : C[size_t(n - 1 - k)];
        };
        m_chain_saved.clear();
        for_each_chain(n, at, [&](int i, int j) {
            // x_i's density from x_{i-1} (the light's side), x_j's from x_{j+1}.
            Float& from_light = i < s ? at(i).pdf_fwd : at(i).pdf_rev;
            Float& from_camera = j < s ? at(j).pdf_rev : at(j).pdf_fwd;
            const double fl = chain_factor(at, i - 1, i, j + 1);
            const double fc = chain_factor(at, j + 1, j, i - 1);
            m_chain_saved.push_back({&from_light, from_light});
            m_chain_saved.push_back({&from_camera, from_camera});
            from_light = Float(double(from_light) * fl);
            from_camera = Float(double(from_camera) * fc);
        });

        double sum = 0, r = 1;
        for (int i = t - 1; i > 0; --i) {
            r *= double(remap0(C[size_t(i)].pdf_rev)) / remap0(C[size_t(i)].pdf_fwd);
            if (!C[size_t(i)].delta && !C[size_t(i - 1)].delta) sum += r * r;
        }
        r = 1;
        for (int i = s - 1; i >= 0; --i) {
            r *= double(remap0(L[size_t(i)].pdf_rev)) / remap0(L[size_t(i)].pdf_fwd);
            const bool delta_before = i > 0 ? L[size_t(i - 1)].delta : is_delta_light(L[0]);
            if (!L[size_t(i)].delta && !delta_before) sum += r * r;
        }

        for (size_t k = m_chain_saved.size(); k-- > 0;)
            *m_chain_saved[k].first = m_chain_saved[k].second;
        if (pt) pt->pdf_rev = pt_rev, pt->delta = pt_delta;
        if (ptm) ptm->pdf_rev = ptm_rev;
        if (qs) qs->pdf_rev = qs_rev, qs->delta = qs_delta;
        if (qsm) qsm->pdf_rev = qsm_rev;
        if (s == 1) std::swap(L[0], sampled);
        if (t == 1) std::swap(C[0], sampled);
        const double w = 1 / (1 + sum);
        return std::isfinite(w) ? Float(w) : 0;
    }

    // ---- connections -----------------------------------------------------------------------

    /// The unweighted contribution of strategy (s, t) (0 if it cannot make a path), with the
    /// film position of a t = 1 connection in p_raster and its vertex in `sampled`.
    SampledSpectrum connect(std::vector<Vertex>& L, std::vector<Vertex>& C, int s, int t,
                            Vertex& sampled, Point2& p_raster) {
        // The sample dimensions a strategy uses are consumed before anything can end it.
        Float ul = 0;
        Point2 u(0, 0);
        if (t == 1 && s > 0) {
            u = m_sampler->get_2d();
        } else if (s == 1) {
            ul = m_sampler->get_1d();
            u = m_sampler->get_2d();
        }
        SampledSpectrum c(0);
        if (t > 1 && s != 0 && C[size_t(t - 1)].type == VertexType::Light) return c;
        if (s == 0) {
            const Vertex& pt = C[size_t(t - 1)];
            if (is_light(pt)) c = le(pt, C[size_t(t - 2)]) * pt.beta;
        } else if (t == 1) {
            const Vertex& qs = L[size_t(s - 1)];
            // (A light vertex reaches the camera only from a surface: a point light, as in
            // pbrt-v4's lightpath, and an infinite light's disk are not seen directly.)
            if (!connectible(qs) || (qs.type == VertexType::Light && !qs.on_surface())) return c;
            auto cs = m_scene.camera->sample_wi(qs.p, u);
            if (!cs || !m_ctx.inside(cs->p_raster)) return c;
            p_raster = cs->p_raster;
            sampled = Vertex{};
            sampled.type = VertexType::Camera;
            sampled.p = cs->p_lens;
            sampled.ng = sampled.ns = cs->n_lens;
            sampled.medium_in = sampled.medium_out = m_scene.camera_medium;
            sampled.beta = SampledSpectrum(cs->we / cs->pdf);
            if (qs.type == VertexType::Light) {
                // The light's own vertex (lightpath's s = 1): its emission towards the lens.
                c = qs.beta * le(qs, sampled) * sampled.beta;
                if (qs.on_surface()) c *= absdot(cs->wi, qs.ng);
            } else {
                c = qs.beta * f(qs, sampled, TransportMode::Importance) * sampled.beta;
                if (qs.on_surface()) c *= absdot(cs->wi, qs.ns);
            }
            if (!c.is_zero()) c *= tr(qs, sampled);
            c *= m_ctx.crop_factor;
        } else if (s == 1) {
            const Vertex& pt = C[size_t(t - 1)];
            if (!connectible(pt) || m_scene.light_sampler.empty()) return c;
            Float pmf = 0;
            const int li = m_scene.light_sampler.sample(ul, pmf);
            if (li < 0 || !(pmf > 0)) return c;
            const Light& light = m_scene.lights[size_t(li)];
            auto ls = sample_li(light, LightSampleContext{pt.p, pt.p_error, pt.ng}, u, m_lambda,
                                false);
            if (!ls || ls->L.is_zero() || !(ls->pdf_sa > 0)) return c;
            sampled = Vertex{};
            sampled.type = VertexType::Light;
            sampled.light = li;
            sampled.infinite = ls->at_infinity;
            sampled.p = ls->p_light;
            sampled.p_error = ls->p_error;
            sampled.ng = sampled.ns = ls->n_light;
            set_light_media(sampled, li);
            sampled.beta = ls->L / (ls->pdf_sa * pmf);
            if (sampled.infinite) sampled.light = -1;  // densities of all infinite lights
            sampled.pdf_fwd = pdf_light_origin(sampled, pt);
            if (sampled.infinite) sampled.light = li;
            c = pt.beta * f(pt, sampled, TransportMode::Radiance) * sampled.beta;
            if (pt.on_surface()) c *= absdot(ls->wi, pt.ns);
            if (!c.is_zero()) c *= tr(pt, sampled);
        } else {
            const Vertex& qs = L[size_t(s - 1)];
            const Vertex& pt = C[size_t(t - 1)];
            if (!connectible(qs) || !connectible(pt)) return c;
            c = qs.beta * f(qs, pt, TransportMode::Importance) * f(pt, qs, TransportMode::Radiance) *
                pt.beta;
            if (!c.is_zero()) c *= g(qs, pt);  // (with the transmittance between them)
        }
        return c;
    }

    SampledSpectrum li(BdptScratch& sc, const Ray& ray, Point2 p_film, SplatSink& sink) {
        sc.camera.reserve(size_t(m_ctx.max_depth) + 3);
        sc.light.reserve(size_t(m_ctx.max_depth) + 2);
        camera_subpath(sc.camera, ray, m_ctx.max_depth + 1);
        light_subpath(sc.light, m_ctx.max_depth + 1);
        const int nc = int(sc.camera.size()), nl = int(sc.light.size());
        SampledSpectrum Lsum(0);
        for (int t = 1; t <= nc; ++t)
            for (int s = 0; s <= nl; ++s) {
                const int depth = s + t - 2;
                if ((s == 1 && t == 1) || depth < 0 || depth > m_ctx.max_depth) continue;
                if (m_ctx.only_depth >= 0 && depth != m_ctx.only_depth) {
                    // Keep the sampler's dimensions as the full estimator consumes them.
                    if (t == 1) m_sampler->skip_2d();
                    if (s == 1 && t > 1) m_sampler->skip_1d(), m_sampler->skip_2d();
                    continue;
                }
                Point2 p_raster = p_film;
                const SampledSpectrum c = connect(sc.light, sc.camera, s, t, sc.sampled, p_raster);
                if (c.is_zero()) continue;
                const Float w = m_ctx.unweighted ? 1 : mis_weight(sc.light, sc.camera, sc.sampled, s, t);
                const SampledSpectrum cw = c * w;
                if (m_ctx.visualize) sink.strategy(s, t, p_raster, c, w);
                if (t == 1)
                    sink.splat(p_raster, cw);
                else
                    Lsum += cw;
            }
        return Lsum;
    }

    /// Strategy (s, t) alone, its subpaths of exactly s and t vertices, the camera's from
    /// `cam`, the light's from `light` and the connection's numbers from `conn`.
    SampledSpectrum strategy(BdptScratch& sc, int s, int t, const Ray& ray, Sampler& cam,
                             Sampler& light, Sampler& conn, Point2& p_raster) {
        sc.camera.reserve(size_t(m_ctx.max_depth) + 3);
        sc.light.reserve(size_t(m_ctx.max_depth) + 2);
        m_sampler = &cam;
        camera_subpath(sc.camera, ray, t - 1);
        if (int(sc.camera.size()) != t) return SampledSpectrum(0);
        sc.light.clear();
        if (s > 0) {
            m_sampler = &light;
            light_subpath(sc.light, s);
            if (int(sc.light.size()) != s) return SampledSpectrum(0);
        }
        m_sampler = &conn;
        const SampledSpectrum c = connect(sc.light, sc.camera, s, t, sc.sampled, p_raster);
        if (c.is_zero()) return c;
        return c * mis_weight(sc.light, sc.camera, sc.sampled, s, t);
    }

    void lightpath(BdptScratch& sc, SplatSink& sink) {
        sc.light.reserve(size_t(m_ctx.max_depth) + 2);
        light_subpath(sc.light, m_ctx.max_depth + 1);
        for (int s = 1; s <= int(sc.light.size()); ++s) {
            Point2 p_raster;
            const SampledSpectrum c = connect(sc.light, sc.camera, s, 1, sc.sampled, p_raster);
            if (!c.is_zero()) sink.splat(p_raster, c);
        }
    }

    // ---- test access -----------------------------------------------------------------------

    std::vector<bdpt_test::WeightCheck> weights_of_camera_path(const Ray& ray, int n) {
        std::vector<bdpt_test::WeightCheck> out;
        std::vector<Vertex> cam;
        cam.reserve(size_t(m_ctx.max_depth) + 3);
        camera_subpath(cam, ray, m_ctx.max_depth + 1);
        if (int(cam.size()) < n) return out;
        cam.resize(size_t(n));
        const Vertex& last = cam.back();
        if (!is_light(last) || last.infinite || last.type != VertexType::Surface) return out;
        // The full path x_0 (the emitter) ... x_{n-1} (the camera).
        std::vector<Vertex> x(cam.rbegin(), cam.rend());
        int n_medium = 0;
        for (const Vertex& v : x) n_medium += v.type == VertexType::Medium;
        // The emitter as a light vertex.
        Vertex& x0 = x[0];
        x0.type = VertexType::Light;
        x0.delta = false;
        x0.ns = x0.ng;
        // Densities of each vertex generated from the light side (pl) and the camera side
        // (pc), a density generated by a specular vertex remapped to 1 as the recursion does.
        std::vector<double> pl(size_t(n), 0), pc(size_t(n), 0);
        pl[0] = pdf_light_origin(x[0], x[1]);
        for (int i = 1; i < n; ++i) {
            if (i == 1)
                pl[1] = pdf_light(x[0], x[1]);
            else
                pl[size_t(i)] = x[size_t(i - 1)].delta
                                    ? 1
                                    : pdf(x[size_t(i - 1)], &x[size_t(i - 2)], x[size_t(i)]);
        }
        pc[size_t(n - 1)] = 1;  // the camera vertex: never met by another strategy
        for (int i = n - 2; i >= 0; --i) {
            if (i == n - 2)
                pc[size_t(i)] = pdf(x[size_t(n - 1)], nullptr, x[size_t(i)]);
            else
                pc[size_t(i)] = x[size_t(i + 1)].delta
                                    ? 1
                                    : pdf(x[size_t(i + 1)], &x[size_t(i + 2)], x[size_t(i)]);
        }
        // The walks' own densities (the subpaths below get these), then those of the
        // strategies' comparison: into specular chains as mis_weight sets them.
        const std::vector<double> pl_walk = pl, pc_walk = pc;
        auto xat = [&](int k) -> const Vertex& { return x[size_t(k)]; };
        for_each_chain(n, xat, [&](int i, int j) {
            pl[size_t(i)] *= chain_factor(xat, i - 1, i, j + 1);
            pc[size_t(j)] *= chain_factor(xat, j + 1, j, i - 1);
        });
        auto valid = [&](int s) {
            if (s == 0) return true;
            if (s == 1 && n == 2) return false;  // (1, 1) is not a bdpt strategy
            const bool d0 = s - 1 == 0 ? is_delta_light(x[0]) : x[size_t(s - 1)].delta;
            return !d0 && !x[size_t(s)].delta;
        };
        auto p_of = [&](int s) {
            double p = 1;
            for (int i = 0; i < s; ++i) p *= remap0(Float(pl[size_t(i)]));
            for (int i = s; i < n - 1; ++i) p *= remap0(Float(pc[size_t(i)]));
            return p;
        };
        double denom = 0;
        for (int s = 0; s < n; ++s)
            if (valid(s)) denom += sqr(p_of(s));
        for (int s = 0; s < n; ++s) {
            if (!valid(s)) continue;
            const int t = n - s;
            // The subpaths of strategy (s, t), with the densities their own walks give.
            std::vector<Vertex> L(x.begin(), x.begin() + s), C;
            for (int i = n - 1; i >= s; --i) C.push_back(x[size_t(i)]);
            for (int i = 0; i < s; ++i) {
                L[size_t(i)].pdf_fwd = Float(pl_walk[size_t(i)]);
                L[size_t(i)].pdf_rev = Float(pc_walk[size_t(i)]);
            }
            for (int j = 0; j < t; ++j) {
                const int i = n - 1 - j;
                C[size_t(j)].pdf_fwd = Float(pc_walk[size_t(i)]);
                C[size_t(j)].pdf_rev = Float(pl_walk[size_t(i)]);
            }
            // A specular vertex's densities through it are zero in the walks.
            auto zero_delta = [&](std::vector<Vertex>& P) {
                for (size_t j = 1; j < P.size(); ++j)
                    if (P[j - 1].delta) P[j].pdf_fwd = 0;
                for (size_t j = 0; j + 1 < P.size(); ++j)
                    if (P[j + 1].delta) P[j].pdf_rev = 0;
            };
            zero_delta(L);
            zero_delta(C);
            if (s == 0) C.back().type = VertexType::Surface;  // met by the camera path
            Vertex sampled;
            if (s == 1) sampled = L[0];
            if (t == 1) sampled = C[0];
            const double rw = s + t == 2 ? 1 : mis_weight(L, C, sampled, s, t);
            out.push_back({s, rw, sqr(p_of(s)) / denom, n_medium});
        }
        return out;
    }

private:
    const BidirContext& m_ctx;
    const Scene& m_scene;
    SampledWavelengths& m_lambda;
    Sampler* m_sampler;
    PathCounters& m_counters;
    const MaterialContext m_mctx;
    const bool m_media;       ///< the scene has media: connections track transmittance
    /// mis_weight's densities changed for specular chains, with their values to restore.
    mutable std::vector<std::pair<Float*, Float>> m_chain_saved;
    const uint64_t m_tr_key;  ///< keys the transmittance streams of this sample's connections
};

}  // namespace

SampledSpectrum bdpt_li(const BidirContext& ctx, BdptScratch& scratch, const Ray& camera_ray,
                        Point2 p_film, SampledWavelengths& lambda, Sampler& sampler,
                        PathCounters& counters, SplatSink& sink) {
    Bidir b(ctx, lambda, sampler, counters);
    return b.li(scratch, camera_ray, p_film, sink);
}

SampledSpectrum bdpt_strategy(const BidirContext& ctx, BdptScratch& scratch, int s, int t,
                              const Ray& camera_ray, SampledWavelengths& lambda, Sampler& camera,
                              Sampler& light, Sampler& connection, PathCounters& counters,
                              Point2& p_raster) {
    if (t < 1 || s < 0 || (s == 1 && t == 1) || s + t - 2 > ctx.max_depth) return SampledSpectrum(0);
    Bidir b(ctx, lambda, camera, counters);
    return b.strategy(scratch, s, t, camera_ray, camera, light, connection, p_raster);
}

void lightpath_sample(const BidirContext& ctx, BdptScratch& scratch, SampledWavelengths& lambda,
                      Sampler& sampler, PathCounters& counters, SplatSink& sink) {
    Bidir b(ctx, lambda, sampler, counters);
    b.lightpath(scratch, sink);
}

std::vector<bdpt_test::WeightCheck> bdpt_test::mis_weights_of_camera_path(
    const BidirContext& ctx, const Ray& ray, SampledWavelengths& lambda, Sampler& sampler,
    int n_vertices) {
    PathCounters counters;
    Bidir b(ctx, lambda, sampler, counters);
    return b.weights_of_camera_path(ray, n_vertices);
}

}  // namespace sr
