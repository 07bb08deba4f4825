#pragma once
/// Shared BSDF vocabulary: transport mode, lobe flags, and the sample record.
/// All directions are in the local shading frame (z = shading normal); wo and wi both
/// point away from the surface.
#include <cstdint>
#include <optional>

#include "steradian/core/math.h"
#include "steradian/spectrum/sampled.h"

namespace sr {

/// Which quantity the path carries: radiance (camera paths) or importance (light paths).
enum class TransportMode : uint8_t { Radiance, Importance };

enum LobeFlags : uint8_t {
    kLobeNone = 0,
    kLobeReflection = 1 << 0,
    kLobeTransmission = 1 << 1,
    kLobeDiffuse = 1 << 2,
    kLobeGlossy = 1 << 3,
    kLobeSpecular = 1 << 4,
};

/// A sampled direction: f is the BSDF value (no cosine), pdf_sa the solid-angle pdf of wi
/// (for specular lobes, the discrete probability, and f carries the delta's weight).
/// eta is the relative IOR across the boundary for transmission, 1 otherwise.
struct BsdfSample {
    SampledSpectrum f;
    Vec3 wi;
    Float pdf_sa = 0;
    uint8_t flags = kLobeNone;
    Float eta = 1;
    /// |cos(theta_i)| / pdf_sa where the lobe knows it in closed form (Lambert: pi), so that
    /// the path's weight f |cos| / pdf needs no division; 0: compute it from wi and pdf_sa.
    /// Whoever changes pdf_sa or wi of a sample must reset it.
    Float cos_over_pdf = 0;
    bool is_specular() const { return flags & kLobeSpecular; }
    bool is_transmission() const { return flags & kLobeTransmission; }
    bool is_reflection() const { return flags & kLobeReflection; }
};

}  // namespace sr
