#pragma once
/// Scene materials: a std::variant of plain structs that build the per-hit Bsdf.
#include <optional>
#include <variant>

#include "steradian/bsdf/bsdf.h"
#include "steradian/material/texture.h"

namespace sr {

/// pbrt-v4 "diffuse": Lambertian with a reflectance texture (clamped to [0, 1]).
struct DiffuseMaterial {
    int reflectance = -1;  ///< index into the scene's spectrum textures
};

/// pbrt-v4 "interface": marks a boundary without scattering; rays pass straight through.
struct InterfaceMaterial {};

using Material = std::variant<DiffuseMaterial, InterfaceMaterial>;

struct MaterialContext {
    const std::vector<SpectrumTexture>* spectrum_textures = nullptr;
    const std::vector<FloatTexture>* float_textures = nullptr;
};

/// The BSDF at hit h, or empty for interface materials (no scattering).
std::optional<Bsdf> make_bsdf(const Material& m, const MaterialContext& ctx, const SurfaceHit& h,
                              const SampledWavelengths& lambda);

}  // namespace sr
