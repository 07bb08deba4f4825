#include "steradian/bsdf/layered.h"

#include <limits>

#include "steradian/sampling/hash.h"
#include "steradian/sampling/rng.h"
#include "steradian/sampling/warp.h"

namespace sr {

namespace {

using Branch = DielectricLobe::Branch;

/// Walks are not cut by Russian roulette before this many events, and then only when their
/// largest weight is below kRrThreshold (the thresholds of pbrt-v4's LayeredBxDF).
constexpr int kRrMinDepth = 4;
constexpr Float kRrThreshold = 0.25f;

/// Seeds of the three independent random streams.
constexpr uint32_t kSeedF = 0x66, kSeedPdf = 0x70, kSeedSample = 0x73;

TransportMode adjoint(TransportMode m) {
    return m == TransportMode::Radiance ? TransportMode::Importance : TransportMode::Radiance;
}

/// Power heuristic with beta = 2 for one sample of each strategy (Veach 1997, Sec. 9.2.4).
Float power_heuristic(Float pf, Float pg) {
    Float f = pf * pf, g = pg * pg;
    if (std::isinf(f)) return 1;
    return f + g > 0 ? f / (f + g) : 0;
}

/// Transmittance exp(-sigma_t |dz / cos|) of the slab (sigma_t = 1) over a depth difference dz
/// along w.
Float slab_tr(Float dz, Vec3 w) {
    if (dz == 0) return 1;
    return std::exp(-std::abs(dz / w.z));
}

/// Henyey-Greenstein phase function (Henyey & Greenstein 1941, ApJ 93) for travel directions
/// w_in -> w_out with cos_theta = w_in . w_out (g > 0: forward scattering), per steradian of
/// w_out: (1 - g^2) / (4 pi (1 + g^2 - 2 g cos_theta)^(3/2)). It is its own sampling pdf.
Float hg_phase(Float cos_theta, Float g) {
    Float denom = 1 + sqr(g) - 2 * g * cos_theta;
    return kInv4Pi * (1 - sqr(g)) / (denom * safe_sqrt(denom));
}

/// Samples w_out with density hg_phase(w_in . w_out, g) by inverting the CDF of cos_theta.
Vec3 sample_hg(Vec3 w_in, Float g, Point2 u) {
    Float cos_theta;
    if (std::abs(g) < 1e-3f) {
        cos_theta = 1 - 2 * u.x;
    } else {
        Float s = (1 - sqr(g)) / (1 - g + 2 * g * u.x);
        cos_theta = clamp((1 + sqr(g) - sqr(s)) / (2 * g), Float(-1), Float(1));
    }
    Float sin_theta = safe_sqrt(1 - sqr(cos_theta));
    Float phi = 2 * kPi * u.y;
    Vec3 s, t;
    coordinate_system(w_in, s, t);
    return normalize(s * (sin_theta * std::cos(phi)) + t * (sin_theta * std::sin(phi)) +
                     w_in * cos_theta);
}

/// The slab thickness the walks use: at least the smallest normal float, so that the two
/// boundaries z = 0 and z = thickness stay distinct (a zero-thickness slab is then invisible:
/// its transmittance rounds to 1 and every sampled distance crosses it).
Float slab_thickness(Float t) { return std::max(t, std::numeric_limits<Float>::min()); }

/// The depth of the next collision in the slab (sigma_t = 1) for a walk at depth z travelling
/// along w: a free-flight distance t ~ exp(-t) projected on the normal, dz = t |cos|. When dz
/// vanishes in float next to z (grazing w), the collision is moved by one ulp in the direction
/// of travel, so that the walk neither stalls nor has to give up.
Float next_depth(Float z, Vec3 w, Float u) {
    Float dz = sample_exponential(u, 1 / std::abs(w.z));
    Float zp = w.z > 0 ? z + dz : z - dz;
    if (zp == z) zp = std::nextafter(z, w.z > 0 ? kInfinity : -kInfinity);
    return zp;
}

struct Random {
    Pcg32 rng;
    Float operator()() { return rng.next_float(); }
    Point2 pair() {
        Float a = rng.next_float();
        return {a, rng.next_float()};
    }
};

Pcg32 stream(Vec3 a, Vec3 b, uint32_t tag) {
    return Pcg32(hash(a.x, a.y, a.z, b.x, b.y, b.z, tag));
}

bool bad(const std::optional<BsdfSample>& s) {
    return !s || s->f.is_zero() || !(s->pdf_sa > 0) || s->wi.z == 0;
}

struct Estimate {
    SampledSpectrum f;
    Float pdf = 0;
};

/// The next-event random walks of f() (kF) and pdf() (kPdf) for wo, wi in the upper hemisphere
/// (the stack's outside). The walk samples the interface restricted to transmission at entry
/// and to reflection from below, and the base and the slab as sample() does; beta is the BSDF
/// throughput (f |cos| / density of the walk) and beta_p the ratio of sample()'s path density to
/// the walk's (the probabilities with which sample() would have refracted in and reflected
/// back where the walk did). An exit from a base or medium vertex at event `depth` happens at
/// event depth + 1 of sample(), so it is counted only if depth + 1 < max_depth.
template <bool kF, bool kPdf, typename Bottom>
Estimate walk(const LayeredLobe<Bottom>& l, Vec3 wo, Vec3 wi, TransportMode mode, Random& r) {
    const DielectricLobe& top = l.top;
    const bool top_specular = top.flags() & kLobeSpecular;
    const bool bottom_specular = l.bottom.flags() & kLobeSpecular;
    const bool medium = !l.albedo.is_zero();
    const Float d = slab_thickness(l.thickness);
    const int n = std::max(1, int(l.n_samples));

    Estimate e;
    // Reflection at the interface itself (rough; a smooth one's delta is not in f or pdf).
    if (!top_specular) {
        if constexpr (kF) e.f = top.f(wo, wi, mode) * Float(n);
        if constexpr (kPdf) e.pdf = top.pdf(wo, wi, mode) * Float(n);
    }

    for (int s = 0; s < n; ++s) {
        // Into the slab at wo.
        Float c_in = 0;
        std::optional<BsdfSample> in =
            top.sample_branch(wo, r.pair(), mode, Branch::Transmission, &c_in);
        if (bad(in)) continue;
        // The exit at wi, sampled from wi's side with the adjoint mode:
        // f_adj(wi, v) = f(v, wi) is the BSDF of leaving along wi from inside direction v.
        // A failed presample (a rough microfacet that does not refract into the slab) leaves
        // the connections along sampled directions, whose MIS weights count its density.
        Float c_ex = 0;
        std::optional<BsdfSample> ex =
            top.sample_branch(wi, r.pair(), adjoint(mode), Branch::Transmission, &c_ex);
        const bool have_ex = !bad(ex);
        if (!have_ex && top_specular) continue;            // no way out along wi
        const Vec3 v = have_ex ? ex->wi : Vec3(0, 0, -1);  // the interface's wo leaving along wi
        const Vec3 w_up = -v;  // the travel direction inside that leaves along wi
        const Float q_v = have_ex ? ex->pdf_sa : 0;
        const SampledSpectrum ex_weight =
            have_ex ? ex->f / q_v : SampledSpectrum(0);  // f(v, wi) / q_v
        // Density of sample() leaving along wi, per unit density of travelling along w_up
        // from a vertex and arriving unscattered: smooth, the refraction probability times the
        // Jacobian d omega_v / d omega_wi = |cos wi| / (eta^2 |cos v|) (Snell; radiance
        // etendue n^2 cos d omega); rough, sample()'s density of wi from v over q_v.
        Float exit_pdf = 0;
        if constexpr (kPdf) {
            if (have_ex)
                exit_pdf = top_specular ? c_ex * std::abs(wi.z) / (sqr(top.eta) * std::abs(v.z))
                                        : top.pdf(v, wi, mode) / q_v;
        }

        SampledSpectrum beta = in->f * (std::abs(in->wi.z) / in->pdf_sa);
        Float beta_p = c_in;
        Vec3 w = in->wi;  // travel direction
        Float z = d;

        for (int depth = 0; depth < l.max_depth; ++depth) {
            if (depth >= kRrMinDepth) {
                Float m = 0;
                if constexpr (kF) m = std::max(m, beta.max_value());
                if constexpr (kPdf) m = std::max(m, beta_p);
                if (m < kRrThreshold) {
                    if (r() >= m) break;
                    beta /= m;
                    beta_p /= m;
                }
            }
            const bool can_exit = depth + 1 < l.max_depth;

            if (medium) {
                Float zp = next_depth(z, w, r());
                if (zp > 0 && zp < d) {
                    // Scattering vertex at depth zp (weights: sigma_s Tr / (sigma_t Tr) = albedo
                    // for f, 1 for the density since sample() samples distances alike).
                    if (have_ex && can_exit) {
                        // Exit along the presampled w_up.
                        Float ph = hg_phase(dot(w, w_up), l.g);
                        Float wt = top_specular ? 1 : power_heuristic(q_v, ph);
                        Float tr = slab_tr(d - zp, w_up);
                        if constexpr (kF) e.f += beta * l.albedo * ex_weight * (ph * tr * wt);
                        if constexpr (kPdf) e.pdf += beta_p * ph * tr * exit_pdf * wt;
                    }
                    Vec3 wn = sample_hg(w, l.g, r.pair());
                    if (wn.z == 0) break;
                    if constexpr (kF) beta *= l.albedo;
                    if (!top_specular && can_exit && wn.z > 0) {
                        // Exit along the sampled direction.
                        Float ph = hg_phase(dot(w, wn), l.g);
                        Float wt =
                            power_heuristic(ph, top.pdf_branch(wi, -wn, Branch::Transmission));
                        Float tr = slab_tr(d - zp, wn);
                        if constexpr (kF) e.f += beta * top.f(-wn, wi, mode) * (tr * wt);
                        if constexpr (kPdf) e.pdf += beta_p * top.pdf(-wn, wi, mode) * tr * wt;
                    }
                    w = wn;
                    z = zp;
                    continue;
                }
                z = zp <= 0 ? 0 : d;  // reached a boundary unscattered (weight Tr / Tr = 1)
            } else {
                z = z == d ? 0 : d;
                if constexpr (kF) beta *= slab_tr(d, w);
            }

            if (z == d) {
                // The interface from below: reflect back (sample() would refract out with the
                // complementary probability; those exits are the next-event terms).
                Float c_r = 0;
                std::optional<BsdfSample> rs =
                    top.sample_branch(-w, r.pair(), mode, Branch::Reflection, &c_r);
                if (bad(rs)) break;
                if constexpr (kF) beta *= rs->f * (std::abs(rs->wi.z) / rs->pdf_sa);
                beta_p *= c_r;
                w = rs->wi;
                continue;
            }

            // The base, entered along w (w.z < 0), seen from inside as wb.
            const Vec3 wb = -w;
            if (have_ex && !bottom_specular && can_exit) {
                // Exit along the presampled w_up.
                SampledSpectrum fb = l.bottom.f(wb, w_up, mode);
                if (!fb.is_zero()) {
                    Float pb = l.bottom.pdf(wb, w_up, mode);
                    Float wt = top_specular ? 1 : power_heuristic(q_v, pb);
                    Float tr = slab_tr(d, w_up);
                    if constexpr (kF) e.f += beta * fb * ex_weight * (std::abs(v.z) * tr * wt);
                    if constexpr (kPdf) e.pdf += beta_p * pb * (medium ? tr : 1) * exit_pdf * wt;
                }
            }
            Float uc = r();
            std::optional<BsdfSample> bs = l.bottom.sample(wb, uc, r.pair(), mode);
            if (bad(bs)) break;
            if constexpr (kF) beta *= bs->f * (std::abs(bs->wi.z) / bs->pdf_sa);
            w = bs->wi;
            if (!top_specular && can_exit) {
                // Exit along the base's sampled direction.
                Float wt =
                    bottom_specular
                        ? 1
                        : power_heuristic(bs->pdf_sa, top.pdf_branch(wi, -w, Branch::Transmission));
                Float tr = slab_tr(d, w);
                if constexpr (kF) e.f += beta * top.f(-w, wi, mode) * (tr * wt);
                if constexpr (kPdf)
                    e.pdf += beta_p * top.pdf(-w, wi, mode) * (medium ? tr : 1) * wt;
            }
        }
    }
    e.f /= Float(n);
    e.pdf /= Float(n);
    return e;
}

}  // namespace

template <typename Bottom>
uint8_t LayeredLobe<Bottom>::flags() const {
    uint8_t t = top.flags(), b = bottom.flags();
    uint8_t fl = kLobeReflection;
    if (t & kLobeSpecular) fl |= kLobeSpecular;
    if ((t & kLobeDiffuse) || (b & kLobeDiffuse) || !albedo.is_zero())
        fl |= kLobeDiffuse;
    else if ((t & kLobeGlossy) || (b & kLobeGlossy))
        fl |= kLobeGlossy;
    // A black base and no medium: nothing below reaches back, but the interface still reflects.
    return fl;
}

template <typename Bottom>
SampledSpectrum LayeredLobe<Bottom>::f(Vec3 wo, Vec3 wi, TransportMode mode) const {
    if (!(flags() & (kLobeDiffuse | kLobeGlossy))) return SampledSpectrum(0);
    Random r{stream(wo, wi, kSeedF)};
    if (wo.z < 0) {
        wo = -wo;
        wi = -wi;
    }
    if (wo.z == 0 || wi.z <= 0) return SampledSpectrum(0);
    return walk<true, false>(*this, wo, wi, mode, r).f;
}

template <typename Bottom>
Float LayeredLobe<Bottom>::pdf(Vec3 wo, Vec3 wi, TransportMode mode) const {
    if (!(flags() & (kLobeDiffuse | kLobeGlossy))) return 0;
    Random r{stream(wo, wi, kSeedPdf)};
    if (wo.z < 0) {
        wo = -wo;
        wi = -wi;
    }
    if (wo.z == 0 || wi.z <= 0) return 0;
    Float p = walk<false, true>(*this, wo, wi, mode, r).pdf;
    return p > kPdfFloor ? p : kPdfFloor;  // also maps a NaN to the floor
}

template <typename Bottom>
std::optional<BsdfSample> LayeredLobe<Bottom>::sample(Vec3 wo_in, Float uc, Point2 u,
                                                      TransportMode mode) const {
    const bool flip = wo_in.z < 0;
    const Vec3 wo = flip ? -wo_in : wo_in;
    if (wo.z == 0) return std::nullopt;
    // The walk keeps its weight beta = prod f |cos| / pdf (products of f and of pdf alone
    // overflow on long walks through smooth-ish rough interfaces) and, while every event is
    // specular, the product of their discrete probabilities. The result has
    // f |cos wi| / pdf_sa = beta, with pdf_sa that product for a specular walk and pdf(wo, wi)
    // otherwise (the function next-event estimation evaluates, for consistent MIS weights).
    auto finish = [&](const SampledSpectrum& beta, Float prob, Vec3 wi, uint8_t fl) {
        Vec3 wi_out = flip ? -wi : wi;
        Float p = (fl & kLobeSpecular) ? prob : pdf(wo_in, wi_out, mode);
        return BsdfSample{beta * (p / std::abs(wi.z)), wi_out, p, fl, 1};
    };
    auto weight = [](const BsdfSample& s) { return s.f * (std::abs(s.wi.z) / s.pdf_sa); };

    std::optional<BsdfSample> bs = top.sample(wo, uc, u, mode);
    if (bad(bs)) return std::nullopt;
    if (bs->is_reflection()) {
        if (bs->is_specular())
            return flip ? BsdfSample{bs->f, -bs->wi, bs->pdf_sa, bs->flags, 1} : *bs;
        return finish(weight(*bs), 0, bs->wi, bs->flags);
    }

    Random r{Pcg32(hash(wo_in.x, wo_in.y, wo_in.z, uc, u.x, u.y, kSeedSample))};
    const bool medium = !albedo.is_zero();
    const bool diffuse_base = bottom.flags() & kLobeDiffuse;
    SampledSpectrum beta = weight(*bs);
    Float prob = bs->pdf_sa;  // meaningful while `specular`
    bool specular = bs->is_specular();
    bool diffuse = false;
    Vec3 w = bs->wi;
    const Float d = slab_thickness(thickness);
    Float z = d;
    for (int depth = 0; depth < max_depth; ++depth) {
        if (medium) {
            Float zp = next_depth(z, w, r());
            if (zp > 0 && zp < d) {
                Vec3 wn = sample_hg(w, g, r.pair());
                if (wn.z == 0) return std::nullopt;
                beta *= albedo;  // sigma_s Tr phase / (sigma_t Tr phase)
                specular = false;
                diffuse = true;
                w = wn;
                z = zp;
                continue;
            }
            z = zp <= 0 ? 0 : d;  // reached a boundary: Tr / Tr = 1
        } else {
            z = z == d ? 0 : d;
            beta *= slab_tr(d, w);
        }
        if (z == 0) {
            Float ub = r();
            std::optional<BsdfSample> b = bottom.sample(-w, ub, r.pair(), mode);
            if (bad(b)) return std::nullopt;
            beta *= weight(*b);
            prob *= b->pdf_sa;
            specular &= b->is_specular();
            diffuse |= diffuse_base;
            w = b->wi;
            continue;
        }
        Float ut = r();
        std::optional<BsdfSample> t = top.sample(-w, ut, r.pair(), mode);
        if (bad(t)) return std::nullopt;
        beta *= weight(*t);
        prob *= t->pdf_sa;
        specular &= t->is_specular();
        if (t->is_transmission()) {
            uint8_t fl = kLobeReflection | (specular  ? kLobeSpecular
                                            : diffuse ? kLobeDiffuse
                                                      : kLobeGlossy);
            return finish(beta, prob, t->wi, fl);
        }
        w = t->wi;
    }
    return std::nullopt;
}

template struct LayeredLobe<LambertLobe>;
template struct LayeredLobe<ConductorLobe>;

}  // namespace sr
