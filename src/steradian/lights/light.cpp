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
               (goniometric->sphere_radius > 0 ? 1 : area / goniometric->opening_area);
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

Float light_phi_y(const Light& light) {
    return std::visit([](const auto& l) { return l.phi_y(); }, light);
}

}  // namespace sr
