#include "steradian/lights/light.h"

#include "steradian/sampling/hash.h"
#include "steradian/sampling/warp.h"

namespace sr {

namespace {
Float photometric(const Spectrum& s) { return spectrum_to_photometric(s); }
}  // namespace

// ---- point ----------------------------------------------------------------------------

std::optional<LightLiSample> PointLight::sample_li(const LightSampleContext& ctx, Point2,
                                                   const SampledWavelengths& lambda) const {
    Vec3 d = p - ctx.p;
    Float dist2 = length_squared(d);
    if (dist2 == 0) return std::nullopt;
    LightLiSample s;
    s.wi = d / std::sqrt(dist2);
    s.L = intensity.sample(lambda) * (scale / dist2);
    s.pdf_sa = 1;
    s.p_light = p;
    s.delta = true;
    return s;
}

Float PointLight::phi_y() const { return 4 * kPi * scale * photometric(intensity); }

// ---- goniometric (photometric point) ---------------------------------------------------

std::optional<LightLiSample> GoniometricLight::sample_li(const LightSampleContext& ctx, Point2,
                                                         const SampledWavelengths& lambda) const {
    Vec3 d = p - ctx.p;
    Float dist2 = length_squared(d);
    if (dist2 == 0) return std::nullopt;
    LightLiSample s;
    s.wi = d / std::sqrt(dist2);
    Float i = image ? image->lookup(profile.light_from_world.vector(-s.wi)) : profile.intensity(-s.wi);
    if (!(i > 0)) return std::nullopt;
    s.L = spectrum.sample(lambda) * (scale * i / dist2);
    s.pdf_sa = 1;
    s.p_light = p;
    s.delta = true;
    return s;
}

Float GoniometricImage::lookup(Vec3 w) const {
    Float len = length(w);
    if (!(len > 0) || res <= 0) return 0;
    // pbrt-v4's light frame has y and z swapped relative to the light's local frame.
    Point2 uv = equal_area_sphere_to_square(Vec3(w.x, w.z, w.y) / len);
    int x = std::clamp(int(uv.x * Float(res)), 0, res - 1);
    int yy = std::clamp(int(uv.y * Float(res)), 0, res - 1);
    return y[size_t(yy) * size_t(res) + size_t(x)];
}

Float GoniometricImage::mean() const {
    double s = 0;
    for (float v : y) s += v;
    return y.empty() ? 0 : Float(s / double(y.size()));
}

// ---- spot -----------------------------------------------------------------------------

std::optional<LightLiSample> SpotLight::sample_li(const LightSampleContext& ctx, Point2,
                                                  const SampledWavelengths& lambda) const {
    Vec3 d = p - ctx.p;
    Float dist2 = length_squared(d);
    if (dist2 == 0) return std::nullopt;
    LightLiSample s;
    s.wi = d / std::sqrt(dist2);
    Vec3 w_light = normalize(light_from_world.vector(-s.wi));
    // Smooth falloff between the two cone angles (pbrt-v4's smoothstep on cos theta).
    Float cos_t = w_light.z;
    Float falloff;
    if (cos_t >= cos_falloff_start) {
        falloff = 1;
    } else if (cos_t <= cos_falloff_end) {
        falloff = 0;
    } else {
        Float t = (cos_t - cos_falloff_end) / (cos_falloff_start - cos_falloff_end);
        falloff = t * t * (3 - 2 * t);
    }
    if (falloff == 0) return std::nullopt;
    s.L = intensity.sample(lambda) * (scale * falloff / dist2);
    s.pdf_sa = 1;
    s.p_light = p;
    s.delta = true;
    return s;
}

Float SpotLight::phi_y() const {
    return scale * photometric(intensity) * 2 * kPi *
           ((1 - cos_falloff_start) + (cos_falloff_start - cos_falloff_end) / 2);
}

// ---- distant --------------------------------------------------------------------------

std::optional<LightLiSample> DistantLight::sample_li(const LightSampleContext& ctx, Point2,
                                                     const SampledWavelengths& lambda) const {
    LightLiSample s;
    s.wi = w_light;
    s.L = radiance.sample(lambda) * scale;
    s.pdf_sa = 1;
    s.p_light = ctx.p + w_light * (2 * scene_radius);
    s.delta = true;
    s.at_infinity = true;
    return s;
}

Float DistantLight::phi_y() const {
    return scale * photometric(radiance) * kPi * sqr(scene_radius);
}

// ---- uniform infinite -----------------------------------------------------------------

std::optional<LightLiSample> UniformInfiniteLight::sample_li(
    const LightSampleContext& ctx, Point2 u, const SampledWavelengths& lambda) const {
    LightLiSample s;
    s.wi = sample_uniform_sphere(u);
    s.pdf_sa = uniform_sphere_pdf();
    s.L = radiance.sample(lambda) * scale;
    s.p_light = ctx.p + s.wi * (2 * scene_radius);
    s.at_infinity = true;
    return s;
}

Float UniformInfiniteLight::pdf_li(const LightSampleContext&, Vec3) const {
    return uniform_sphere_pdf();
}

Float UniformInfiniteLight::phi_y() const {
    return 4 * kPi * kPi * sqr(scene_radius) * scale * photometric(radiance);
}

// ---- diffuse area ---------------------------------------------------------------------

std::optional<LightLiSample> DiffuseAreaLight::sample_li(const LightSampleContext& ctx,
                                                         Point2 u,
                                                         const SampledWavelengths& lambda) const {
    // Every return returns r, so that it is the caller's object: a local sample, written
    // field by field and copied out in 16-byte pieces, stalled store-to-load forwarding.
    std::optional<LightLiSample> r;
    // A one-sided flat emitter sends nothing to points behind it: skip the sampling.
    if (triangle && !two_sided && !goniometric && triangle->behind(ctx.p)) return r;
    // Initialised by the sampler itself (a default-constructed ShapeSample assigned from
    // it cost a zero fill and a copy).
    ShapeSample ss = triangle ? triangle->sample_from(ctx.p, u)
                     : sphere ? sphere->sample_from(ctx.p, u)
                              : disk->sample_area(u);
    if (!triangle && !sphere) ss.pdf = area_to_solid_angle_pdf(ss.pdf, ctx.p, ss.p, ss.n);
    if (ss.pdf == 0 || !std::isfinite(ss.pdf)) return r;
    Vec3 d = ss.p - ctx.p;
    Float dist2 = length_squared(d);
    if (dist2 == 0) return r;
    Vec3 wi = d / std::sqrt(dist2);
    SampledSpectrum L = l(ss.n, -wi, lambda);
    if (L.is_zero() || (alpha && masked(ss.p))) return r;
#if defined(__clang__) && __clang_major__ < 16
    // Clang before 16 lacks C++20's parenthesized aggregate initialisation (P0960).
    r = LightLiSample{L, wi, ss.pdf, ss.p, ss.p_error, ss.n};
#else
    r.emplace(L, wi, ss.pdf, ss.p, ss.p_error, ss.n);
#endif
    return r;
}

bool DiffuseAreaLight::masked(Point3 p) const {
    if (!alpha) return false;
    SurfaceHit h;
    if (mesh) {
        // Barycentrics of p in the triangle (least squares in its plane).
        const Triangle& t = *triangle;
        const Vec3 e1 = t.p1 - t.p0, e2 = t.p2 - t.p0, q = p - t.p0;
        const Float a11 = dot(e1, e1), a12 = dot(e1, e2), a22 = dot(e2, e2);
        const Float det = a11 * a22 - a12 * a12;
        if (!(det > 0)) return false;
        const Float b1 = (a22 * dot(q, e1) - a12 * dot(q, e2)) / det;
        const Float b2 = (a11 * dot(q, e2) - a12 * dot(q, e1)) / det;
        mesh->fill_hit(prim, b1, b2, h);
    } else if (sphere) {
        sphere->fill_hit(sphere->world_from_object.inverse().point(p), h);
    } else if (disk) {
        disk->fill_hit(disk->world_from_object.inverse().point(p), h);
    } else {
        return false;
    }
    const Float a = alpha->alpha(h);
    if (a >= 1) return false;
    if (!(a > 0)) return true;
    return Float(double(hash(p.x, p.y, p.z) >> 11) * 0x1p-53) > a;
}

Float DiffuseAreaLight::pdf_li_point(const LightSampleContext& ctx, Point3 p_light,
                                     Normal3 n_light) const {
    if (sphere) return sphere->pdf_from(ctx.p, p_light, n_light);
    if (triangle) return triangle->pdf_from(ctx.p, p_light, n_light);
    return area_to_solid_angle_pdf(1 / area, ctx.p, p_light, n_light);
}

Float DiffuseAreaLight::phi_y() const {
    // A luminous opening's primitives share the distribution's flux by area.
    if (goniometric)
        return goniometric->scale * goniometric->flux_lm *
               (goniometric->body == LuminousBody::Sphere ? 1 : area / goniometric->opening_area);
    return scale * photometric(radiance) * kPi * area * (two_sided ? 2 : 1);
}

// ---- dispatch -------------------------------------------------------------------------

std::optional<LightLiSample> sample_li(const Light& light, const LightSampleContext& ctx,
                                       Point2 u, const SampledWavelengths& lambda,
                                       bool allow_incomplete_pdf) {
    if (const auto* im = std::get_if<ImageInfiniteLight>(&light))
        return im->sample_li(ctx, u, lambda, allow_incomplete_pdf);
    return std::visit([&](const auto& l) { return l.sample_li(ctx, u, lambda); }, light);
}

SampledSpectrum infinite_le(const Light& light, const Ray& ray, const SampledWavelengths& lambda,
                            Float* pdf, bool allow_incomplete_pdf) {
    if (const auto* im = std::get_if<ImageInfiniteLight>(&light))
        return im->le(ray.o, ray.d, lambda, pdf, allow_incomplete_pdf);
    if (const auto* un = std::get_if<UniformInfiniteLight>(&light)) {
        if (pdf) *pdf = un->pdf_li({}, ray.d);
        return un->le(ray.d, lambda);
    }
    if (pdf) *pdf = 0;
    return SampledSpectrum(0);
}

// ---- emission (light paths) -------------------------------------------------------------

namespace {

/// Spot falloff (pbrt-v4's smoothstep on cos theta), as SpotLight::sample_li computes it.
Float spot_falloff(const SpotLight& l, Float cos_t) {
    if (cos_t >= l.cos_falloff_start) return 1;
    if (cos_t <= l.cos_falloff_end) return 0;
    const Float t = (cos_t - l.cos_falloff_end) / (l.cos_falloff_start - l.cos_falloff_end);
    return t * t * (3 - 2 * t);
}

/// Whether an area light emits from both faces.
bool two_faced(const DiffuseAreaLight& a) {
    return a.two_sided || (a.goniometric && a.goniometric->body == LuminousBody::Flat);
}

/// A ray of an infinite or distant light travelling in direction d: its origin on the disk
/// of the scene's bounding radius perpendicular to d, on the side light comes from.
Point3 disk_origin(Point3 center, Float radius, Vec3 d, Point2 u) {
    const Frame f = Frame::from_z(d);
    const Point2 pd = sample_uniform_disk_concentric(u);
    return center - d * radius + (f.s * pd.x + f.t * pd.y) * radius;
}

}  // namespace

bool light_can_emit(const Light& light) {
    if (const auto* im = std::get_if<ImageInfiniteLight>(&light)) return !im->portal;
    return true;
}

bool light_delta_position(const Light& light) {
    return std::holds_alternative<PointLight>(light) || std::holds_alternative<SpotLight>(light) ||
           std::holds_alternative<GoniometricLight>(light);
}

bool light_delta_direction(const Light& light) { return std::holds_alternative<DistantLight>(light); }

std::optional<LightLeSample> sample_le(const Light& light, Point2 u_pos, Point2 u_dir,
                                       const SampledWavelengths& lambda) {
    std::optional<LightLeSample> r;
    LightLeSample s;
    if (const auto* a = std::get_if<DiffuseAreaLight>(&light)) {
        ShapeSample ss;
        if (a->triangle) {
            const auto b = sample_uniform_triangle(u_pos);
            ss = a->triangle->point_at(b[0], b[1], b[2]);
        } else if (a->sphere) {
            ss = a->sphere->sample_area(u_pos);
        } else {
            ss = a->disk->sample_area(u_pos);
        }
        if (!(a->area > 0) || (a->alpha && a->masked(ss.p))) return r;
        Normal3 n = ss.n;
        Float face = 1;
        Point2 ud = u_dir;
        if (two_faced(*a)) {
            face = 0.5f;
            if (ud.x < 0.5f) {
                ud.x = std::min(ud.x * 2, kOneMinusEpsilon);
                n = -n;
            } else {
                ud.x = std::min((ud.x - 0.5f) * 2, kOneMinusEpsilon);
            }
        }
        const Vec3 wl = sample_cosine_hemisphere(ud);
        const Vec3 w = Frame::from_z(Vec3(n)).to_world(wl);
        s.L = a->l(ss.n, w, lambda);
        s.pdf_pos = 1 / a->area;
        s.pdf_dir = face * cosine_hemisphere_pdf(wl.z);
        s.n = n;  // the emitting face's normal
        s.p_error = ss.p_error;
        s.ray = Ray{offset_ray_origin(ss.p, ss.p_error, ss.n, w), w, kInfinity};
        s.p = ss.p;
    } else if (const auto* pl = std::get_if<PointLight>(&light)) {
        s.ray = Ray{pl->p, sample_uniform_sphere(u_dir), kInfinity};
        s.L = pl->intensity.sample(lambda) * pl->scale;
        s.pdf_pos = 1;
        s.pdf_dir = uniform_sphere_pdf();
    } else if (const auto* gl = std::get_if<GoniometricLight>(&light)) {
        const Vec3 w = sample_uniform_sphere(u_dir);
        const Float i = gl->image ? gl->image->lookup(gl->profile.light_from_world.vector(w))
                                  : gl->profile.intensity(w);
        if (!(i > 0)) return r;
        s.ray = Ray{gl->p, w, kInfinity};
        s.L = gl->spectrum.sample(lambda) * (gl->scale * i);
        s.pdf_pos = 1;
        s.pdf_dir = uniform_sphere_pdf();
    } else if (const auto* sl = std::get_if<SpotLight>(&light)) {
        const Vec3 wl = sample_uniform_cone(u_dir, sl->cos_falloff_end);
        const Float f = spot_falloff(*sl, wl.z);
        if (f == 0) return r;
        s.ray = Ray{sl->p, normalize(sl->light_from_world.inverse().vector(wl)), kInfinity};
        s.L = sl->intensity.sample(lambda) * (sl->scale * f);
        s.pdf_pos = 1;
        s.pdf_dir = uniform_cone_pdf(sl->cos_falloff_end);
    } else if (const auto* dl = std::get_if<DistantLight>(&light)) {
        const Vec3 d = -dl->w_light;
        s.ray = Ray{disk_origin(dl->scene_center, dl->scene_radius, d, u_pos), d, kInfinity};
        s.L = dl->radiance.sample(lambda) * dl->scale;
        s.pdf_pos = 1 / (kPi * sqr(dl->scene_radius));
        s.pdf_dir = 1;
    } else if (const auto* ul = std::get_if<UniformInfiniteLight>(&light)) {
        const Vec3 d = -sample_uniform_sphere(u_dir);
        s.ray = Ray{disk_origin(ul->scene_center, ul->scene_radius, d, u_pos), d, kInfinity};
        s.L = ul->radiance.sample(lambda) * ul->scale;
        s.pdf_pos = 1 / (kPi * sqr(ul->scene_radius));
        s.pdf_dir = uniform_sphere_pdf();
    } else if (const auto* im = std::get_if<ImageInfiniteLight>(&light)) {
        if (im->portal) return r;
        auto li = im->sample_li(LightSampleContext{im->scene_center, {0, 0, 0}, {0, 0, 0}}, u_dir,
                                lambda, false);
        if (!li || !(li->pdf_sa > 0)) return r;
        const Vec3 d = -li->wi;
        s.ray = Ray{disk_origin(im->scene_center, im->scene_radius, d, u_pos), d, kInfinity};
        s.L = li->L;
        s.pdf_pos = 1 / (kPi * sqr(im->scene_radius));
        s.pdf_dir = li->pdf_sa;
    }
    if (!(s.pdf_pos > 0) || !(s.pdf_dir > 0) || s.L.is_zero()) return r;
    if (!std::holds_alternative<DiffuseAreaLight>(light)) s.p = s.ray.o;
    r = s;
    return r;
}

SampledSpectrum light_emitted(const Light& light, Point3 p, Normal3 n, Vec3 w,
                              const SampledWavelengths& lambda) {
    if (const auto* a = std::get_if<DiffuseAreaLight>(&light)) {
        if (a->alpha && a->masked(p)) return SampledSpectrum(0);
        return a->l(n, w, lambda);
    }
    if (const auto* pl = std::get_if<PointLight>(&light))
        return pl->intensity.sample(lambda) * pl->scale;
    if (const auto* gl = std::get_if<GoniometricLight>(&light)) {
        const Float i = gl->image ? gl->image->lookup(gl->profile.light_from_world.vector(w))
                                  : gl->profile.intensity(w);
        return i > 0 ? gl->spectrum.sample(lambda) * (gl->scale * i) : SampledSpectrum(0);
    }
    if (const auto* sl = std::get_if<SpotLight>(&light)) {
        const Float f = spot_falloff(*sl, normalize(sl->light_from_world.vector(w)).z);
        return sl->intensity.sample(lambda) * (sl->scale * f);
    }
    return SampledSpectrum(0);
}

void light_emitted(const Light& light, Point3 p, Normal3 n, Vec3 w,
                   const SampledWavelengths* lambdas, int count, SampledSpectrum* out) {
    const auto* a = std::get_if<DiffuseAreaLight>(&light);
    if (!a || !a->goniometric) {
        for (int i = 0; i < count; ++i) out[i] = light_emitted(light, p, n, w, lambdas[i]);
        return;
    }
    // A luminous opening: the intensity's factor once (GoniometricEmission::radiance), then
    // the spectrum per set.
    const GoniometricEmission& g = *a->goniometric;
    Float f = 0;
    if (!(a->alpha && a->masked(p)) && (g.body == LuminousBody::Flat || dot(n, w) > 0)) {
        const Vec3 l = g.profile.local(w);
        const Float proj = g.projected_area(l);
        const Float i = proj > 0 ? Float(g.profile.data->intensity_direction(l.x, l.y, l.z)) : 0;
        if (i > 0) f = g.scale * i / proj;
    }
    for (int k = 0; k < count; ++k)
        out[k] = f > 0 ? g.spectrum.sample(lambdas[k]) * f : SampledSpectrum(0);
}

void pdf_le(const Light& light, Point3 p, Normal3 n, Vec3 w, Float& pdf_pos, Float& pdf_dir) {
    pdf_pos = pdf_dir = 0;
    if (const auto* a = std::get_if<DiffuseAreaLight>(&light)) {
        const Float c = dot(n, w);
        if (!two_faced(*a) && c <= 0) return;
        if (a->alpha && a->masked(p)) return;
        pdf_pos = 1 / a->area;
        pdf_dir = (two_faced(*a) ? 0.5f : 1.f) * cosine_hemisphere_pdf(std::abs(c));
    } else if (std::holds_alternative<PointLight>(light) ||
               std::holds_alternative<GoniometricLight>(light)) {
        pdf_pos = 1;
        pdf_dir = uniform_sphere_pdf();
    } else if (const auto* sl = std::get_if<SpotLight>(&light)) {
        pdf_pos = 1;
        const Vec3 wl = normalize(sl->light_from_world.vector(w));
        pdf_dir = wl.z > sl->cos_falloff_end ? uniform_cone_pdf(sl->cos_falloff_end) : 0;
    } else if (const auto* dl = std::get_if<DistantLight>(&light)) {
        pdf_pos = 1 / (kPi * sqr(dl->scene_radius));
        pdf_dir = 0;  // a delta: no density another strategy could match
    } else if (const auto* ul = std::get_if<UniformInfiniteLight>(&light)) {
        pdf_pos = 1 / (kPi * sqr(ul->scene_radius));
        pdf_dir = uniform_sphere_pdf();
    } else if (const auto* im = std::get_if<ImageInfiniteLight>(&light)) {
        pdf_pos = 1 / (kPi * sqr(im->scene_radius));
        pdf_dir = im->pdf_li(LightSampleContext{p, {0, 0, 0}, {0, 0, 0}}, -w, false);
    }
}

Float light_phi_y(const Light& light) {
    return std::visit([](const auto& l) { return l.phi_y(); }, light);
}

}  // namespace sr
