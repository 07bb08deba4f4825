#pragma once
/// Textures: float- and spectrum-valued, a std::variant of plain structs each.
/// Image textures are MIP-mapped and filtered over the pixel's footprint as pbrt-v4 does
/// (point, bilinear, trilinear, EWA), looked up by (u, v) with pbrt-v4's uv mapping
/// (s = su * u + du, t = sv * v + dv; the image's first row is t = 1).
#include <memory>
#include <variant>

#include "steradian/core/transform.h"
#include "steradian/film/image_io.h"
#include "steradian/geometry/hit.h"
#include "steradian/spectrum/spectrum.h"

namespace sr {

enum class SpectrumKind { Albedo, Unbounded, Illuminant };

/// pbrt-v4's 2D texture mappings ("mapping" of a texture): (s, t) from the hit's (u, v)
/// ("uv": s = su u + du, t = sv v + dv), or from its position p in the texture's space
/// (the CTM at the Texture directive): "spherical" s = theta / pi, t = phi / 2 pi of p about
/// the origin (theta from +z); "cylindrical" s = (pi + atan2(y, x)) / 2 pi, t = z;
/// "planar" s = du + p . v1, t = dv + p . v2.
/// Texture coordinates (s, t) and their change from one pixel to the next in x and y.
struct TexCoord2 {
    Point2 st;
    Float dsdx = 0, dsdy = 0, dtdx = 0, dtdy = 0;
};

struct UvMapping {
    enum class Kind { Uv, Spherical, Cylindrical, Planar };
    Kind kind = Kind::Uv;
    Float su = 1, sv = 1, du = 0, dv = 0;
    Transform texture_from_world;  ///< not for Uv
    Vec3 v1{1, 0, 0}, v2{0, 1, 0};  ///< Planar
    Point2 map(Point2 uv) const { return {su * uv.x + du, sv * uv.y + dv}; }
    Point2 map(const SurfaceHit& h) const {
        if (kind == Kind::Uv) return map(h.uv);
        return map_position(h.p);
    }
    Point2 map_position(Point3 p_world) const;
    /// (s, t) and their derivatives from the hit's footprint (SurfaceHit::dudx, dpdx, ...):
    /// the chain rule through the mapping.
    TexCoord2 map_footprint(const SurfaceHit& h) const;
};

enum class WrapMode { Repeat, Clamp, Black };

/// pbrt-v4's MIP-map filters (an imagemap's "filter").
enum class TextureFilter { Point, Bilinear, Trilinear, Ewa };

/// An RGB or single-channel image in linear values, shared between textures, with its
/// MIP pyramid when build_pyramid() was called.
struct TextureImage {
    Image image;
    WrapMode wrap = WrapMode::Repeat;
    /// Levels 1, 2, ... of the pyramid (level 0 is `image`): each level ceil(w/2) x ceil(h/2)
    /// of the one below, every texel the exact area average of the texels it covers (so a
    /// level's mean is the image's), down to 1 x 1.
    std::vector<Image> pyramid;
    void build_pyramid();
    int levels() const { return 1 + int(pyramid.size()); }
    const Image& level(int i) const { return i == 0 ? image : pyramid[size_t(i) - 1]; }

    /// Bilinear lookup at (s, t) in [0,1]^2 texture space in level `lev`; returns up to 3
    /// channels (a single-channel image is replicated).
    Rgb bilerp(Point2 st, int lev = 0) const;
    /// Texel (x, y) of level `lev` (x right, y down), wrapped by the wrap mode.
    Rgb texel(int lev, int x, int y) const;
    /// pbrt-v4's MIPMap::Filter: the level is chosen from the footprint's width (twice its
    /// largest derivative); point, bilinear (at that level) or trilinear (between it and
    /// the next, except below level 1, as pbrt-v4); EWA: an elliptically weighted average
    /// (Heckbert 1989, Gaussian weights exp(-2 r^2) - exp(-2)) over the footprint's ellipse,
    /// its minor axis widened to at least major / max_aniso, at the level of the minor axis
    /// and the next, blended. A zero footprint is a bilinear lookup of level 0.
    Rgb filter(const TexCoord2& c, TextureFilter f, Float max_aniso) const;

private:
    Rgb ewa(int lev, Point2 st, Vec2 d0, Vec2 d1) const;
};

struct ConstantFloatTexture {
    Float value = 0;
    Float evaluate(const SurfaceHit&) const { return value; }
};

struct ImageFloatTexture {
    std::shared_ptr<const TextureImage> image;
    UvMapping mapping;
    Float scale = 1;
    bool invert = false;
    TextureFilter filter = TextureFilter::Bilinear;
    Float max_aniso = 8;
    Float evaluate(const SurfaceHit& h) const;
};

struct ScaleFloatTexture;
struct MixFloatTexture;
struct CheckerboardFloatTexture;
struct DirectionMixFloatTexture;

/// pbrt-v4's "bilerp": v00 (1 - s)(1 - t) + v10 s (1 - t) + v01 (1 - s) t + v11 s t.
struct BilerpFloatTexture {
    UvMapping mapping;
    Float v00 = 0, v01 = 1, v10 = 0, v11 = 1;
    Float evaluate(const SurfaceHit& h) const {
        const Point2 st = mapping.map(h);
        return (1 - st.x) * (1 - st.y) * v00 + st.x * (1 - st.y) * v10 +
               (1 - st.x) * st.y * v01 + st.x * st.y * v11;
    }
};

/// pbrt-v4's noise textures ("fbm", "wrinkled", "windy"), of the hit's position in the
/// texture's space (core/noise.h), with every octave (no ray differentials).
struct NoiseFloatTexture {
    enum class Kind { Fbm, Wrinkled, Windy };
    Kind kind = Kind::Fbm;
    Transform texture_from_world;
    int octaves = 8;
    Float omega = Float(0.5);  ///< "roughness"
    Float evaluate(const SurfaceHit& h) const;
};

struct DotsFloatTexture;

using FloatTexture = std::variant<ConstantFloatTexture, ImageFloatTexture, ScaleFloatTexture,
                                  MixFloatTexture, CheckerboardFloatTexture,
                                  DirectionMixFloatTexture, BilerpFloatTexture,
                                  NoiseFloatTexture, DotsFloatTexture>;

/// pbrt-v4's "dots": in the unit cell around integer (s, t) (s, t from the mapping) whose
/// noise at the cell's centre is positive, a disk of radius 0.35 centred within 0.15 of the
/// cell's middle (offset by noise); `inside` there, `outside` elsewhere.
bool dots_inside(const UvMapping& m, const SurfaceHit& h);
Float evaluate(const FloatTexture& t, const SurfaceHit& h);

/// pbrt-v4's 2D checkerboard: tex1 on the squares where floor(s) + floor(t) is even, tex2
/// on the others ((s, t) from the mapping). Returns the weight of tex2: 0 or 1 for a zero
/// footprint, else the checker pattern filtered over the footprint as pbrt-v4 filters it (a
/// separable triangle filter of half-width 1.5 x the largest derivative of s, and of t; its
/// closed-form integral).
Float checkerboard_weight(const UvMapping& m, const SurfaceHit& h);

/// Composite textures own copies of their inputs (textures are immutable once built).
struct ScaleFloatTexture {
    std::shared_ptr<const FloatTexture> tex, scale;
    Float evaluate(const SurfaceHit& h) const;
};
/// (1 - amount) tex1 + amount tex2.
struct MixFloatTexture {
    std::shared_ptr<const FloatTexture> tex1, tex2, amount;
    Float evaluate(const SurfaceHit& h) const;
};
struct CheckerboardFloatTexture {
    std::shared_ptr<const FloatTexture> tex1, tex2;
    UvMapping mapping;
    Float evaluate(const SurfaceHit& h) const;
};
struct DotsFloatTexture {
    UvMapping mapping;
    std::shared_ptr<const FloatTexture> inside, outside;
    Float evaluate(const SurfaceHit& h) const;
};
/// pbrt-v4's "directionmix": a tex1 + (1 - a) tex2 with a = |ng . dir| (dir: unit, world).
struct DirectionMixFloatTexture {
    std::shared_ptr<const FloatTexture> tex1, tex2;
    Vec3 dir{0, 1, 0};
    Float evaluate(const SurfaceHit& h) const;
};

struct ConstantSpectrumTexture {
    Spectrum value;
    SampledSpectrum evaluate(const SurfaceHit&, const SampledWavelengths& lambda) const {
        return value.sample(lambda);
    }
};

struct ImageSpectrumTexture {
    std::shared_ptr<const TextureImage> image;
    UvMapping mapping;
    Float scale = 1;
    bool invert = false;
    TextureFilter filter = TextureFilter::Bilinear;
    Float max_aniso = 8;
    SpectrumKind kind = SpectrumKind::Albedo;
    SampledSpectrum evaluate(const SurfaceHit& h, const SampledWavelengths& lambda) const;
};

struct ScaleSpectrumTexture;
struct MixSpectrumTexture;
struct CheckerboardSpectrumTexture;
struct DirectionMixSpectrumTexture;

/// pbrt-v4's "bilerp" of four spectra, weighted as BilerpFloatTexture.
struct BilerpSpectrumTexture {
    UvMapping mapping;
    Spectrum v00, v01, v10, v11;
    SampledSpectrum evaluate(const SurfaceHit& h, const SampledWavelengths& lambda) const;
};

struct DotsSpectrumTexture;

/// pbrt-v4's "marble": m = p.y + variation fbm(p, omega, octaves) of the position p in the
/// texture's space times `scale` (the noise band-limited by the footprint), t = (1 + sin m)
/// / 2, and the colour 1.5 x pbrt-v4's marble spline at t, an sRGB albedo.
struct MarbleSpectrumTexture {
    Transform texture_from_world;
    int octaves = 8;
    Float omega = Float(0.5), scale = 1, variation = Float(0.2);
    SampledSpectrum evaluate(const SurfaceHit& h, const SampledWavelengths& lambda) const;
};

using SpectrumTexture = std::variant<ConstantSpectrumTexture, ImageSpectrumTexture,
                                     ScaleSpectrumTexture, MixSpectrumTexture,
                                     CheckerboardSpectrumTexture, DirectionMixSpectrumTexture,
                                     BilerpSpectrumTexture, DotsSpectrumTexture,
                                     MarbleSpectrumTexture>;
SampledSpectrum evaluate(const SpectrumTexture& t, const SurfaceHit& h,
                         const SampledWavelengths& lambda);

/// tex * scale (scale a float texture).
struct ScaleSpectrumTexture {
    std::shared_ptr<const SpectrumTexture> tex;
    std::shared_ptr<const FloatTexture> scale;
    SampledSpectrum evaluate(const SurfaceHit& h, const SampledWavelengths& lambda) const;
};
/// (1 - amount) tex1 + amount tex2, amount a float texture.
struct MixSpectrumTexture {
    std::shared_ptr<const SpectrumTexture> tex1, tex2;
    std::shared_ptr<const FloatTexture> amount;
    SampledSpectrum evaluate(const SurfaceHit& h, const SampledWavelengths& lambda) const;
};
struct CheckerboardSpectrumTexture {
    std::shared_ptr<const SpectrumTexture> tex1, tex2;
    UvMapping mapping;
    SampledSpectrum evaluate(const SurfaceHit& h, const SampledWavelengths& lambda) const;
};

/// pbrt-v4's "directionmix" of two spectrum textures (as DirectionMixFloatTexture).
struct DirectionMixSpectrumTexture {
    std::shared_ptr<const SpectrumTexture> tex1, tex2;
    Vec3 dir{0, 1, 0};
    SampledSpectrum evaluate(const SurfaceHit& h, const SampledWavelengths& lambda) const;
};

/// pbrt-v4's "dots" of two spectrum textures (as DotsFloatTexture).
struct DotsSpectrumTexture {
    UvMapping mapping;
    std::shared_ptr<const SpectrumTexture> inside, outside;
    SampledSpectrum evaluate(const SurfaceHit& h, const SampledWavelengths& lambda) const;
};

}  // namespace sr
