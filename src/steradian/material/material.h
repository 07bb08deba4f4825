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

/// Microfacet roughness as float-texture indices (u along dpdu, v across), optionally
/// remapped from pbrt's perceptual "roughness" to alpha (remaproughness, default true).
struct Roughness {
    int u = -1, v = -1;
    bool remap = true;
};

/// pbrt-v4 "dielectric": Fresnel reflection and refraction, smooth or rough. A tabulated
/// (wavelength-dependent) eta disperses: the path keeps only its hero wavelength.
struct DielectricMaterial {
    Spectrum eta;
    bool dispersive = false;
    Roughness roughness;
};

/// pbrt-v4 "thindielectric": a pane with all internal reflections summed.
struct ThinDielectricMaterial {
    Spectrum eta;
    bool dispersive = false;
};

/// pbrt-v4 "conductor": complex Fresnel reflection with spectral eta and k, or the
/// "reflectance" form (eta = 1, k chosen so the normal-incidence reflectance is r).
struct ConductorMaterial {
    Spectrum eta, k;
    int reflectance = -1;  ///< spectrum texture; when >= 0 it replaces eta and k
    Roughness roughness;
};

/// pbrt-v4 "diffusetransmission": Lambertian reflection and transmission (lamp shades).
struct DiffuseTransmissionMaterial {
    int reflectance = -1, transmittance = -1;  ///< spectrum textures
    Float scale = 1;
};

using Material = std::variant<DiffuseMaterial, InterfaceMaterial, DielectricMaterial,
                              ThinDielectricMaterial, ConductorMaterial,
                              DiffuseTransmissionMaterial>;

struct MaterialContext {
    const std::vector<SpectrumTexture>* spectrum_textures = nullptr;
    const std::vector<FloatTexture>* float_textures = nullptr;
};

/// The BSDF at hit h, or empty for interface materials (no scattering). A dispersive
/// material terminates the secondary wavelengths of `lambda`.
std::optional<Bsdf> make_bsdf(const Material& m, const MaterialContext& ctx, const SurfaceHit& h,
                              SampledWavelengths& lambda);

}  // namespace sr
