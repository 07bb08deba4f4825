#pragma once
/// The generalised cosine-lobe model of E. P. F. Lafortune, S.-C. Foo, K. E. Torrance and
/// D. P. Greenberg, "Non-Linear Approximation of Reflectance Functions" (SIGGRAPH 1997), a
/// steradian extension (pbrt-v4 has none):
///
///   f(wo, wi) = rho_d / pi + sum_i rho_s,i max(0, Cx,i wo.x wi.x + Cy,i wo.y wi.y
///                                              + Cz,i wo.z wi.z)^(n_i)
///
/// in the shading frame (x along dpdu). The bracket is symmetric in wo and wi, so f is
/// reciprocal. Cx = Cy = -Cz gives a Phong lobe about the mirror direction; |Cx| > Cz an
/// off-specular peak growing towards grazing; Cx, Cy > 0 retro-reflection; Cx != Cy
/// anisotropy; Cx = Cy = 0 a lobe about the normal. rho_s,i is a plain multiplier of lobe i
/// (the paper folds it into the C's): the lobes are not normalised.
///
/// Energy: the model does not conserve energy for arbitrary parameters. A sufficient condition
/// for albedo <= 1 at every incidence: max(rho_d) + sum_i rho_s,i Cmax_i^n_i 2 pi / (n_i + 1)
/// <= 1 with Cmax_i = max(|Cx,i|, |Cy,i|, |Cz,i|) (the bracket is at most Cmax cos(beta), beta
/// the angle to the lobe axis, and int cos^n(beta) cos(theta) dw <= 2 pi / (n + 1)).
///
/// Sampling: lobe i is the power cosine (|C o wo| cos beta)^n_i about the axis
/// a_i = (Cx wo.x, Cy wo.y, Cz wo.z) / |...|, sampled with density
/// (n_i + 1) / (2 pi) cos^n_i(beta) (directions below the surface are failed samples); the
/// diffuse term is sampled cosine-weighted. One component is chosen with probability
/// proportional to an approximation of its albedo: avg(rho_d) for the diffuse term;
/// rho_s,i |C o wo|^n_i 2 pi / (n_i + 2) max(a_i.z, 1 / (n_i + 2)) for lobe i (exact for a
/// lobe the horizon does not clip; the floor keeps lobes that graze the horizon sampled).
/// pdf() is the exact mixture density. Both sides of the surface reflect.
#include <array>

#include "steradian/bsdf/bxdf_common.h"

namespace sr {

/// One generalised cosine lobe: rho * max(0, cx wo.x wi.x + cy wo.y wi.y + cz wo.z wi.z)^n.
struct LafortuneCosine {
    Float cx = -1, cy = -1, cz = 1;
    Float n = 1;    ///< exponent >= 0
    Float rho = 1;  ///< multiplier >= 0 (rho_s,i)
};

struct LafortuneLobe {
    static constexpr int kMaxLobes = 3;
    SampledSpectrum rho_d;  ///< diffuse albedo, in [0, 1]
    std::array<LafortuneCosine, kMaxLobes> lobes{};
    int count = 0;  ///< number of lobes in use, 0..kMaxLobes

    /// BSDF value (1/sr, no cosine) on wo's side; zero on the other side.
    SampledSpectrum f(Vec3 wo, Vec3 wi, TransportMode mode) const;
    /// Samples the diffuse term (cosine-weighted) or one lobe (power cosine about its axis),
    /// chosen with uc; u samples the direction. Empty if wo is grazing, the chosen lobe
    /// vanishes for this wo, or the direction falls below the surface.
    std::optional<BsdfSample> sample(Vec3 wo, Float uc, Point2 u, TransportMode mode) const;
    /// Solid-angle pdf of sample() producing wi (the exact mixture density; 0 on the other
    /// side).
    Float pdf(Vec3 wo, Vec3 wi, TransportMode mode) const;
    uint8_t flags() const;

    /// The sum of the lobes (without rho_d / pi) at (wo, wi): the specular part of f.
    Float lobe_sum(Vec3 wo, Vec3 wi) const;

  private:
    struct Mixture {
        Float p[1 + kMaxLobes] = {};  ///< probabilities: diffuse, then lobe i
        Vec3 axis[kMaxLobes];         ///< unit lobe axes for this wo
    };
    Mixture mixture(Vec3 wo) const;
    Float mixture_pdf(const Mixture& m, Vec3 wi) const;
};

/// The largest directional albedo (maximum over wavelengths) of `lobe` over polar angles
/// 0, 5, ..., 85, 89 degrees and azimuths 0, 45, 90 degrees from x, each estimated by Monte
/// Carlo from sample() with `samples` fixed-seed samples; with the standard error of that
/// estimate and the polar angle (degrees) where it occurs. For the builder's energy warning.
struct LafortuneAlbedo {
    Float albedo = 0, std_error = 0, theta_deg = 0;
};
LafortuneAlbedo lafortune_max_albedo(const LafortuneLobe& lobe, int samples = 4096);

}  // namespace sr
