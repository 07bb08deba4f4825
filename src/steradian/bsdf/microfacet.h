#pragma once
/// The anisotropic Trowbridge-Reitz (GGX) microfacet distribution with Smith's
/// height-correlated masking-shadowing function, and sampling of its distribution of visible
/// normals.
///
/// References: Trowbridge & Reitz 1975, JOSA 65(5); Walter, Marschner, Li, Torrance 2007,
/// "Microfacet Models for Refraction through Rough Surfaces", EGSR; Heitz 2014,
/// "Understanding the Masking-Shadowing Function in Microfacet-Based BRDFs", JCGT 3(2);
/// Heitz 2018, "Sampling the GGX Distribution of Visible Normals", JCGT 7(4).
///
/// All directions are unit vectors in the local shading frame (z = macro-surface normal).
/// Microfacet normals wm lie in the upper hemisphere (wm.z > 0).
#include <algorithm>

#include "steradian/bsdf/bxdf_common.h"

namespace sr {

struct TrowbridgeReitz {
    Float alpha_x = 0;  ///< roughness (RMS slope / sqrt 2) along the frame's x axis
    Float alpha_y = 0;  ///< roughness along y; alpha_x == alpha_y is isotropic

    /// pbrt-v4's map from a user "roughness" in [0, 1] to alpha: sqrt(roughness), which
    /// spreads perceptually even steps better than alpha = roughness.
    static Float roughness_to_alpha(Float roughness) { return std::sqrt(roughness); }

    /// True if the surface is so smooth that it is treated as a perfect specular interface
    /// (max alpha < 1e-3): the lobe then uses Dirac deltas and never evaluates D.
    bool effectively_smooth() const { return std::max(alpha_x, alpha_y) < Float(1e-3); }

    /// pbrt-v4's path regularization (TrowbridgeReitzDistribution::Regularize, applied by its
    /// path integrators with "bool regularize" after the first non-specular bounce): an alpha
    /// below 0.3 is doubled and clamped to [0.1, 0.3], so a mirror becomes a lobe of alpha 0.1
    /// and paths such as light -> mirror -> diffuse -> camera become reachable (biased).
    void regularize() {
        if (alpha_x < Float(0.3)) alpha_x = std::clamp(2 * alpha_x, Float(0.1), Float(0.3));
        if (alpha_y < Float(0.3)) alpha_y = std::clamp(2 * alpha_y, Float(0.1), Float(0.3));
    }

    /// Distribution of normals D(wm) (per steradian of wm), normalised so that the projected
    /// microfacet area equals the macro-surface area: integral of D(wm) cos(theta_m) dwm = 1.
    /// In the form D = 1 / (pi ax ay (x^2/ax^2 + y^2/ay^2 + z^2)^2) for unit wm (Heitz 2014,
    /// Eq. 85), which needs no tangents and stays finite at grazing wm. 0 for wm.z <= 0.
    Float D(Vec3 wm) const {
        if (wm.z <= 0) return 0;
        Float t = sqr(wm.x / alpha_x) + sqr(wm.y / alpha_y) + sqr(wm.z);
        return 1 / (kPi * alpha_x * alpha_y * sqr(t));
    }

    /// Smith's auxiliary function Lambda(w) for GGX (Heitz 2014, Eq. 86, with the
    /// anisotropic alpha of the direction's azimuth, Eq. 80):
    /// (sqrt(1 + (ax^2 x^2 + ay^2 y^2) / z^2) - 1) / 2. Symmetric in w -> -w; infinite at
    /// grazing (w.z == 0).
    Float lambda(Vec3 w) const {
        if (w.z == 0) return kInfinity;
        Float a2_tan2 = (sqr(alpha_x * w.x) + sqr(alpha_y * w.y)) / sqr(w.z);
        return (std::sqrt(1 + a2_tan2) - 1) / 2;
    }

    /// Smith masking function G1(w) = 1 / (1 + Lambda(w)) (Heitz 2014, Eq. 43 for the
    /// Smith microsurface profile): the visible fraction of the microfacets facing w. 1 at
    /// normal incidence, 0 at grazing.
    Float G1(Vec3 w) const { return 1 / (1 + lambda(w)); }

    /// Height-correlated Smith masking-shadowing G(wo, wi) = 1 / (1 + Lambda(wo) + Lambda(wi))
    /// (Heitz 2014, Eq. 99), valid for reflection and transmission.
    Float G(Vec3 wo, Vec3 wi) const { return 1 / (1 + lambda(wo) + lambda(wi)); }

    /// Distribution of normals visible from w, D_w(wm) = G1(w) max(0, w . wm) D(wm) / |cos w|
    /// (Heitz 2014, Eq. 38; Heitz 2018, Eq. 1), per steradian of wm; integrates to 1 over
    /// the hemisphere of wm. A w below the surface is first flipped to the upper hemisphere
    /// (its mirror -w sees the same microfacets), as sample_wm does.
    Float D(Vec3 w, Vec3 wm) const {
        if (w.z < 0) w = -w;
        if (w.z == 0) return 0;
        return G1(w) / w.z * D(wm) * std::max(Float(0), dot(w, wm));
    }

    /// Solid-angle pdf of sample_wm(w, .) at wm: the visible-normal distribution D(w, wm).
    Float pdf(Vec3 w, Vec3 wm) const { return D(w, wm); }

    /// Samples a microfacet normal wm with density D(w, wm) by the method of Heitz 2018
    /// (Sec. 3 and 4, listing of Appendix A): stretch w into the configuration where
    /// alpha = 1 (the microsurface is a hemisphere), sample a point uniformly on the projected
    /// area of the hemisphere seen from the stretched direction (a unit disk whose lower half
    /// is squashed by cos(theta)), lift it onto the hemisphere, and unstretch the normal.
    /// w may lie below the surface (it is flipped first). u in [0, 1)^2.
    Vec3 sample_wm(Vec3 w, Point2 u) const {
        // Sec. 3.2: stretch (the hemisphere configuration).
        Vec3 wh = normalize(Vec3(alpha_x * w.x, alpha_y * w.y, w.z));
        if (wh.z < 0) wh = -wh;
        // Sec. 4.1: orthonormal basis around wh (T1 horizontal).
        Float len2 = sqr(wh.x) + sqr(wh.y);
        Vec3 t1 = len2 > 0 ? Vec3(-wh.y, wh.x, 0) / std::sqrt(len2) : Vec3(1, 0, 0);
        Vec3 t2 = cross(wh, t1);
        // Sec. 4.2: uniform point on the unit disk, the half behind wh scaled by cos(theta_h):
        // p2 <- lerp(s, sqrt(1 - p1^2), p2) with s = (1 + cos theta_h) / 2.
        Float r = std::sqrt(u.x);
        Float phi = 2 * kPi * u.y;
        Float p1 = r * std::cos(phi), p2 = r * std::sin(phi);
        Float s = Float(0.5) * (1 + wh.z);
        p2 = (1 - s) * safe_sqrt(1 - sqr(p1)) + s * p2;
        // Sec. 4.3: reproject onto the hemisphere.
        Vec3 nh = t1 * p1 + t2 * p2 + wh * safe_sqrt(1 - sqr(p1) - sqr(p2));
        // Sec. 3.4: unstretch (normals transform by the inverse transpose). The floor on z
        // keeps wm strictly above the horizon for rounding-error samples on the rim.
        return normalize(Vec3(alpha_x * nh.x, alpha_y * nh.y, std::max(Float(1e-6), nh.z)));
    }
};

}  // namespace sr
