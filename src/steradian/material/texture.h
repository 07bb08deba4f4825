#pragma once
/// Textures: float- and spectrum-valued, a std::variant of plain structs each.
/// Image textures are bilinearly filtered, looked up by (u, v) with pbrt-v4's uv mapping
/// (s = su * u + du, t = sv * v + dv; the image's first row is t = 1).
#include <memory>
#include <variant>

#include "steradian/film/image_io.h"
#include "steradian/geometry/hit.h"
#include "steradian/spectrum/spectrum.h"

namespace sr {

enum class SpectrumKind { Albedo, Unbounded, Illuminant };

struct UvMapping {
    Float su = 1, sv = 1, du = 0, dv = 0;
    Point2 map(Point2 uv) const { return {su * uv.x + du, sv * uv.y + dv}; }
};

enum class WrapMode { Repeat, Clamp, Black };

/// An RGB or single-channel image in linear values, shared between textures.
struct TextureImage {
    Image image;
    WrapMode wrap = WrapMode::Repeat;
    /// Bilinear lookup at (s, t) in [0,1]^2 texture space; returns up to 3 channels
    /// (a single-channel image is replicated).
    Rgb bilerp(Point2 st) const;
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
    Float evaluate(const SurfaceHit& h) const;
};

using FloatTexture = std::variant<ConstantFloatTexture, ImageFloatTexture>;
Float evaluate(const FloatTexture& t, const SurfaceHit& h);

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
    SpectrumKind kind = SpectrumKind::Albedo;
    SampledSpectrum evaluate(const SurfaceHit& h, const SampledWavelengths& lambda) const;
};

using SpectrumTexture = std::variant<ConstantSpectrumTexture, ImageSpectrumTexture>;
SampledSpectrum evaluate(const SpectrumTexture& t, const SurfaceHit& h,
                         const SampledWavelengths& lambda);

}  // namespace sr
