/// Image-based infinite lights: the environment map (equal-area octahedral, or a lat-long
/// image resampled to one) and the light that rotates it into the scene.
#include <fmt/format.h>

#include <cmath>

#include "steradian/core/error.h"
#include "steradian/lights/light.h"
#include "steradian/sampling/warp.h"

namespace sr {

namespace {

/// Texels of an environment map at most (as film pixels and image textures).
constexpr int64_t kMaxEnvironmentTexels = int64_t(1) << 26;

/// Luminance of linear sRGB (IEC 61966-2-1: the Y row of the RGB -> XYZ matrix).
Float luminance(const float* rgb) {
    return Float(0.2126) * rgb[0] + Float(0.7152) * rgb[1] + Float(0.0722) * rgb[2];
}

/// Bilinear lookup of a lat-long image at (s, t) in [0,1]^2, pixel centres at
/// (i + 0.5) / width: wrapping around in s (longitude), clamped in t (latitude).
void bilerp_latlong(const std::vector<float>& rgb, int w, int h, Float s, Float t, float out[3]) {
    const Float x = s * Float(w) - Float(0.5), y = t * Float(h) - Float(0.5);
    const int x0 = int(std::floor(x)), y0 = int(std::floor(y));
    const Float fx = x - Float(x0), fy = y - Float(y0);
    auto px = [&](int i, int j) {
        i = ((i % w) + w) % w;
        j = std::clamp(j, 0, h - 1);
        return &rgb[(size_t(j) * size_t(w) + size_t(i)) * 3];
    };
    const float *a = px(x0, y0), *b = px(x0 + 1, y0), *c = px(x0, y0 + 1), *d = px(x0 + 1, y0 + 1);
    for (int k = 0; k < 3; ++k)
        out[k] = float((1 - fx) * (1 - fy) * a[k] + fx * (1 - fy) * b[k] + (1 - fx) * fy * c[k] +
                       fx * fy * d[k]);
}

/// The equal-area square of a lat-long image: res = its width; each texel the average of
/// 4x4 bilinear lookups at the centres of its sub-squares (a box filter over the texel).
std::vector<float> latlong_to_equal_area(const std::vector<float>& rgb, int w, int h, int res) {
    std::vector<float> out(size_t(res) * size_t(res) * 3, 0.f);
    constexpr int kSub = 4;
    for (int y = 0; y < res; ++y)
        for (int x = 0; x < res; ++x) {
            double sum[3] = {0, 0, 0};
            for (int j = 0; j < kSub; ++j)
                for (int i = 0; i < kSub; ++i) {
                    const Point2 p((Float(x) + (Float(i) + Float(0.5)) / kSub) / Float(res),
                                   (Float(y) + (Float(j) + Float(0.5)) / kSub) / Float(res));
                    const Vec3 d = equal_area_square_to_sphere(p);
                    const Float theta = std::acos(std::clamp(d.z, Float(-1), Float(1)));
                    Float phi = std::atan2(d.y, d.x);
                    if (phi < 0) phi += 2 * kPi;
                    float v[3];
                    bilerp_latlong(rgb, w, h, phi / (2 * kPi), theta / kPi, v);
                    for (int k = 0; k < 3; ++k) sum[k] += v[k];
                }
            for (int k = 0; k < 3; ++k)
                out[(size_t(y) * size_t(res) + size_t(x)) * 3 + size_t(k)] =
                    float(sum[k] / (kSub * kSub));
        }
    return out;
}

}  // namespace

std::shared_ptr<const EnvironmentMap> make_environment_map(const std::vector<float>& rgb_in,
                                                           int width, int height) {
    if (width <= 0 || height <= 0 || rgb_in.size() != size_t(width) * size_t(height) * 3)
        throw Error(fmt::format("an environment map needs RGB pixels ({} x {}, {} values)", width,
                                height, rgb_in.size()));
    for (float v : rgb_in)
        if (!std::isfinite(v)) throw Error("the environment map has NaN or infinite pixel values");
    std::vector<float> rgb;
    int res = 0;
    if (width == height) {
        res = width;
        rgb = rgb_in;
    } else if (width == 2 * height) {
        res = width;
        if (int64_t(res) * res > kMaxEnvironmentTexels)
            throw Error(
                fmt::format("a {} x {} lat-long map makes an equal-area map of {} x {} "
                            "texels, more than the limit of {}",
                            width, height, res, res, kMaxEnvironmentTexels));
        rgb = latlong_to_equal_area(rgb_in, width, height, res);
    } else {
        throw Error(
            fmt::format("the environment map is {} x {}: neither square (pbrt-v4's "
                        "equal-area layout) nor 2:1 (latitude-longitude)",
                        width, height));
    }
    if (int64_t(res) * res > kMaxEnvironmentTexels)
        throw Error(
            fmt::format("the environment map has {} x {} texels, more than the limit "
                        "of {}",
                        res, res, kMaxEnvironmentTexels));

    auto map = std::make_shared<EnvironmentMap>();
    map->res = res;
    map->illuminant = Spectrum(srgb_illuminant());
    const size_t n = size_t(res) * size_t(res);
    map->texels.resize(n);
    build_rgb_uplift_table();
    std::vector<Float> d(n);
    double sum_y = 0, upper = 0, sum_d = 0;
    map->coarse_res = std::min(res, 32);
    map->coarse_y.assign(size_t(map->coarse_res) * size_t(map->coarse_res), 0.f);
    for (size_t i = 0; i < n; ++i) {
        float* p = &rgb[i * 3];
        for (int k = 0; k < 3; ++k) p[k] = std::max(p[k], 0.f);  // pbrt-v4 clamps at zero
        map->texels[i] = rgb_unbounded_spectrum_interpolated(Rgb{p[0], p[1], p[2]});
        d[i] = (p[0] + p[1] + p[2]) / 3;
        sum_d += d[i];
        const Float y = luminance(p);
        sum_y += y;
        const int tx = int(i % size_t(res)), ty = int(i / size_t(res));
        const int cr = map->coarse_res;
        map->coarse_y[size_t(ty * cr / res) * size_t(cr) + size_t(tx * cr / res)] += float(y);
        const Vec3 w = equal_area_square_to_sphere(
            Point2((Float(tx) + Float(0.5)) / Float(res), (Float(ty) + Float(0.5)) / Float(res)));
        if (w.z > 0) upper += double(y) * w.z;
    }
    map->mean_y = Float(sum_y / double(n));
    // Each texel covers 4 pi / n steradians.
    map->upper_illuminance = Float(upper * 4 * kPi / double(n));
    map->distribution = Distribution2D(d, res, res);
    const double mean = sum_d / double(n);
    bool any = false;
    for (Float& v : d) {
        v = std::max(Float(0), Float(double(v) - mean));
        any = any || v > 0;
    }
    if (!any) std::fill(d.begin(), d.end(), Float(1));
    map->compensated = Distribution2D(d, res, res);
    return map;
}

SampledSpectrum EnvironmentMap::le(Point2 uv, const SampledWavelengths& lambda) const {
    const int tx = std::clamp(int(uv.x * Float(res)), 0, res - 1);
    const int ty = std::clamp(int(uv.y * Float(res)), 0, res - 1);
    const RgbUnboundedSpectrum& t = texels[size_t(ty) * size_t(res) + size_t(tx)];
    // The texel's scale * S(c0 l^2 + c1 l + c2) (spectrum/sigmoid.h) at the four wavelengths
    // at once, times the illuminant; |x| is clamped where S is 0 or 1 to float precision.
    const Float4 zero{};
    Float4 l;
    for (int i = 0; i < kSpectrumSamples; ++i) l[i] = lambda.lambda[i];
    Float4 x = (zero + t.c0) * l + t.c1;
    x = x * l + t.c2;
    const Float4 lim = zero + Float(1e18);
    x = x < -lim ? -lim : x;
    x = x > lim ? lim : x;
    Float4 q = Float(1) + x * x;
    for (int i = 0; i < kSpectrumSamples; ++i) q[i] = std::sqrt(q[i]);
    const Float4 sig = Float(0.5) + x / (Float(2) * q);
    return SampledSpectrum(sig * t.scale) * illuminant.sample(lambda);
}

Float InfinitePortal::pdf_through(Point3 from, Vec3 w) const {
    const Float den = dot(n, w);
    if (den == 0) return 0;
    const Float t = dot(n, p0 - from) / den;
    if (!(t > 0)) return 0;
    // Where the ray meets the portal's plane, in the parallelogram's (a, b) coordinates.
    const Vec3 q = from + w * t - p0;
    const Float g11 = dot(e1, e1), g13 = dot(e1, e3), g33 = dot(e3, e3);
    const Float det = g11 * g33 - g13 * g13;
    const Float q1 = dot(q, e1), q3 = dot(q, e3);
    const Float a = (g33 * q1 - g13 * q3) / det, b = (g11 * q3 - g13 * q1) / det;
    if (!(a >= 0 && a <= 1 && b >= 0 && b <= 1)) return 0;
    return t * t / (area * std::abs(den));
}

Float ImageInfiniteLight::map_pdf(Vec3 w, bool allow_incomplete_pdf) const {
    const Point2 uv = equal_area_sphere_to_square(normalize(light_from_world.vector(w)));
    const Float p = allow_incomplete_pdf ? map->compensated.pdf(uv) : map->distribution.pdf(uv);
    return p / (4 * kPi);
}

SampledSpectrum ImageInfiniteLight::le(Point3 origin, Vec3 dir, const SampledWavelengths& lambda,
                                       Float* pdf, bool allow_incomplete_pdf) const {
    const Point2 uv = equal_area_sphere_to_square(normalize(light_from_world.vector(dir)));
    if (pdf) {
        *pdf = (allow_incomplete_pdf ? map->compensated.pdf(uv) : map->distribution.pdf(uv)) /
               (4 * kPi);
        if (portal) *pdf = Float(0.5) * (*pdf + portal->pdf_through(origin, normalize(dir)));
    }
    if (portal && !(dot(portal->n, dir) > 0)) return SampledSpectrum(0);
    return map->le(uv, lambda) * scale;
}

std::optional<LightLiSample> ImageInfiniteLight::sample_li(const LightSampleContext& ctx, Point2 u,
                                                           const SampledWavelengths& lambda,
                                                           bool allow_incomplete_pdf) const {
    LightLiSample s;
    if (portal && u.x < Float(0.5)) {
        // Uniformly over the portal's area (u.x rescaled to [0, 1)).
        const Float a = std::min(u.x * 2, kOneMinusEpsilon);
        const Vec3 d = portal->p0 + portal->e1 * a + portal->e3 * u.y - ctx.p;
        const Float len = length(d);
        if (!(len > 0)) return std::nullopt;
        s.wi = d / len;
    } else {
        Point2 um = u;
        if (portal) um.x = std::min((u.x - Float(0.5)) * 2, kOneMinusEpsilon);
        Float map_pdf = 0;
        const Point2 uv = allow_incomplete_pdf ? map->compensated.sample(um, &map_pdf)
                                               : map->distribution.sample(um, &map_pdf);
        if (!(map_pdf > 0)) return std::nullopt;
        s.wi = normalize(world_from_light.vector(equal_area_square_to_sphere(uv)));
        if (!portal) {
            s.pdf_sa = map_pdf / (4 * kPi);
            s.L = map->le(uv, lambda) * scale;
        }
    }
    if (portal) {
        // The light reaches the scene only through the portal, from its outer side.
        if (!(dot(portal->n, s.wi) > 0)) return std::nullopt;
        s.pdf_sa = Float(0.5) * (map_pdf(s.wi, allow_incomplete_pdf) +
                                 portal->pdf_through(ctx.p, s.wi));
        if (!(s.pdf_sa > 0)) return std::nullopt;
        s.L = map->le(equal_area_sphere_to_square(normalize(light_from_world.vector(s.wi))),
                      lambda) *
              scale;
    }
    s.p_light = ctx.p + s.wi * (2 * scene_radius);
    s.at_infinity = true;
    return s;
}

Float ImageInfiniteLight::pdf_li(const LightSampleContext& ctx, Vec3 w,
                                 bool allow_incomplete_pdf) const {
    const Float p = map_pdf(w, allow_incomplete_pdf);
    return portal ? Float(0.5) * (p + portal->pdf_through(ctx.p, normalize(w))) : p;
}

Float ImageInfiniteLight::phi_y() const {
    if (portal) return portal_phi_y;
    // As the uniform light: radiance over the sphere of directions, through a disk of the
    // scene's radius (pbrt-v4's Phi), with the map's mean luminance.
    return 4 * kPi * kPi * sqr(scene_radius) * scale * map->mean_y *
           spectrum_to_photometric(map->illuminant);
}

}  // namespace sr
