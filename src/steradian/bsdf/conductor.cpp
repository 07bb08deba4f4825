#include "steradian/bsdf/conductor.h"

#include "steradian/bsdf/fresnel.h"

namespace sr {

SampledSpectrum ConductorLobe::f(Vec3 wo, Vec3 wi, TransportMode) const {
    if (!same_hemisphere(wo, wi) || mf.effectively_smooth()) return SampledSpectrum(0);
    Float cos_o = std::abs(wo.z), cos_i = std::abs(wi.z);
    Vec3 wm = wo + wi;
    if (length_squared(wm) == 0) return SampledSpectrum(0);
    wm = face_forward(normalize(wm), Vec3(0, 0, 1));
    SampledSpectrum fr = fr_complex(absdot(wo, wm), eta, k);
    return fr * (mf.D(wm) * mf.G(wo, wi) / (4 * cos_i * cos_o));
}

std::optional<BsdfSample> ConductorLobe::sample(Vec3 wo, Float, Point2 u, TransportMode) const {
    if (wo.z == 0) return std::nullopt;
    if (mf.effectively_smooth()) {
        Vec3 wi(-wo.x, -wo.y, wo.z);
        Float cos_i = std::abs(wi.z);
        return BsdfSample{fr_complex(cos_i, eta, k) / cos_i, wi, 1, kLobeReflection | kLobeSpecular,
                          1};
    }
    Vec3 wm = mf.sample_wm(wo, u);
    Vec3 wi = reflect(wo, wm);
    if (!same_hemisphere(wo, wi)) return std::nullopt;
    // dwm/dwi = 1 / (4 |wo . wm|) (Walter et al. 2007, Eq. 14).
    Float pdf = mf.pdf(wo, wm) / (4 * absdot(wo, wm));
    Float cos_o = std::abs(wo.z), cos_i = std::abs(wi.z);
    SampledSpectrum fr = fr_complex(absdot(wo, wm), eta, k);
    SampledSpectrum f = fr * (mf.D(wm) * mf.G(wo, wi) / (4 * cos_i * cos_o));
    return BsdfSample{f, wi, pdf, kLobeReflection | kLobeGlossy, 1};
}

Float ConductorLobe::pdf(Vec3 wo, Vec3 wi, TransportMode) const {
    if (!same_hemisphere(wo, wi) || mf.effectively_smooth()) return 0;
    Vec3 wm = wo + wi;
    if (length_squared(wm) == 0) return 0;
    wm = face_forward(normalize(wm), Vec3(0, 0, 1));
    return mf.pdf(wo, wm) / (4 * absdot(wo, wm));
}

}  // namespace sr
