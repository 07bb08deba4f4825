// LayeredLobe (coateddiffuse, coatedconductor) and the "mix" material. The layered f() and
// pdf() are Monte Carlo estimates, so the checks compare expectations within standard errors
// estimated from the same runs (fixed seeds), never fixed epsilons:
// - sampling is unbiased for the BSDF: per cell of the hemisphere, the mean of sample()'s
//   weights f |cos| / pdf landing there equals the integral of the estimated f |cos| over the
//   cell (z-tests combined into a chi-square statistic);
// - pdf() is the density of sample(): per cell the observed frequency of non-specular samples
//   equals the integral of the estimated pdf, and the integral over the hemisphere equals the
//   fraction of non-specular samples (not 1: specular reflections, absorbed and truncated
//   walks take the rest);
// - energy: albedo <= 1, and = 1 for lossless stacks (white base, smooth coating, no absorbing
//   slab or a purely scattering one), from sample() and from the integral of f;
// - closed forms: a smooth coating over a black base reflects exactly the Fresnel reflectance
//   specularly; an index-matched coating over a Lambertian base through an absorbing slab is
//   (r / pi) exp(-tau / cos_o) exp(-tau / cos_i) (Beer-Lambert), with albedo
//   r exp(-tau / cos_o) 2 E_3(tau); at normal incidence a smooth coating over a mirror
//   conductor through an absorbing slab reflects R + T^2 a / (1 - R a), a = F_c exp(-2 tau)
//   (the geometric series of internal reflections);
// - reciprocity in expectation: averages of f(wo, wi) and f(wi, wo) over independent
//   estimates (the seeds change with a common rotation about the normal, which leaves an
//   isotropic BSDF unchanged);
// - mix: the choice frequency is "amount", the albedo is the amount-weighted average of the
//   two materials' albedos, the choice is a deterministic function of (p, wo);
// - the interface's branch-restricted sampling used by the walks (chi-square against its pdf,
//   and pdf_sa times the branch probability equals the unrestricted pdf).
#include "steradian/bsdf/layered.h"

#include <gtest/gtest.h>

#include <array>
#include <cstdio>
#include <functional>
#include <vector>

#include "stat/lobe_util.h"
#include "steradian/bsdf/fresnel.h"
#include "steradian/material/material.h"
#include "steradian/sampling/stats.h"
#include "steradian/sampling/warp.h"

namespace sr {
namespace {

using testing::direction_deg;

constexpr double kZ = 4.5;  // z-score tolerance for single comparisons (two-sided p ~ 7e-6)

// ---- lobe construction ------------------------------------------------------------------

struct Slab {
    Float thickness = 0.01f;
    SampledSpectrum albedo{0};
    Float g = 0;
    int max_depth = 10, n_samples = 1;
};

template <typename Bottom>
LayeredLobe<Bottom> make_layered(DielectricLobe top, Bottom bottom, const Slab& s) {
    LayeredLobe<Bottom> l;
    l.top = top;
    l.bottom = bottom;
    l.albedo = s.albedo;
    l.thickness = s.thickness;
    l.g = s.g;
    l.max_depth = uint16_t(s.max_depth);
    l.n_samples = uint16_t(s.n_samples);
    return l;
}

CoatedDiffuseLobe coated_diffuse(Float eta, TrowbridgeReitz mf, SampledSpectrum r, const Slab& s) {
    return make_layered(DielectricLobe{eta, mf}, LambertLobe{r}, s);
}

CoatedConductorLobe coated_conductor(Float eta, TrowbridgeReitz mf, SampledSpectrum ce,
                                     SampledSpectrum ck, TrowbridgeReitz mc, const Slab& s) {
    return make_layered(DielectricLobe{eta, mf}, ConductorLobe{ce, ck, mc}, s);
}

// ---- running statistics -----------------------------------------------------------------

struct Accum {
    double sum = 0, sum2 = 0;
    int64_t n = 0;
    void add(double x) {
        sum += x;
        sum2 += x * x;
        ++n;
    }
    double mean() const { return n ? sum / double(n) : 0; }
    /// Standard error of the mean.
    double se() const {
        if (n < 2) return 0;
        double m = mean();
        return std::sqrt(std::max(sum2 / double(n) - m * m, 0.0) / double(n));
    }
};

using Channels = std::array<Accum, kSpectrumSamples>;

/// Directional albedo from f() per wavelength channel: the integral of f(wo, wi) |cos wi| over
/// the hemisphere by cosine-weighted wi (estimator pi f).
template <typename L>
Channels f_albedo_channels(const L& lobe, Vec3 wo, TransportMode mode, int n, uint64_t seed) {
    Channels a;
    Pcg32 rng(seed);
    for (int k = 0; k < n; ++k) {
        Vec3 wi = sample_cosine_hemisphere({rng.next_float(), rng.next_float()});
        if (wo.z < 0) wi.z = -wi.z;
        SampledSpectrum f = wi.z != 0 ? lobe.f(wo, wi, mode) : SampledSpectrum(0);
        for (int c = 0; c < kSpectrumSamples; ++c) a[c].add(double(f[c]) * kPi);
    }
    return a;
}

/// Directional albedo from sample() weights per wavelength channel.
template <typename L>
Channels sample_albedo_channels(const L& lobe, Vec3 wo, TransportMode mode, int n, uint64_t seed) {
    Channels a;
    Pcg32 rng(seed);
    for (int k = 0; k < n; ++k) {
        Float uc = rng.next_float();
        Point2 u{rng.next_float(), rng.next_float()};
        std::optional<BsdfSample> s = lobe.sample(wo, uc, u, mode);
        SampledSpectrum w(0);
        if (s && s->pdf_sa > 0) w = s->f * (std::abs(s->wi.z) / s->pdf_sa);
        for (int c = 0; c < kSpectrumSamples; ++c) a[c].add(double(w[c]));
    }
    return a;
}

template <typename L>
Accum f_albedo(const L& lobe, Vec3 wo, TransportMode mode, int n, uint64_t seed) {
    return f_albedo_channels(lobe, wo, mode, n, seed)[0];
}
template <typename L>
Accum sample_albedo(const L& lobe, Vec3 wo, TransportMode mode, int n, uint64_t seed) {
    return sample_albedo_channels(lobe, wo, mode, n, seed)[0];
}

// ---- per-cell comparisons over the hemisphere ------------------------------------------------

/// Cells of the hemisphere on wo's side in (cos theta, phi): equal solid angle each, and a
/// point uniform in a cell's (|cos theta|, phi) rectangle is uniform in solid angle.
struct Grid {
    int nz = 8, nphi = 12;
    int cells() const { return nz * nphi; }
    double area() const { return 2 * kPi / cells(); }
    int cell(Vec3 w) const {
        double z = std::abs(w.z);
        double phi = std::atan2(double(w.y), double(w.x)) + kPi;
        int i = std::min(int(z * nz), nz - 1), j = std::min(int(phi / (2 * kPi) * nphi), nphi - 1);
        return i * nphi + j;
    }
    /// A point of cell c for u in [0,1)^2, on the side of `side`.
    Vec3 point(int c, Point2 u, Float side) const {
        int i = c / nphi, j = c % nphi;
        double z = (i + double(u.x)) / nz;
        double phi = (j + double(u.y)) / nphi * 2 * kPi - kPi;
        double r = std::sqrt(std::max(0.0, 1 - z * z));
        return Vec3(Float(r * std::cos(phi)), Float(r * std::sin(phi)), Float(side > 0 ? z : -z));
    }
};

struct CellReport {
    double chi2 = 0;  ///< sum of squared z-scores over the compared cells
    int dof = 0;      ///< number of compared cells
    double p = 1;
    double worst_z = 0;
    std::string worst;
};

/// Sum of z^2 over cells whose two estimates a_c, b_c (standard errors sa_c, sb_c) are compared;
/// cells where both estimates are zero with zero errors are skipped. A chi-square statistic
/// with one degree of freedom per cell for independent, asymptotically normal estimates.
CellReport compare_cells(const std::vector<double>& a, const std::vector<double>& sa,
                         const std::vector<double>& b, const std::vector<double>& sb) {
    CellReport r;
    for (size_t c = 0; c < a.size(); ++c) {
        double var = sqr(sa[c]) + sqr(sb[c]);
        if (var == 0) {
            EXPECT_EQ(a[c], b[c]) << "cell " << c;
            continue;
        }
        double z = (a[c] - b[c]) / std::sqrt(var);
        r.chi2 += z * z;
        ++r.dof;
        if (std::abs(z) > std::abs(r.worst_z)) {
            r.worst_z = z;
            char buf[160];
            std::snprintf(buf, sizeof buf, "cell %zu: %.6g +- %.3g vs %.6g +- %.3g", c, a[c], sa[c],
                          b[c], sb[c]);
            r.worst = buf;
        }
    }
    r.p = r.dof ? chi2_sf(r.chi2, r.dof) : 1;
    return r;
}

/// What one configuration's sampling run gives per cell.
struct SamplingRun {
    std::vector<double> weight_mean, weight_se;  ///< E[f |cos| / pdf ; non-specular, in cell]
    std::vector<double> freq, freq_se;           ///< fraction of samples non-specular in cell
    std::vector<double> f_int, f_int_se;         ///< integral of f() |cos| over the cell
    std::vector<double> pdf_int, pdf_int_se;     ///< integral of pdf() over the cell
    Accum nonspecular;                           ///< indicator of a non-specular sample
    double pdf_total = 0, pdf_total_se = 0;      ///< integral of pdf() over the hemisphere
};

template <typename L>
SamplingRun run_cells(const L& lobe, Vec3 wo, TransportMode mode, int n_samples, int per_cell,
                      uint64_t seed, const Grid& grid = {}) {
    const int nc = grid.cells();
    SamplingRun run;
    std::vector<double> ws(nc, 0), ws2(nc, 0), cnt(nc, 0);
    Pcg32 rng(seed);
    for (int k = 0; k < n_samples; ++k) {
        Float uc = rng.next_float();
        Point2 u{rng.next_float(), rng.next_float()};
        std::optional<BsdfSample> s = lobe.sample(wo, uc, u, mode);
        bool ok = s && s->pdf_sa > 0 && !s->is_specular();
        run.nonspecular.add(ok ? 1 : 0);
        if (!ok) continue;
        EXPECT_GT(s->wi.z * wo.z, 0) << "the stack is opaque";
        int c = grid.cell(s->wi);
        double w = double(s->f[0]) * std::abs(s->wi.z) / s->pdf_sa;
        ws[c] += w;
        ws2[c] += w * w;
        cnt[c] += 1;
        // The reported pdf is pdf() at the sampled direction (MIS sees one function).
        EXPECT_EQ(s->pdf_sa, lobe.pdf(wo, s->wi, mode));
    }
    const double n = n_samples;
    for (int c = 0; c < nc; ++c) {
        double m = ws[c] / n;
        run.weight_mean.push_back(m);
        run.weight_se.push_back(std::sqrt(std::max(ws2[c] / n - m * m, 0.0) / n));
        double p = cnt[c] / n;
        run.freq.push_back(p);
        run.freq_se.push_back(std::sqrt(std::max(p * (1 - p), 0.0) / n));
    }
    // Cell integrals of f() |cos| and pdf(): stratified uniform points in each cell.
    const int strata = int(std::sqrt(double(per_cell)));
    double total_var = 0;
    for (int c = 0; c < nc; ++c) {
        Accum fa, pa;
        for (int k = 0; k < per_cell; ++k) {
            int sx = k % strata, sy = (k / strata) % strata;
            Point2 u{Float((sx + rng.next_float()) / strata),
                     Float((sy + rng.next_float()) / strata)};
            Vec3 wi = grid.point(c, u, wo.z);
            fa.add(double(lobe.f(wo, wi, mode)[0]) * std::abs(wi.z));
            pa.add(double(lobe.pdf(wo, wi, mode)));
        }
        run.f_int.push_back(fa.mean() * grid.area());
        run.f_int_se.push_back(fa.se() * grid.area());
        run.pdf_int.push_back(pa.mean() * grid.area());
        run.pdf_int_se.push_back(pa.se() * grid.area());
        run.pdf_total += run.pdf_int.back();
        total_var += sqr(run.pdf_int_se.back());
    }
    run.pdf_total_se = std::sqrt(total_var);
    return run;
}

// ---- configurations ---------------------------------------------------------------------------

struct Config {
    const char* name;
    std::function<std::optional<BsdfSample>(Vec3, Float, Point2, TransportMode)> sample;
    std::function<SampledSpectrum(Vec3, Vec3, TransportMode)> f;
    std::function<Float(Vec3, Vec3, TransportMode)> pdf;
};

/// Type-erases a lobe for the table of configurations.
struct AnyLobe {
    Config c;
    /// Directions per cell for the cell integrals of f() and pdf(). With a specular base under
    /// a rough coating, the exit is estimated along the mirror direction only (there is no
    /// second strategy to weigh against), so single estimates are heavy-tailed and their sample
    /// variance understates the error of small means: such configurations need more of them.
    int per_cell = 400;
    std::optional<BsdfSample> sample(Vec3 wo, Float uc, Point2 u, TransportMode m) const {
        return c.sample(wo, uc, u, m);
    }
    SampledSpectrum f(Vec3 wo, Vec3 wi, TransportMode m) const { return c.f(wo, wi, m); }
    Float pdf(Vec3 wo, Vec3 wi, TransportMode m) const { return c.pdf(wo, wi, m); }
};

template <typename L>
AnyLobe erase(const char* name, L lobe) {
    return AnyLobe{Config{
        name,
        [lobe](Vec3 wo, Float uc, Point2 u, TransportMode m) { return lobe.sample(wo, uc, u, m); },
        [lobe](Vec3 wo, Vec3 wi, TransportMode m) { return lobe.f(wo, wi, m); },
        [lobe](Vec3 wo, Vec3 wi, TransportMode m) { return lobe.pdf(wo, wi, m); }}};
}

// Gold-like conductor relative to a coating of eta 1.5 (eta and k of Au at ~600 nm / 1.5).
const SampledSpectrum kAuEta({0.25f / 1.5f, 0.2f / 1.5f, 0.4f / 1.5f, 0.9f / 1.5f});
const SampledSpectrum kAuK({3.0f / 1.5f, 3.3f / 1.5f, 2.6f / 1.5f, 2.0f / 1.5f});

std::vector<AnyLobe> configurations() {
    std::vector<AnyLobe> v;
    Slab thin;  // pbrt-v4's defaults: thickness 0.01, albedo 0, g 0, maxdepth 10, nsamples 1
    v.push_back(erase("diffuse, smooth coat, thin absorbing slab",
                      coated_diffuse(1.5f, {}, SampledSpectrum(0.8f), thin)));
    Slab absorbing{0.2f, SampledSpectrum(0), 0, 10, 1};
    v.push_back(erase("diffuse, rough coat 0.3, absorbing slab 0.2",
                      coated_diffuse(1.5f, {0.3f, 0.3f}, SampledSpectrum(0.8f), absorbing)));
    Slab scattering{0.5f, SampledSpectrum({0.9f, 0.5f, 0.7f, 0.2f}), 0.6f, 10, 1};
    v.push_back(erase("diffuse, smooth coat, scattering slab g 0.6",
                      coated_diffuse(1.5f, {}, SampledSpectrum({0.6f, 0.3f, 0.9f, 0.5f}),
                                     scattering)));
    Slab back{0.3f, SampledSpectrum(0.7f), -0.3f, 10, 1};
    v.push_back(erase("diffuse, anisotropic rough coat (0.2, 0.5), slab g -0.3",
                      coated_diffuse(1.33f, {0.2f, 0.5f}, SampledSpectrum(0.5f), back)));
    v.push_back(erase("conductor 0.3, rough coat 0.2, no slab",
                      coated_conductor(1.5f, {0.2f, 0.2f}, kAuEta, kAuK, {0.3f, 0.3f},
                                       Slab{0, SampledSpectrum(0), 0, 10, 1})));
    Slab cc{0.4f, SampledSpectrum(0.8f), 0.2f, 10, 1};
    v.push_back(erase("conductor 0.4, smooth coat, scattering slab",
                      coated_conductor(1.5f, {}, kAuEta, kAuK, {0.4f, 0.4f}, cc)));
    v.push_back(erase("mirror conductor, rough coat 0.3",
                      coated_conductor(1.5f, {0.3f, 0.3f}, kAuEta, kAuK, {}, thin)));
    v.back().per_cell = 4000;
    Slab short_walks{0.05f, SampledSpectrum(0.5f), 0, 3, 4};
    v.push_back(erase("diffuse, rough coat 0.3, maxdepth 3, nsamples 4",
                      coated_diffuse(1.5f, {0.3f, 0.3f}, SampledSpectrum(0.9f), short_walks)));
    return v;
}

const double kConfigThetas[] = {20, 70};
constexpr int kNumCellTests = 8 * 2 * 2;  // configurations x angles x (f, pdf)

// ---- tests --------------------------------------------------------------------------------------

// sample() is unbiased for f (per cell), and pdf() is the density of sample() (per cell and in
// total). The pdf part is the chi-square test of sample() against pdf(), with the expected
// counts themselves estimated (their variance enters each cell's z-score).
TEST(Layered, SamplingIsUnbiasedForFAndPdfIsItsDensity) {
    const double alpha = sidak_alpha(0.01, kNumCellTests);
    std::vector<AnyLobe> configs = configurations();
    ASSERT_EQ(int(configs.size()) * 2 * 2, kNumCellTests);
    uint64_t seed = 1000;
    for (const AnyLobe& lobe : configs) {
        for (double t : kConfigThetas) {
            Vec3 wo = direction_deg(t, 0.7);
            TransportMode mode = t > 45 ? TransportMode::Importance : TransportMode::Radiance;
            SamplingRun run = run_cells(lobe, wo, mode, 200000, lobe.per_cell, ++seed);
            CellReport rf = compare_cells(run.weight_mean, run.weight_se, run.f_int, run.f_int_se);
            CellReport rp = compare_cells(run.freq, run.freq_se, run.pdf_int, run.pdf_int_se);
            double frac = run.nonspecular.mean(), frac_se = run.nonspecular.se();
            std::printf(
                "[layered] %s, theta_o %g: f vs sample p = %.3g (chi2 %.1f / %d, worst "
                "%s); pdf vs sample p = %.3g (chi2 %.1f / %d, worst %s); pdf integral "
                "%.5f +- %.5f, non-specular fraction %.5f +- %.5f\n",
                lobe.c.name, t, rf.p, rf.chi2, rf.dof, rf.worst.c_str(), rp.p, rp.chi2, rp.dof,
                rp.worst.c_str(), run.pdf_total, run.pdf_total_se, frac, frac_se);
            EXPECT_GT(rf.p, alpha) << lobe.c.name << " theta " << t << ": " << rf.worst;
            EXPECT_GT(rp.p, alpha) << lobe.c.name << " theta " << t << ": " << rp.worst;
            // The pdf integrates to the probability of a non-specular sample (the floor
            // kPdfFloor adds at most 2 pi 1e-6).
            EXPECT_NEAR(run.pdf_total, frac,
                        kZ * std::sqrt(sqr(run.pdf_total_se) + sqr(frac_se)) + 1e-5)
                << lobe.c.name << " theta " << t;
        }
    }
}

// Lossless stacks (white base, smooth coating, no absorption, long walks) reflect everything:
// every completed walk has weight exactly 1, and the integral of f is 1 within its error.
TEST(Layered, LosslessStacksHaveUnitAlbedo) {
    struct Case {
        const char* name;
        CoatedDiffuseLobe lobe;
    };
    const Case cases[] = {
        {"no slab",
         coated_diffuse(1.5f, {}, SampledSpectrum(1), Slab{0, SampledSpectrum(0), 0, 1000, 1})},
        {"scattering slab albedo 1, g 0.5",
         coated_diffuse(1.5f, {}, SampledSpectrum(1), Slab{1, SampledSpectrum(1), 0.5f, 1000, 1})},
        {"eta 1.33, thin scattering slab g -0.4",
         coated_diffuse(1.33f, {}, SampledSpectrum(1),
                        Slab{0.05f, SampledSpectrum(1), -0.4f, 1000, 1})},
    };
    uint64_t seed = 50;
    for (const Case& c : cases) {
        for (double t : {0.0, 45.0, 80.0, 135.0}) {  // 135: wo below (two-sided)
            Vec3 wo = direction_deg(t);
            for (TransportMode mode : {TransportMode::Radiance, TransportMode::Importance}) {
                Accum s = sample_albedo(c.lobe, wo, mode, 20000, ++seed);
                EXPECT_NEAR(s.mean(), 1, 1e-5) << c.name << " theta " << t;
                // f() leaves out the coating's specular reflection R (a delta): add it.
                Accum f = f_albedo(c.lobe, wo, mode, 20000, ++seed);
                double r = fr_dielectric(std::abs(wo.z), c.lobe.top.eta);
                std::printf(
                    "[layered] lossless %s, theta %g: sample %.6f, R + integral of f "
                    "%.5f +- %.5f\n",
                    c.name, t, s.mean(), r + f.mean(), f.se());
                EXPECT_NEAR(r + f.mean(), 1, kZ * f.se()) << c.name << " theta " << t;
                EXPECT_LT(f.se(), 0.02);
            }
        }
    }
}

// Energy bound for every configuration (sample() and f() estimates), per wavelength channel.
// A rough coating loses the energy its single-scattering microfacet model misses (as the rough
// dielectric lobe alone does), so white rough stacks stay below 1 but close to it.
TEST(Layered, AlbedoAtMostOne) {
    std::vector<AnyLobe> configs = configurations();
    configs.push_back(erase("white diffuse, rough coat 0.3, no slab",
                            coated_diffuse(1.5f, {0.3f, 0.3f}, SampledSpectrum(1),
                                           Slab{0, SampledSpectrum(0), 0, 1000, 1})));
    configs.push_back(erase("white diffuse, rough coat 0.05, no slab",
                            coated_diffuse(1.5f, {0.05f, 0.05f}, SampledSpectrum(1),
                                           Slab{0, SampledSpectrum(0), 0, 1000, 1})));
    uint64_t seed = 300;
    for (const AnyLobe& lobe : configs) {
        for (double t : {0.0, 60.0, 85.0}) {
            Vec3 wo = direction_deg(t, 1.1);
            Channels sa = sample_albedo_channels(lobe, wo, TransportMode::Radiance, 20000, ++seed);
            Channels fa = f_albedo_channels(lobe, wo, TransportMode::Radiance, 20000, ++seed);
            for (int ch = 0; ch < kSpectrumSamples; ++ch) {
                const Accum &s = sa[ch], &f = fa[ch];
                EXPECT_LE(s.mean(), 1 + kZ * s.se()) << lobe.c.name << " " << t << " " << ch;
                EXPECT_LE(f.mean(), 1 + kZ * f.se()) << lobe.c.name << " " << t << " " << ch;
            }
            std::printf(
                "[layered] %s, theta %g: albedo (channel 0) sample %.4f +- %.4f, "
                "integral of f %.4f +- %.4f\n",
                lobe.c.name, t, sa[0].mean(), sa[0].se(), fa[0].mean(), fa[0].se());
        }
    }
    // White base under a rough coat: the loss shrinks with the roughness, towards the lossless
    // smooth coat (albedo 1).
    double previous = 0;
    for (Float alpha : {0.5f, 0.2f, 0.05f, 0.01f}) {
        CoatedDiffuseLobe lobe = coated_diffuse(1.5f, {alpha, alpha}, SampledSpectrum(1),
                                                Slab{0, SampledSpectrum(0), 0, 1000, 1});
        Accum s = sample_albedo(lobe, direction_deg(30), TransportMode::Radiance, 50000, 9);
        std::printf("[layered] white diffuse, rough coat %g: albedo %.4f +- %.4f\n", alpha,
                    s.mean(), s.se());
        EXPECT_GT(s.mean(), previous + kZ * s.se()) << alpha;
        EXPECT_LE(s.mean(), 1 + kZ * s.se()) << alpha;
        previous = s.mean();
    }
}

// A smooth coating over a black base: only the specular Fresnel reflection remains.
TEST(Layered, BlackBaseReflectsTheFresnelReflectance) {
    for (Float eta : {1.5f, 1.33f, 2.0f}) {
        CoatedDiffuseLobe lobe = coated_diffuse(eta, {}, SampledSpectrum(0), Slab{});
        EXPECT_EQ(lobe.flags(), kLobeReflection | kLobeSpecular);
        for (double t : {0.0, 30.0, 60.0, 85.0}) {
            Vec3 wo = direction_deg(t, 0.4);
            Float r = fr_dielectric(wo.z, eta);
            const int n = 40000;
            Accum a;
            Pcg32 rng(uint64_t(t * 10) + 1);
            for (int k = 0; k < n; ++k) {
                Float uc = rng.next_float();
                Point2 u{rng.next_float(), rng.next_float()};
                std::optional<BsdfSample> s = lobe.sample(wo, uc, u, TransportMode::Radiance);
                if (!s) {
                    a.add(0);
                    continue;
                }
                ASSERT_TRUE(s->is_specular() && s->is_reflection());
                EXPECT_EQ(s->wi, Vec3(-wo.x, -wo.y, wo.z));
                a.add(s->f[0] * std::abs(s->wi.z) / s->pdf_sa);
            }
            // Each sample weighs 1 (reflected, probability R) or 0: a binomial mean.
            double se = std::sqrt(std::max(double(r) * (1 - r), 1e-12) / n);
            EXPECT_NEAR(a.mean(), r, kZ * se + 1e-6) << eta << " " << t;
            EXPECT_TRUE(lobe.f(wo, direction_deg(20), TransportMode::Radiance).is_zero());
            EXPECT_EQ(lobe.pdf(wo, direction_deg(20), TransportMode::Radiance), 0);
        }
    }
}

// 2 E_3(tau) = 2 int_0^1 mu exp(-tau / mu) d mu: the cosine-weighted transmittance of a slab.
double two_e3(double tau) {
    return 2 * simpson_1d([&](double mu) { return mu > 0 ? mu * std::exp(-tau / mu) : 0.0; }, 0, 1,
                          20000);
}

// An index-matched coating (eta 1) over a Lambertian base through an absorbing slab: light goes
// straight in and out once, attenuated by Beer-Lambert along each slanted crossing.
TEST(Layered, AbsorbingSlabFollowsBeerLambert) {
    for (Float tau : {0.1f, 0.5f, 1.5f}) {
        for (Float rho : {0.3f, 1.0f}) {
            CoatedDiffuseLobe lobe = coated_diffuse(1, {}, SampledSpectrum(rho),
                                                    Slab{tau, SampledSpectrum(0), 0, 10, 1});
            Pcg32 rng(7);
            for (int k = 0; k < 200; ++k) {
                Vec3 wo = sample_uniform_hemisphere({rng.next_float(), rng.next_float()});
                Vec3 wi = sample_uniform_hemisphere({rng.next_float(), rng.next_float()});
                if (wo.z < 0.05f || wi.z < 0.05f) continue;  // keep clear of float underflow
                double expected =
                    rho / kPi * std::exp(-tau / double(wo.z)) * std::exp(-tau / double(wi.z));
                // One path only: the estimate is exact (up to float rounding).
                EXPECT_NEAR(lobe.f(wo, wi, TransportMode::Radiance)[0], expected,
                            2e-5 * expected + 1e-30)
                    << tau << " " << rho;
            }
            for (double t : {0.0, 50.0, 80.0}) {
                Vec3 wo = direction_deg(t);
                double expected = rho * std::exp(-tau / double(wo.z)) * two_e3(tau);
                Accum s = sample_albedo(lobe, wo, TransportMode::Radiance, 40000, 11);
                EXPECT_NEAR(s.mean(), expected, kZ * s.se()) << tau << " " << rho << " " << t;
            }
        }
    }
}

// Normal incidence on a smooth coating over a mirror conductor through an absorbing slab: every
// path stays on the normal; the reflectance is the sum of the internal reflections' series.
TEST(Layered, NormalIncidenceMultipleReflectionSeries) {
    for (Float tau : {0.0f, 0.3f, 1.0f}) {
        for (Float eta : {1.5f, 2.2f}) {
            SampledSpectrum ce(0.2f), ck(1.5f);
            CoatedConductorLobe lobe =
                coated_conductor(eta, {}, ce, ck, {}, Slab{tau, SampledSpectrum(0), 0, 400, 1});
            EXPECT_EQ(lobe.flags(), kLobeReflection | kLobeSpecular);
            double r0 = fr_dielectric(1, eta), t0 = 1 - r0;
            double fc = fr_complex(1, ce[0], ck[0]);
            double a = fc * std::exp(-2.0 * tau);
            double expected = r0 + t0 * t0 * a / (1 - r0 * a);
            Accum s = sample_albedo(lobe, Vec3(0, 0, 1), TransportMode::Radiance, 100000, 13);
            std::printf("[layered] series tau %g eta %g: %.5f +- %.5f, expected %.5f\n", tau, eta,
                        s.mean(), s.se(), expected);
            EXPECT_NEAR(s.mean(), expected, kZ * s.se() + 1e-6) << tau << " " << eta;
        }
    }
}

// Helmholtz reciprocity in expectation: f(wo, wi) and f(wi, wo) averaged over independent
// estimates agree; so do the Radiance- and Importance-mode values (f*(wo, wi) = f(wi, wo)).
TEST(Layered, ReciprocalInExpectation) {
    std::vector<AnyLobe> configs = configurations();
    const int iso[] = {0, 1, 2, 4, 5, 6, 7};  // isotropic configurations
    const double pairs[][3] = {{10, 60, 0.5}, {45, 75, 2.5}, {30, 30, 3.0}};
    int tests = 0;
    for (int ci : iso) {
        const AnyLobe& lobe = configs[ci];
        for (const auto& pr : pairs) {
            Accum oi, io, imp;
            for (int k = 0; k < 4000; ++k) {
                // A common rotation about the normal: same f, new random stream.
                double rot = 0.001 * k;
                Vec3 wo = direction_deg(pr[0], rot), wi = direction_deg(pr[1], rot + pr[2]);
                oi.add(lobe.f(wo, wi, TransportMode::Radiance)[0]);
                io.add(lobe.f(wi, wo, TransportMode::Radiance)[0]);
                imp.add(lobe.f(wi, wo, TransportMode::Importance)[0]);
            }
            double se = std::sqrt(sqr(oi.se()) + sqr(io.se()));
            EXPECT_NEAR(oi.mean(), io.mean(), kZ * se)
                << lobe.c.name << " " << pr[0] << " " << pr[1];
            double se2 = std::sqrt(sqr(oi.se()) + sqr(imp.se()));
            EXPECT_NEAR(oi.mean(), imp.mean(), kZ * se2) << lobe.c.name;
            EXPECT_GT(oi.mean(), 0) << lobe.c.name;
            ++tests;
        }
    }
    EXPECT_EQ(tests, 21);
}

// f, pdf and sample are pure functions of their arguments; the stack is two-sided and opaque.
TEST(Layered, DeterministicTwoSidedOpaque) {
    CoatedConductorLobe lobe = coated_conductor(1.5f, {0.3f, 0.3f}, kAuEta, kAuK, {0.2f, 0.2f},
                                                Slab{0.3f, SampledSpectrum(0.5f), 0.3f, 10, 2});
    Vec3 wo = direction_deg(35, 0.2), wi = direction_deg(55, 2.0);
    SampledSpectrum f1 = lobe.f(wo, wi, TransportMode::Radiance);
    SampledSpectrum f2 = lobe.f(wo, wi, TransportMode::Radiance);
    for (int i = 0; i < kSpectrumSamples; ++i) EXPECT_EQ(f1[i], f2[i]);
    EXPECT_EQ(lobe.pdf(wo, wi, TransportMode::Radiance), lobe.pdf(wo, wi, TransportMode::Radiance));
    auto s1 = lobe.sample(wo, 0.7f, {0.2f, 0.9f}, TransportMode::Radiance);
    auto s2 = lobe.sample(wo, 0.7f, {0.2f, 0.9f}, TransportMode::Radiance);
    ASSERT_EQ(bool(s1), bool(s2));
    if (s1) {
        EXPECT_EQ(s1->wi, s2->wi);
        EXPECT_EQ(s1->pdf_sa, s2->pdf_sa);
    }
    // Opaque: nothing through the stack.
    EXPECT_TRUE(lobe.f(wo, -wi, TransportMode::Radiance).is_zero());
    EXPECT_EQ(lobe.pdf(wo, -wi, TransportMode::Radiance), 0);
    // Two-sided: from below, samples stay below and f is non-zero there.
    Pcg32 rng(3);
    int below = 0;
    for (int k = 0; k < 1000; ++k) {
        auto s = lobe.sample(-wo, rng.next_float(), {rng.next_float(), rng.next_float()},
                             TransportMode::Radiance);
        if (!s) continue;
        EXPECT_LT(s->wi.z, 0);
        ++below;
    }
    EXPECT_GT(below, 500);
    EXPECT_FALSE(lobe.f(-wo, -wi, TransportMode::Radiance).is_zero());
}

// maxdepth 1: the walk never comes back out, only the coating's own reflection remains
// (pbrt-v4's convention: maxdepth counts the events below the interface).
TEST(Layered, MaxDepthOneKeepsOnlyTheCoatingReflection) {
    DielectricLobe top{1.5f, {0.3f, 0.3f}};
    CoatedDiffuseLobe lobe = coated_diffuse(1.5f, {0.3f, 0.3f}, SampledSpectrum(1),
                                            Slab{0, SampledSpectrum(0), 0, 1, 1});
    Pcg32 rng(5);
    for (int k = 0; k < 200; ++k) {
        Vec3 wo = sample_uniform_hemisphere({rng.next_float(), rng.next_float()});
        Vec3 wi = sample_uniform_hemisphere({rng.next_float(), rng.next_float()});
        EXPECT_EQ(lobe.f(wo, wi, TransportMode::Radiance)[0],
                  top.f(wo, wi, TransportMode::Radiance)[0]);
        EXPECT_EQ(lobe.pdf(wo, wi, TransportMode::Radiance),
                  std::max(top.pdf(wo, wi, TransportMode::Radiance), CoatedDiffuseLobe::kPdfFloor));
    }
}

// The interface sampling the walks rely on: DielectricLobe::sample_branch against
// pdf_branch (chi-square), and its relation to the unrestricted lobe: the same f, and
// pdf_sa * branch probability = pdf().
TEST(Layered, DielectricBranchSamplingMatchesItsPdf) {
    using Branch = DielectricLobe::Branch;
    const TrowbridgeReitz rough[] = {{0.3f, 0.3f}, {0.1f, 0.4f}};
    const double thetas[] = {30, 80, 150};  // 150: from inside (total internal reflection)
    const int tests = 2 * 2 * 3;
    const double alpha = sidak_alpha(0.01, tests);
    uint64_t seed = 700;
    for (const TrowbridgeReitz& mf : rough) {
        DielectricLobe lobe{1.5f, mf};
        for (Branch b : {Branch::Reflection, Branch::Transmission}) {
            for (double t : thetas) {
                Vec3 wo = direction_deg(t);
                testing::SphereChi2Config cfg;
                cfg.seed = ++seed;
                cfg.sample_count = 300000;
                testing::SphereChi2Outcome r = testing::sphere_chi2(
                    [&](Pcg32& rng) -> std::optional<Vec3> {
                        Float prob = 0;
                        auto s = lobe.sample_branch(wo, {rng.next_float(), rng.next_float()},
                                                    TransportMode::Radiance, b, &prob);
                        if (!s) return std::nullopt;
                        EXPECT_NEAR(s->pdf_sa, lobe.pdf_branch(wo, s->wi, b), 1e-3 * s->pdf_sa);
                        EXPECT_NEAR(s->pdf_sa * prob, lobe.pdf(wo, s->wi, TransportMode::Radiance),
                                    1e-3 * s->pdf_sa * prob + 1e-7);
                        EXPECT_NEAR(s->f[0], lobe.f(wo, s->wi, TransportMode::Radiance)[0],
                                    1e-3 * s->f[0]);
                        return s->wi;
                    },
                    [&](Vec3 wi) { return lobe.pdf_branch(wo, wi, b); }, cfg);
                std::printf("[chi2] dielectric branch %s alpha (%g, %g) theta %g: %s\n",
                            b == Branch::Reflection ? "R" : "T", mf.alpha_x, mf.alpha_y, t,
                            r.summary().c_str());
                EXPECT_GT(r.chi2.p_value, alpha) << r.tables();
            }
        }
    }
    // Smooth: the specular direction with probability 1, weight R or T.
    DielectricLobe smooth{1.5f, {}};
    Vec3 wo = direction_deg(40);
    Float r = fr_dielectric(wo.z, 1.5f), prob = 0;
    auto sr = smooth.sample_branch(wo, {0.5f, 0.5f}, TransportMode::Importance, Branch::Reflection,
                                   &prob);
    ASSERT_TRUE(sr);
    EXPECT_EQ(sr->pdf_sa, 1);
    EXPECT_FLOAT_EQ(prob, r);
    EXPECT_FLOAT_EQ(sr->f[0] * sr->wi.z, r);
    auto st = smooth.sample_branch(wo, {0.5f, 0.5f}, TransportMode::Importance,
                                   Branch::Transmission, &prob);
    ASSERT_TRUE(st);
    EXPECT_FLOAT_EQ(prob, 1 - r);
    EXPECT_FLOAT_EQ(st->f[0] * std::abs(st->wi.z), 1 - r);
    // Beyond the critical angle (41.8 degrees) from inside, transmission is impossible.
    EXPECT_FALSE(smooth.sample_branch(direction_deg(130), {0.5f, 0.5f}, TransportMode::Radiance,
                                      Branch::Transmission, &prob));
}

// ---- mix ------------------------------------------------------------------------------------

/// A tiny scene context: constant textures and a material list.
struct MixWorld {
    std::vector<SpectrumTexture> spectra;
    std::vector<FloatTexture> floats;
    std::vector<Material> materials;
    MaterialContext ctx() const { return {&spectra, &floats, &materials}; }
    int spectrum(Float v) {
        spectra.push_back(ConstantSpectrumTexture{ConstantSpectrum{v}});
        return int(spectra.size()) - 1;
    }
    int scalar(Float v) {
        floats.push_back(ConstantFloatTexture{v});
        return int(floats.size()) - 1;
    }
};

SurfaceHit hit_at(Point3 p, Vec3 wo) {
    SurfaceHit h;
    h.p = p;
    h.ng = h.ns = Normal3(0, 0, 1);
    h.dpdu = Vec3(1, 0, 0);
    h.wo = wo;
    return h;
}

TEST(Mix, ChoosesByAmountAndAveragesAlbedos) {
    MixWorld w;
    // Material 0: diffuse 0.2; material 1: a coated diffuse (white base, smooth coat, no slab:
    // albedo exactly 1 per completed walk); material 2: the mix.
    DiffuseMaterial diffuse;
    diffuse.reflectance = w.spectrum(0.2f);
    w.materials.push_back(diffuse);
    CoatedDiffuseMaterial cd;
    cd.reflectance = w.spectrum(1);
    cd.roughness = Roughness{w.scalar(0), w.scalar(0), true};
    cd.eta = ConstantSpectrum{1.5f};
    cd.layer = LayerParams{w.scalar(0), w.spectrum(0), w.scalar(0), 1000, 1};
    w.materials.push_back(cd);
    const Float amount = 0.3f;
    MixMaterial mix;
    mix.materials[0] = 0;
    mix.materials[1] = 1;
    mix.amount = w.scalar(amount);
    w.materials.push_back(mix);
    MaterialContext ctx = w.ctx();

    const int n = 40000;
    Pcg32 rng(17);
    Accum chose1, albedo;
    for (int k = 0; k < n; ++k) {
        Point3 p(rng.next_float(), rng.next_float(), 0);
        Vec3 wo = sample_uniform_hemisphere({rng.next_float(), rng.next_float()});
        SampledWavelengths lambda = SampledWavelengths::sample_visible(rng.next_float());
        SurfaceHit h = hit_at(p, wo);
        std::optional<Bsdf> b = make_bsdf(w.materials[2], ctx, h, lambda);
        ASSERT_TRUE(b);
        // Deterministic: the same point and direction choose the same material.
        SampledWavelengths lambda2 = lambda;
        std::optional<Bsdf> b2 = make_bsdf(w.materials[2], ctx, h, lambda2);
        ASSERT_EQ(b->lobe().index(), b2->lobe().index());
        bool one = std::holds_alternative<CoatedDiffuseLobe>(b->lobe());
        chose1.add(one);
        auto s = b->sample(wo, rng.next_float(), {rng.next_float(), rng.next_float()});
        albedo.add(s ? s->f[0] * absdot(s->wi, h.ns) / s->pdf_sa : 0);
    }
    double se_choice = std::sqrt(amount * (1 - amount) / n);
    EXPECT_NEAR(chose1.mean(), amount, kZ * se_choice);
    double expected = (1 - amount) * 0.2 + amount * 1.0;
    std::printf(
        "[mix] chose material 1 in %.4f (amount %.2f); albedo %.4f +- %.4f, expected %.4f\n",
        chose1.mean(), amount, albedo.mean(), albedo.se(), expected);
    EXPECT_NEAR(albedo.mean(), expected, kZ * albedo.se());

    // The choice depends on wo as well as on p (pbrt-v4 hashes both).
    SurfaceHit h = hit_at(Point3(0.25f, 0.5f, 0), Vec3(0, 0, 1));
    int changes = 0;
    SampledWavelengths lambda = SampledWavelengths::sample_visible(0.5f);
    size_t first = make_bsdf(w.materials[2], ctx, h, lambda)->lobe().index();
    for (int k = 0; k < 64; ++k) {
        h.wo = sample_uniform_hemisphere({rng.next_float(), rng.next_float()});
        changes += make_bsdf(w.materials[2], ctx, h, lambda)->lobe().index() != first;
    }
    EXPECT_GT(changes, 0);
    EXPECT_LT(changes, 64);

    // amount 0 and 1 select one material without hashing.
    w.floats[size_t(mix.amount)] = ConstantFloatTexture{0};
    EXPECT_TRUE(
        std::holds_alternative<LambertLobe>(make_bsdf(w.materials[2], ctx, h, lambda)->lobe()));
    w.floats[size_t(mix.amount)] = ConstantFloatTexture{1};
    EXPECT_TRUE(std::holds_alternative<CoatedDiffuseLobe>(
        make_bsdf(w.materials[2], ctx, h, lambda)->lobe()));
}

}  // namespace
}  // namespace sr
