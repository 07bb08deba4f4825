#include "steradian/bsdf/lafortune.h"

#include <cmath>

#include "steradian/bsdf/cosine_lobe.h"
#include "steradian/sampling/rng.h"
#include "steradian/sampling/warp.h"

namespace sr {

namespace {

/// The bracket Cx wo.x wi.x + Cy wo.y wi.y + Cz wo.z wi.z of one lobe.
Float bracket(const LafortuneCosine& l, Vec3 wo, Vec3 wi) {
    return l.cx * wo.x * wi.x + l.cy * wo.y * wi.y + l.cz * wo.z * wi.z;
}

}  // namespace

Float LafortuneLobe::lobe_sum(Vec3 wo, Vec3 wi) const {
    Float s = 0;
    for (int i = 0; i < count; ++i) {
        const LafortuneCosine& l = lobes[i];
        Float b = bracket(l, wo, wi);
        if (b > 0 && l.rho > 0) s += l.rho * std::pow(b, l.n);
    }
    return s;
}

SampledSpectrum LafortuneLobe::f(Vec3 wo, Vec3 wi, TransportMode) const {
    if (!same_hemisphere(wo, wi)) return SampledSpectrum(0);
    return rho_d * kInvPi + SampledSpectrum(lobe_sum(wo, wi));
}

LafortuneLobe::Mixture LafortuneLobe::mixture(Vec3 wo) const {
    Mixture m;
    m.p[0] = std::max(Float(0), rho_d.average());
    Float side = wo.z < 0 ? Float(-1) : Float(1);
    for (int i = 0; i < count; ++i) {
        const LafortuneCosine& l = lobes[i];
        Vec3 a(l.cx * wo.x, l.cy * wo.y, l.cz * wo.z);
        Float len = length(a);
        if (!(len > 0) || !(l.rho > 0)) continue;  // the lobe vanishes for this wo
        m.axis[i] = a / len;
        // Over the whole cap about the axis, int cos^n(beta) cos(theta_i) dw = a.z 2 pi / (n + 2)
        // (cos(theta_i) is a.z cos(beta) plus a part perpendicular to the axis that averages
        // out over the azimuth): the lobe's albedo when the horizon does not clip it.
        Float up = std::max(side * m.axis[i].z, 1 / (l.n + 2));
        m.p[1 + i] = l.rho * std::pow(len, l.n) * (2 * kPi / (l.n + 2)) * up;
    }
    Float total = 0;
    for (Float p : m.p) total += p;
    if (!(total > 0) || !std::isfinite(total)) return Mixture{};
    for (Float& p : m.p) p /= total;
    return m;
}

Float LafortuneLobe::mixture_pdf(const Mixture& m, Vec3 wi) const {
    Float pdf = m.p[0] * cosine_hemisphere_pdf(std::abs(wi.z));
    for (int i = 0; i < count; ++i)
        if (m.p[1 + i] > 0) pdf += m.p[1 + i] * cosine_power_pdf(dot(m.axis[i], wi), lobes[i].n);
    return pdf;
}

std::optional<BsdfSample> LafortuneLobe::sample(Vec3 wo, Float uc, Point2 u,
                                                TransportMode mode) const {
    if (wo.z == 0) return std::nullopt;
    Mixture m = mixture(wo);
    // Choose the component: the first whose cumulative probability exceeds uc.
    int chosen = -1;
    Float cdf = 0;
    for (int c = 0; c < 1 + count; ++c) {
        cdf += m.p[c];
        if (m.p[c] > 0 && uc < cdf) {
            chosen = c;
            break;
        }
    }
    if (chosen < 0) {  // rounding left uc above the last cumulative sum: take the last one
        for (int c = count; c >= 0 && chosen < 0; --c)
            if (m.p[c] > 0) chosen = c;
        if (chosen < 0) return std::nullopt;
    }
    Vec3 wi;
    uint8_t fl;
    Float pdf_chosen;  // the chosen component's density, from its own sampling variables
    if (chosen == 0) {
        wi = sample_cosine_hemisphere(u);
        pdf_chosen = cosine_hemisphere_pdf(wi.z);
        if (wo.z < 0) wi.z = -wi.z;
        fl = kLobeReflection | kLobeDiffuse;
    } else {
        int i = chosen - 1;
        Vec3 local = sample_cosine_power(u, lobes[i].n);
        wi = Frame::from_z(m.axis[i]).to_world(local);
        pdf_chosen = cosine_power_pdf(local.z, lobes[i].n);
        fl = kLobeReflection | kLobeGlossy;
    }
    if (!same_hemisphere(wo, wi)) return std::nullopt;
    // The mixture density: the chosen component's plus the others' evaluated at wi.
    Float pdf_sa = m.p[chosen] * pdf_chosen;
    if (chosen != 0) pdf_sa += m.p[0] * cosine_hemisphere_pdf(std::abs(wi.z));
    for (int i = 0; i < count; ++i)
        if (1 + i != chosen && m.p[1 + i] > 0)
            pdf_sa += m.p[1 + i] * cosine_power_pdf(dot(m.axis[i], wi), lobes[i].n);
    if (!(pdf_sa > 0)) return std::nullopt;
    return BsdfSample{f(wo, wi, mode), wi, pdf_sa, fl, 1};
}

Float LafortuneLobe::pdf(Vec3 wo, Vec3 wi, TransportMode) const {
    if (!same_hemisphere(wo, wi)) return 0;
    return mixture_pdf(mixture(wo), wi);
}

uint8_t LafortuneLobe::flags() const {
    uint8_t fl = kLobeNone;
    if (!rho_d.is_zero()) fl |= kLobeReflection | kLobeDiffuse;
    for (int i = 0; i < count; ++i)
        if (lobes[i].rho > 0) fl |= kLobeReflection | kLobeGlossy;
    return fl;
}

LafortuneAlbedo lafortune_max_albedo(const LafortuneLobe& lobe, int samples) {
    LafortuneAlbedo worst;
    Pcg32 rng(7);
    for (int t5 = 0; t5 <= 90; t5 += 5) {
        int t = std::min(t5, 89);
        for (int k = 0; k < 3; ++k) {
            Float theta = radians(Float(t)), phi = radians(Float(45 * k));
            Vec3 wo(std::sin(theta) * std::cos(phi), std::sin(theta) * std::sin(phi),
                    std::cos(theta));
            double sum = 0, sum2 = 0;
            for (int s = 0; s < samples; ++s) {
                Float uc = rng.next_float();
                Point2 u{rng.next_float(), rng.next_float()};
                std::optional<BsdfSample> bs = lobe.sample(wo, uc, u, TransportMode::Radiance);
                if (!bs) continue;
                double w = double(bs->f.max_value()) * std::abs(bs->wi.z) / bs->pdf_sa;
                sum += w;
                sum2 += w * w;
            }
            double mean = sum / samples;
            double se = std::sqrt(std::max(0.0, sum2 / samples - mean * mean) / samples);
            if (mean - 3 * se > worst.albedo - 3 * worst.std_error)
                worst = {Float(mean), Float(se), Float(t)};
        }
    }
    return worst;
}

}  // namespace sr
