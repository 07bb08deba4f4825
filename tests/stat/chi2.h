#pragma once
/// Chi-square goodness-of-fit test of a direction sampler against the solid-angle pdf it
/// claims, over a (theta, phi) grid of the whole unit sphere (in the spirit of the tests of
/// Mitsuba 3's chi2 library and pbrt-v3's bsdfs test):
/// - theta in [0, pi] and phi in [-pi, pi] are split into equal-angle cells (odd counts, so
///   that the pole-to-horizon and azimuthal symmetry lines fall inside cells rather than on
///   their edges, where rounding would decide the bin);
/// - the expected count of a cell is N times the integral of the pdf over it, by the
///   adaptive Simpson cubature in (theta, phi) with the Jacobian sin(theta); a cell that
///   straddles the horizon is integrated as two pieces, so the jump of a pdf at z = 0
///   (reflection vs transmission) is not smeared across Simpson nodes;
/// - sample() calls that produce no direction go to an extra "failed" cell whose expected
///   count is N (1 - integral of the pdf): a sampler may give up where the pdf has no mass,
///   but not elsewhere;
/// - sparse cells (expected count < 5) are pooled by sr::chi2_test;
/// - the caller compares the p-value with a Sidak-corrected significance level over all the
///   chi-square tests in its file, and prints tables() on failure.
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <optional>
#include <string>
#include <vector>

#include "steradian/core/math.h"
#include "steradian/sampling/rng.h"
#include "steradian/sampling/stats.h"

namespace sr::testing {

struct SphereChi2Config {
    int theta_res = 11;  ///< cells in theta over [0, pi] (odd)
    int phi_res = 21;    ///< cells in phi over [-pi, pi] (odd)
    int64_t sample_count = 1'000'000;
    double integration_tol = 1e-7;  ///< absolute error goal of each cell's pdf integral
    double min_expected = 5;        ///< pooling threshold of chi2_test
    uint64_t seed = 1;              ///< PCG32 stream of the sampler's random numbers
};

struct SphereChi2Outcome {
    Chi2Result chi2;
    double pdf_mass = 0;  ///< integral of the pdf over the sphere
    int64_t failures = 0;
    double expected_failures = 0;
    int theta_res = 0, phi_res = 0;
    std::vector<double> observed, expected;  ///< theta-major cells (without the failed cell)

    /// One line: p-value, statistic, dof, pooled cells, pdf mass, failures.
    std::string summary() const {
        char buf[256];
        std::snprintf(buf, sizeof buf,
                      "p = %.4g (chi2 = %.1f, dof = %d, pooled %d), pdf mass = %.6f, failed "
                      "samples %lld (expected %.1f)",
                      chi2.p_value, chi2.statistic, chi2.dof, chi2.pooled_cells, pdf_mass,
                      static_cast<long long>(failures), expected_failures);
        return buf;
    }
    /// The observed and expected counts as theta rows (pole first) by phi columns.
    std::string tables() const {
        std::string s;
        auto table = [&](const char* title, const std::vector<double>& v, const char* fmt) {
            s += title;
            s += " (rows: theta cells from +z to -z; columns: phi cells from -pi)\n";
            char buf[32];
            for (int i = 0; i < theta_res; ++i) {
                for (int j = 0; j < phi_res; ++j) {
                    std::snprintf(buf, sizeof buf, fmt, v[i * phi_res + j]);
                    s += buf;
                }
                s += '\n';
            }
        };
        table("observed", observed, "%8.0f");
        table("expected", expected, "%8.1f");
        s += summary() + "\n";
        return s;
    }
};

inline constexpr int kCubatureMaxDepth = 9;

/// Adaptive cubature of g(theta, phi) over [t0, t1] x [p0, p1]: a tensor Simpson rule on the
/// rectangle is compared with the sum over its four quadrants; the rectangle is split until
/// the two agree to within max(abs_tol, rel_tol |I|) (abs_tol scaled by the area fraction, so
/// a whole cell meets abs_tol), or the depth limit is reached. Sharp lobes (alpha = 0.05 at
/// grazing incidence: pdf ~ 10^3 / sr over 10^-3 sr) are resolved where they are. depth counts
/// down from kCubatureMaxDepth.
template <typename G>
double adaptive_cubature(G& g, double t0, double t1, double p0, double p1, double whole,
                         double estimate, double abs_tol, double rel_tol, int depth) {
    // Always split the first min_depth times: features narrower than the coarse node spacing
    // (e.g. a visible-normal pdf that is non-zero only within 1 degree of the pole) would
    // otherwise be missed when every node of both estimates reads 0.
    constexpr int max_depth = kCubatureMaxDepth, min_depth = 3;
    constexpr int kN = 4;  // Simpson intervals per rectangle and dimension
    double tm = 0.5 * (t0 + t1), pm = 0.5 * (p0 + p1);
    double q[4] = {simpson_2d(g, t0, tm, p0, pm, kN, kN), simpson_2d(g, tm, t1, p0, pm, kN, kN),
                   simpson_2d(g, t0, tm, pm, p1, kN, kN), simpson_2d(g, tm, t1, pm, p1, kN, kN)};
    double refined = q[0] + q[1] + q[2] + q[3];
    double area_fraction = (t1 - t0) * (p1 - p0) / whole;
    double err = std::abs(refined - estimate);
    bool deep_enough = depth <= max_depth - min_depth;
    if (depth <= 0 ||
        (deep_enough && err <= 15 * std::max(abs_tol * area_fraction, rel_tol * std::abs(refined))))
        return refined + (refined - estimate) / 15;  // Richardson: Simpson is O(h^4)
    return adaptive_cubature(g, t0, tm, p0, pm, whole, q[0], abs_tol, rel_tol, depth - 1) +
           adaptive_cubature(g, tm, t1, p0, pm, whole, q[1], abs_tol, rel_tol, depth - 1) +
           adaptive_cubature(g, t0, tm, pm, p1, whole, q[2], abs_tol, rel_tol, depth - 1) +
           adaptive_cubature(g, tm, t1, pm, p1, whole, q[3], abs_tol, rel_tol, depth - 1);
}

/// Integral of pdf(w) over the cell [t0, t1] x [p0, p1] of (theta, phi), in steradians, to
/// an absolute accuracy of about abs_tol.
template <typename Pdf>
double sphere_cell_integral(Pdf& pdf, double t0, double t1, double p0, double p1, double abs_tol) {
    auto integrand = [&](double theta, double phi) {
        double st = std::sin(theta), ct = std::cos(theta);
        Vec3 w(Float(st * std::cos(phi)), Float(st * std::sin(phi)), Float(ct));
        return double(pdf(w)) * st;
    };
    auto piece = [&](double a, double b) {
        double whole = (b - a) * (p1 - p0);
        double estimate = simpson_2d(integrand, a, b, p0, p1, 4, 4);
        return adaptive_cubature(integrand, a, b, p0, p1, whole, estimate, abs_tol, 1e-5,
                                 kCubatureMaxDepth);
    };
    // A cell straddling the horizon is integrated as two pieces whose nodes stay strictly on
    // their own side of z = 0 (the omitted 2e-7 rad sliver carries a negligible mass).
    constexpr double kHalfPi = 1.5707963267948966, kGap = 1e-7;
    if (t0 < kHalfPi && t1 > kHalfPi) return piece(t0, kHalfPi - kGap) + piece(kHalfPi + kGap, t1);
    return piece(t0, t1);
}

/// Runs the test. sample(Pcg32&) -> std::optional<Vec3> draws one direction (empty: the
/// sampler failed); pdf(Vec3) -> Float is its claimed solid-angle density.
template <typename Sample, typename Pdf>
SphereChi2Outcome sphere_chi2(Sample&& sample, Pdf&& pdf, const SphereChi2Config& cfg = {}) {
    const int nt = cfg.theta_res, np = cfg.phi_res;
    const double dt = 3.141592653589793 / nt, dp = 2 * 3.141592653589793 / np;
    SphereChi2Outcome out;
    out.theta_res = nt;
    out.phi_res = np;
    out.observed.assign(std::size_t(nt * np), 0);
    out.expected.assign(std::size_t(nt * np), 0);

    Pcg32 rng(cfg.seed);
    for (int64_t s = 0; s < cfg.sample_count; ++s) {
        std::optional<Vec3> w = sample(rng);
        if (!w) {
            ++out.failures;
            continue;
        }
        Vec3d v = normalize(Vec3d(*w));
        double theta = std::acos(clamp(v.z, -1.0, 1.0));
        double phi = std::atan2(v.y, v.x) + 3.141592653589793;
        int i = std::min(int(theta / dt), nt - 1), j = std::min(int(phi / dp), np - 1);
        out.observed[std::size_t(i * np + j)] += 1;
    }

    for (int i = 0; i < nt; ++i) {
        for (int j = 0; j < np; ++j) {
            double mass =
                sphere_cell_integral(pdf, i * dt, (i + 1) * dt, -3.141592653589793 + j * dp,
                                     -3.141592653589793 + (j + 1) * dp, cfg.integration_tol);
            out.pdf_mass += mass;
            out.expected[std::size_t(i * np + j)] = mass * double(cfg.sample_count);
        }
    }

    // The failed cell. A pdf mass within kMassTolerance of 1 is taken as 1 (quadrature
    // error). When the pdf claims all the mass, a few failures
    // from rounding are still allowed as long as they pool with other sparse cells (a tiny
    // non-zero E).
    constexpr double kMassTolerance = 2e-5;
    double missing = 1 - out.pdf_mass;
    out.expected_failures = (missing > kMassTolerance ? missing : 0.0) * double(cfg.sample_count);
    std::vector<double> obs = out.observed, exp = out.expected;
    obs.push_back(double(out.failures));
    exp.push_back(std::max(out.expected_failures, 1e-6));
    out.chi2 = chi2_test(obs, exp, cfg.min_expected);
    return out;
}

}  // namespace sr::testing
