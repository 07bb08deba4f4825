#include "steradian/material/texture.h"

#include "steradian/core/noise.h"

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

TexCoord2 UvMapping::map_footprint(const SurfaceHit& h) const {
    TexCoord2 c;
    if (kind == Kind::Uv) {
        c.st = map(h.uv);
        c.dsdx = su * h.dudx;
        c.dsdy = su * h.dudy;
        c.dtdx = sv * h.dvdx;
        c.dtdy = sv * h.dvdy;
        return c;
    }
    c.st = map_position(h.p);
    // The gradients of s and t with respect to the texture-space position, then the chain
    // rule with the footprint's dp.
    const Point3 p = texture_from_world.point(h.p);
    const Vec3 dpx = texture_from_world.vector(h.dpdx), dpy = texture_from_world.vector(h.dpdy);
    Vec3 gs(0, 0, 0), gt(0, 0, 0);
    const Float rxy2 = p.x * p.x + p.y * p.y;
    switch (kind) {
        case Kind::Spherical: {
            // s = theta / pi, theta = acos(z / r): dtheta = (x z, y z, -(x^2 + y^2)) /
            // (r^2 sqrt(x^2 + y^2)); t = phi / 2 pi, dphi = (-y, x, 0) / (x^2 + y^2).
            const Float r2 = rxy2 + p.z * p.z, rxy = std::sqrt(rxy2);
            if (rxy2 > 0 && r2 > 0) {
                gs = Vec3(p.x * p.z, p.y * p.z, -rxy2) / (kPi * r2 * rxy);
                gt = Vec3(-p.y, p.x, 0) / (2 * kPi * rxy2);
            }
            break;
        }
        case Kind::Cylindrical:
            if (rxy2 > 0) gs = Vec3(-p.y, p.x, 0) / (2 * kPi * rxy2);
            gt = Vec3(0, 0, 1);
            break;
        case Kind::Planar:
            gs = v1;
            gt = v2;
            break;
        case Kind::Uv: break;
    }
    c.dsdx = dot(gs, dpx);
    c.dsdy = dot(gs, dpy);
    c.dtdx = dot(gt, dpx);
    c.dtdy = dot(gt, dpy);
    return c;
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

/// The source texels output texel i of n_out covers in a row of n_in (an exact box filter
/// of width n_in / n_out): (index, weight) pairs whose weights sum to 1.
std::vector<std::pair<int, Float>> box_weights(int i, int n_in, int n_out) {
    const double w = double(n_in) / n_out, a = i * w, b = (i + 1) * w;
    std::vector<std::pair<int, Float>> r;
    for (int j = int(std::floor(a)); j < n_in && j < b; ++j) {
        const double overlap = std::min(b, double(j + 1)) - std::max(a, double(j));
        if (overlap > 0) r.emplace_back(j, Float(overlap / w));
    }
    return r;
}

/// One level of the pyramid from the one below: a separable exact box filter.
Image half_level(const Image& src) {
    const int w = std::max(1, (src.width + 1) / 2), h = std::max(1, (src.height + 1) / 2);
    const int nc = src.channels;
    Image rows;  // src.width -> w
    rows.width = w;
    rows.height = src.height;
    rows.channels = nc;
    rows.data.assign(size_t(w) * src.height * nc, 0.f);
    for (int x = 0; x < w; ++x) {
        const auto bw = box_weights(x, src.width, w);
        for (int y = 0; y < src.height; ++y)
            for (int c = 0; c < nc; ++c) {
                double acc = 0;
                for (auto [j, wt] : bw) acc += double(wt) * src.at(j, y, c);
                rows.at(x, y, c) = float(acc);
            }
    }
    Image out;
    out.width = w;
    out.height = h;
    out.channels = nc;
    out.data.assign(size_t(w) * h * nc, 0.f);
    for (int y = 0; y < h; ++y) {
        const auto bw = box_weights(y, src.height, h);
        for (int x = 0; x < w; ++x)
            for (int c = 0; c < nc; ++c) {
                double acc = 0;
                for (auto [j, wt] : bw) acc += double(wt) * rows.at(x, j, c);
                out.at(x, y, c) = float(acc);
            }
    }
    return out;
}
}  // namespace

void TextureImage::build_pyramid() {
    pyramid.clear();
    const Image* prev = &image;
    while (prev->width > 1 || prev->height > 1) {
        pyramid.push_back(half_level(*prev));
        prev = &pyramid.back();
    }
}

Rgb TextureImage::texel(int lev, int x, int y) const {
    const Image& im = level(lev);
    if (!remap(x, im.width, wrap) || !remap(y, im.height, wrap)) return {};
    if (im.channels >= 3) return {im.at(x, y, 0), im.at(x, y, 1), im.at(x, y, 2)};
    const Float g = im.at(x, y, 0);
    return {g, g, g};
}

Rgb TextureImage::bilerp(Point2 st, int lev) const {
    const Image& im = level(lev);
    // Texel centres at half-integers; t = 1 is the top row.
    Float x = st.x * im.width - Float(0.5), y = (1 - st.y) * im.height - Float(0.5);
    int xi = int(std::floor(x)), yi = int(std::floor(y));
    Float dx = x - xi, dy = y - yi;
    return texel(lev, xi, yi) * ((1 - dx) * (1 - dy)) + texel(lev, xi + 1, yi) * (dx * (1 - dy)) +
           texel(lev, xi, yi + 1) * ((1 - dx) * dy) + texel(lev, xi + 1, yi + 1) * (dx * dy);
}

Rgb TextureImage::filter(const TexCoord2& c, TextureFilter f, Float max_aniso) const {
    const int n_levels = levels();
    if (f != TextureFilter::Ewa) {
        const Float width = 2 * std::max({std::abs(c.dsdx), std::abs(c.dtdx), std::abs(c.dsdy),
                                          std::abs(c.dtdy)});
        // The level whose texels are as wide as the footprint (width in [0, 1] texture
        // units; level L - 1 has one texel). Without a pyramid, level 0.
        const Float lev = n_levels == 1 ? Float(-1)
                                        : Float(n_levels - 1) +
                                              std::log2(std::max(width, Float(1e-8)));
        if (lev >= Float(n_levels - 1)) return texel(n_levels - 1, 0, 0);
        const int il = std::max(0, int(std::floor(lev)));
        switch (f) {
            case TextureFilter::Point: {
                const Image& im = level(il);
                return texel(il, int(std::lround(c.st.x * im.width - Float(0.5))),
                             int(std::lround((1 - c.st.y) * im.height - Float(0.5))));
            }
            case TextureFilter::Bilinear: return bilerp(c.st, il);
            case TextureFilter::Trilinear: {
                // As pbrt-v4: below level 1 the finest level alone.
                if (il == 0) return bilerp(c.st, 0);
                const Float t = lev - Float(il);
                return bilerp(c.st, il) * (1 - t) + bilerp(c.st, il + 1) * t;
            }
            case TextureFilter::Ewa: break;
        }
    }
    Vec2 d0(c.dsdx, c.dtdx), d1(c.dsdy, c.dtdy);
    auto len2 = [](Vec2 v) { return v.x * v.x + v.y * v.y; };
    if (len2(d0) < len2(d1)) std::swap(d0, d1);
    const Float major = std::sqrt(len2(d0));
    Float minor = std::sqrt(len2(d1));
    if (minor * max_aniso < major && minor > 0) {
        const Float sc = major / (minor * max_aniso);
        d1 = d1 * sc;
        minor *= sc;
    }
    if (!(minor > 0) || n_levels == 1) return bilerp(c.st, 0);
    const Float lod = std::max(Float(0), Float(n_levels - 1) + std::log2(minor));
    const int il = int(std::floor(lod));
    const Float t = lod - Float(il);
    const Rgb a = ewa(il, c.st, d0, d1);
    return t == 0 ? a : a * (1 - t) + ewa(il + 1, c.st, d0, d1) * t;
}

Rgb TextureImage::ewa(int lev, Point2 st, Vec2 d0, Vec2 d1) const {
    if (lev >= levels() - 1) return texel(levels() - 1, 0, 0);
    const Image& im = level(lev);
    const Float w = Float(im.width), h = Float(im.height);
    // The ellipse's centre and axes in this level's texel units (y down).
    const Float x0 = st.x * w - Float(0.5), y0 = (1 - st.y) * h - Float(0.5);
    const Float ax = d0.x * w, ay = -d0.y * h, bx = d1.x * w, by = -d1.y * h;
    // Implicit ellipse A x^2 + B x y + C y^2 <= 1 with the axes (ax, ay), (bx, by), each
    // squared length grown by one texel so that at least one texel centre falls inside.
    Float A = ay * ay + by * by + 1, B = -2 * (ax * ay + bx * by), C = ax * ax + bx * bx + 1;
    const Float F = A * C - B * B / 4;
    if (!(F > 0)) return bilerp(st, lev);
    A /= F;
    B /= F;
    C /= F;
    const Float det = 4 * A * C - B * B;
    const Float ext_x = 2 * std::sqrt(C / det), ext_y = 2 * std::sqrt(A / det);
    const int xa = int(std::ceil(x0 - ext_x)), xb = int(std::floor(x0 + ext_x));
    const int ya = int(std::ceil(y0 - ext_y)), yb = int(std::floor(y0 + ext_y));
    Rgb sum;
    Float wsum = 0;
    const Float floor_w = std::exp(Float(-2));
    for (int y = ya; y <= yb; ++y) {
        const Float dy = Float(y) - y0;
        for (int x = xa; x <= xb; ++x) {
            const Float dx = Float(x) - x0;
            const Float r2 = A * dx * dx + B * dx * dy + C * dy * dy;
            if (r2 >= 1) continue;
            const Float wt = std::exp(-2 * r2) - floor_w;
            sum = sum + texel(lev, x, y) * wt;
            wsum += wt;
        }
    }
    return wsum > 0 ? sum * (1 / wsum) : bilerp(st, lev);
}

Float ImageFloatTexture::evaluate(const SurfaceHit& h) const {
    Rgb c = image->filter(mapping.map_footprint(h), filter, max_aniso);
    Float v = (c.r + c.g + c.b) / 3 * scale;
    return invert ? std::max(Float(0), 1 - v) : v;
}

SampledSpectrum ImageSpectrumTexture::evaluate(const SurfaceHit& h,
                                               const SampledWavelengths& lambda) const {
    Rgb c = image->filter(mapping.map_footprint(h), filter, max_aniso) * scale;
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

namespace {
/// D with D'' = q, q(x) = +1 on [2k, 2k + 1), -1 on [2k + 1, 2k + 2) (the 1D checker):
/// D(x) = floor(x / 2) + D0(f), f = x mod 2, D0 = f^2 / 2 on [0, 1), 2 f - f^2 / 2 - 1 on
/// [1, 2) (one period of the integral of the triangle wave adds 1).
double checker_d(double x) {
    const double k = std::floor(x / 2), f = x - 2 * k;
    return k + (f < 1 ? f * f / 2 : 2 * f - f * f / 2 - 1);
}
/// q convolved with a unit-area triangle filter of half-width r centred at x:
/// (D(x + r) - 2 D(x) + D(x - r)) / r^2; q(x) itself where the filter stays in one cell.
double checker_filtered(double x, double r) {
    if (std::floor(x - r) == std::floor(x + r)) return (int64_t(std::floor(x)) & 1) ? -1 : 1;
    return (checker_d(x + r) - 2 * checker_d(x) + checker_d(x - r)) / (r * r);
}
}  // namespace

Float checkerboard_weight(const UvMapping& m, const SurfaceHit& h) {
    const TexCoord2 c = m.map_footprint(h);
    // pbrt-v4's filter: a triangle of half-width 1.5 times the larger derivative, per axis.
    const double rs = 1.5 * std::max(std::abs(c.dsdx), std::abs(c.dsdy));
    const double rt = 1.5 * std::max(std::abs(c.dtdx), std::abs(c.dtdy));
    const double qs = rs > 0 ? checker_filtered(c.st.x, rs) : checker_filtered(c.st.x, 0);
    const double qt = rt > 0 ? checker_filtered(c.st.y, rt) : checker_filtered(c.st.y, 0);
    return Float(std::clamp(0.5 - qs * qt / 2, 0.0, 1.0));
}

Float CheckerboardFloatTexture::evaluate(const SurfaceHit& h) const {
    const Float w = checkerboard_weight(mapping, h);
    const Float a = w != 1 ? sr::evaluate(*tex1, h) : 0, b = w != 0 ? sr::evaluate(*tex2, h) : 0;
    return (1 - w) * a + w * b;
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
    const Float w = checkerboard_weight(mapping, h);
    SampledSpectrum r(0);
    if (w != 1) r += sr::evaluate(*tex1, h, lambda) * (1 - w);
    if (w != 0) r += sr::evaluate(*tex2, h, lambda) * w;
    return r;
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
    const Vec3 dx = texture_from_world.vector(h.dpdx), dy = texture_from_world.vector(h.dpdy);
    switch (kind) {
        case Kind::Fbm: return fbm(p, dx, dy, omega, octaves);
        case Kind::Wrinkled: return turbulence(p, dx, dy, omega, octaves);
        case Kind::Windy: {
            const Float k = Float(0.1);
            const Float wind = fbm(p * k, dx * k, dy * k, Float(0.5), 3);
            return std::abs(wind) * fbm(p, dx, dy, Float(0.5), 6);
        }
    }
    return 0;
}

SampledSpectrum MarbleSpectrumTexture::evaluate(const SurfaceHit& h,
                                                const SampledWavelengths& lambda) const {
    const Point3 p = texture_from_world.point(h.p) * scale;
    const Vec3 dx = texture_from_world.vector(h.dpdx) * scale;
    const Vec3 dy = texture_from_world.vector(h.dpdy) * scale;
    const Float marble = p.y + variation * fbm(p, dx, dy, omega, octaves);
    Float t = Float(0.5) + Float(0.5) * std::sin(marble);
    // pbrt-v4's marble colour spline (textures.cpp, MarbleTexture::Evaluate): nine sRGB
    // control points, evaluated as the cubic Bezier segment of four consecutive ones that
    // t falls in, times 1.5.
    static constexpr Float kColors[9][3] = {
        {.58f, .58f, .6f}, {.58f, .58f, .6f}, {.58f, .58f, .6f}, {.5f, .5f, .5f},  {.6f, .59f, .58f},
        {.58f, .58f, .6f}, {.58f, .58f, .6f}, {.2f, .2f, .33f},  {.58f, .58f, .6f}};
    constexpr int kSegments = 9 - 3;
    const int first = std::min(int(std::floor(t * kSegments)), kSegments - 1);
    t = t * kSegments - Float(first);
    const Float b[4] = {(1 - t) * (1 - t) * (1 - t), 3 * (1 - t) * (1 - t) * t, 3 * (1 - t) * t * t,
                        t * t * t};
    Float rgb[3] = {0, 0, 0};
    for (int i = 0; i < 4; ++i)
        for (int c = 0; c < 3; ++c) rgb[c] += Float(1.5) * b[i] * kColors[first + i][c];
    const Rgb c{clamp(rgb[0], Float(0), Float(1)), clamp(rgb[1], Float(0), Float(1)),
                clamp(rgb[2], Float(0), Float(1))};
    return Spectrum(rgb_albedo_spectrum_interpolated(c)).sample(lambda);
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
