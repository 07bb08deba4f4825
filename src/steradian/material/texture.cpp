#include "steradian/material/texture.h"

#include "steradian/material/noise.h"

namespace sr {

Point2 UvMapping::map_position(Point3 p_world) const {
    const Point3 p = texture_from_world.point(p_world);
    switch (kind) {
        case Kind::Spherical: {
            const Float r = length(Vec3(p.x, p.y, p.z));
            if (!(r > 0)) return {0, 0};
            const Float theta = std::acos(std::clamp(p.z / r, Float(-1), Float(1)));
            Float phi = std::atan2(p.y, p.x);
            if (phi < 0) phi += 2 * kPi;
            return {theta / kPi, phi / (2 * kPi)};
        }
        case Kind::Cylindrical:
            return {(kPi + std::atan2(p.y, p.x)) / (2 * kPi), p.z};
        case Kind::Planar: {
            const Vec3 v(p.x, p.y, p.z);
            return {du + dot(v, v1), dv + dot(v, v2)};
        }
        case Kind::Uv: break;
    }
    return {0, 0};
}

namespace {
bool remap(int& i, int n, WrapMode wrap) {
    if (i >= 0 && i < n) return true;
    switch (wrap) {
        case WrapMode::Repeat: i = ((i % n) + n) % n; return true;
        case WrapMode::Clamp: i = clamp(i, 0, n - 1); return true;
        case WrapMode::Black: return false;
    }
    return false;
}
}  // namespace

Rgb TextureImage::bilerp(Point2 st) const {
    const int w = image.width, h = image.height, nc = image.channels;
    // Texel centres at half-integers; t = 1 is the top row.
    Float x = st.x * w - Float(0.5), y = (1 - st.y) * h - Float(0.5);
    int xi = int(std::floor(x)), yi = int(std::floor(y));
    Float dx = x - xi, dy = y - yi;
    Rgb acc;
    const Float wts[4] = {(1 - dx) * (1 - dy), dx * (1 - dy), (1 - dx) * dy, dx * dy};
    const int ox[4] = {0, 1, 0, 1}, oy[4] = {0, 0, 1, 1};
    for (int k = 0; k < 4; ++k) {
        int px = xi + ox[k], py = yi + oy[k];
        if (!remap(px, w, wrap) || !remap(py, h, wrap)) continue;
        Rgb v;
        if (nc >= 3) {
            v = {image.at(px, py, 0), image.at(px, py, 1), image.at(px, py, 2)};
        } else {
            Float g = image.at(px, py, 0);
            v = {g, g, g};
        }
        acc = acc + v * wts[k];
    }
    return acc;
}

Float ImageFloatTexture::evaluate(const SurfaceHit& h) const {
    Rgb c = image->bilerp(mapping.map(h));
    Float v = (c.r + c.g + c.b) / 3 * scale;
    return invert ? std::max(Float(0), 1 - v) : v;
}

SampledSpectrum ImageSpectrumTexture::evaluate(const SurfaceHit& h,
                                               const SampledWavelengths& lambda) const {
    Rgb c = image->bilerp(mapping.map(h)) * scale;
    if (invert) c = {std::max(Float(0), 1 - c.r), std::max(Float(0), 1 - c.g), std::max(Float(0), 1 - c.b)};
    switch (kind) {
        case SpectrumKind::Albedo: {
            c = {clamp(c.r, Float(0), Float(1)), clamp(c.g, Float(0), Float(1)), clamp(c.b, Float(0), Float(1))};
            return Spectrum(rgb_albedo_spectrum_interpolated(c)).sample(lambda);
        }
        case SpectrumKind::Unbounded: return Spectrum(rgb_unbounded_spectrum_interpolated(c)).sample(lambda);
        case SpectrumKind::Illuminant: return Spectrum(rgb_illuminant_spectrum_interpolated(c)).sample(lambda);
    }
    return SampledSpectrum(0);
}

Float ScaleFloatTexture::evaluate(const SurfaceHit& h) const {
    Float sc = sr::evaluate(*scale, h);
    return sc == 0 ? 0 : sr::evaluate(*tex, h) * sc;
}

Float MixFloatTexture::evaluate(const SurfaceHit& h) const {
    Float a = sr::evaluate(*amount, h);
    Float v1 = a != 1 ? sr::evaluate(*tex1, h) : 0, v2 = a != 0 ? sr::evaluate(*tex2, h) : 0;
    return (1 - a) * v1 + a * v2;
}

Float CheckerboardFloatTexture::evaluate(const SurfaceHit& h) const {
    return sr::evaluate(checkerboard_even(mapping, h) ? *tex1 : *tex2, h);
}

SampledSpectrum ScaleSpectrumTexture::evaluate(const SurfaceHit& h,
                                               const SampledWavelengths& lambda) const {
    Float sc = sr::evaluate(*scale, h);
    return sc == 0 ? SampledSpectrum(0) : sr::evaluate(*tex, h, lambda) * sc;
}

SampledSpectrum MixSpectrumTexture::evaluate(const SurfaceHit& h,
                                             const SampledWavelengths& lambda) const {
    Float a = sr::evaluate(*amount, h);
    SampledSpectrum r(0);
    if (a != 1) r += sr::evaluate(*tex1, h, lambda) * (1 - a);
    if (a != 0) r += sr::evaluate(*tex2, h, lambda) * a;
    return r;
}

SampledSpectrum CheckerboardSpectrumTexture::evaluate(const SurfaceHit& h,
                                                      const SampledWavelengths& lambda) const {
    return sr::evaluate(checkerboard_even(mapping, h) ? *tex1 : *tex2, h, lambda);
}

Float DirectionMixFloatTexture::evaluate(const SurfaceHit& h) const {
    const Float a = std::abs(dot(Vec3(h.ng.x, h.ng.y, h.ng.z), dir));
    const Float t1 = a != 0 ? sr::evaluate(*tex1, h) : 0, t2 = a != 1 ? sr::evaluate(*tex2, h) : 0;
    return a * t1 + (1 - a) * t2;
}

SampledSpectrum DirectionMixSpectrumTexture::evaluate(const SurfaceHit& h,
                                                      const SampledWavelengths& lambda) const {
    const Float a = std::abs(dot(Vec3(h.ng.x, h.ng.y, h.ng.z), dir));
    SampledSpectrum r(0);
    if (a != 0) r += sr::evaluate(*tex1, h, lambda) * a;
    if (a != 1) r += sr::evaluate(*tex2, h, lambda) * (1 - a);
    return r;
}

SampledSpectrum BilerpSpectrumTexture::evaluate(const SurfaceHit& h,
                                                const SampledWavelengths& lambda) const {
    const Point2 st = mapping.map(h);
    return v00.sample(lambda) * ((1 - st.x) * (1 - st.y)) + v10.sample(lambda) * (st.x * (1 - st.y)) +
           v01.sample(lambda) * ((1 - st.x) * st.y) + v11.sample(lambda) * (st.x * st.y);
}

Float NoiseFloatTexture::evaluate(const SurfaceHit& h) const {
    const Point3 p = texture_from_world.point(h.p);
    switch (kind) {
        case Kind::Fbm: return fbm(p, omega, octaves);
        case Kind::Wrinkled: return turbulence(p, omega, octaves);
        case Kind::Windy: {
            const Float wind = fbm(Point3(p.x * Float(0.1), p.y * Float(0.1), p.z * Float(0.1)),
                                   Float(0.5), 3);
            return std::abs(wind) * fbm(p, Float(0.5), 6);
        }
    }
    return 0;
}

bool dots_inside(const UvMapping& m, const SurfaceHit& h) {
    const Point2 st = m.map(h);
    const Float s_cell = std::floor(st.x + Float(0.5)), t_cell = std::floor(st.y + Float(0.5));
    if (!(perlin_noise(s_cell + Float(0.5), t_cell + Float(0.5)) > 0)) return false;
    constexpr Float kRadius = Float(0.35), kMaxShift = Float(0.5) - kRadius;
    const Float s_center = s_cell + kMaxShift * perlin_noise(s_cell + Float(1.5), t_cell + Float(2.8));
    const Float t_center = t_cell + kMaxShift * perlin_noise(s_cell + Float(4.5), t_cell + Float(9.8));
    return sqr(st.x - s_center) + sqr(st.y - t_center) < sqr(kRadius);
}

Float DotsFloatTexture::evaluate(const SurfaceHit& h) const {
    return sr::evaluate(dots_inside(mapping, h) ? *inside : *outside, h);
}

SampledSpectrum DotsSpectrumTexture::evaluate(const SurfaceHit& h,
                                              const SampledWavelengths& lambda) const {
    return sr::evaluate(dots_inside(mapping, h) ? *inside : *outside, h, lambda);
}

Float evaluate(const FloatTexture& t, const SurfaceHit& h) {
    return std::visit([&](const auto& x) { return x.evaluate(h); }, t);
}

SampledSpectrum evaluate(const SpectrumTexture& t, const SurfaceHit& h,
                         const SampledWavelengths& lambda) {
    return std::visit([&](const auto& x) { return x.evaluate(h, lambda); }, t);
}

}  // namespace sr
