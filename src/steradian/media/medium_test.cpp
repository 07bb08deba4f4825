// Media: the Henyey-Greenstein phase function (normalisation, sampling by chi-square), the grid
// interpolation (pbrt-v4's SampledGrid definition) and free-flight tracking against the
// majorant grid: ratio and delta tracking both estimate exp(-integral of sigma_t) along a ray.
#include "steradian/media/medium.h"

#include <gtest/gtest.h>

#include <cmath>
#include <vector>

#include "steradian/core/noise.h"
#include "steradian/sampling/rng.h"
#include "steradian/sampling/stats.h"
#include "support/majorant_check.h"

namespace sr {
namespace {

TEST(HenyeyGreenstein, IntegratesToOne) {
    for (double g : {-0.8, -0.3, 0.0, 0.5, 0.9}) {
        // The phase function depends only on mu = wo . wi: the sphere integral is 2 pi
        // times the integral over mu.
        double i = simpson_1d([&](double mu) { return 2 * M_PI * hg_phase(Float(mu), Float(g)); },
                              -1, 1, 200000);
        EXPECT_NEAR(i, 1.0, 1e-5) << "g " << g;
    }
    // Isotropic: 1 / (4 pi).
    EXPECT_NEAR(hg_phase(0.3f, 0), 1 / (4 * M_PI), 1e-7);
    // Forward scattering (wi = -wo, mu = -1) is the peak for g > 0: (1 + g) / (4 pi (1 - g)^2).
    EXPECT_NEAR(hg_phase(-1, 0.5f), 1.5 / (4 * M_PI * 0.25), 1e-5);
}

TEST(HenyeyGreenstein, SamplingMatchesThePdf) {
    const Vec3 wo = normalize(Vec3(0.3f, -0.5f, 0.8f));
    const Frame f = Frame::from_z(wo);  // another frame than the sampler's: phi is uniform
    constexpr int kMu = 40, kPhi = 16, kN = 400000;
    for (float g : {-0.7f, 0.0f, 0.4f, 0.85f}) {
        std::vector<double> obs(kMu * kPhi, 0), exp(kMu * kPhi, 0);
        Pcg32 rng(7, uint64_t(g * 1000 + 5000));
        int bad = 0;
        for (int i = 0; i < kN; ++i) {
            PhaseSample s = sample_hg(wo, g, Point2(rng.next_float(), rng.next_float()));
            // The returned value is the density of the returned direction.
            if (std::abs(s.p - hg_phase(dot(wo, s.wi), g)) > 1e-4f * s.p) ++bad;
            Vec3 l = f.to_local(s.wi);
            double mu = std::clamp(double(l.z), -1.0, 1.0);
            double phi = std::atan2(double(l.y), double(l.x)) + M_PI;
            int a = std::min(int((mu + 1) / 2 * kMu), kMu - 1);
            int b = std::min(int(phi / (2 * M_PI) * kPhi), kPhi - 1);
            obs[size_t(a * kPhi + b)] += 1;
        }
        EXPECT_EQ(bad, 0);
        for (int a = 0; a < kMu; ++a) {
            double mu0 = -1 + 2.0 * a / kMu, mu1 = -1 + 2.0 * (a + 1) / kMu;
            double p = simpson_1d([&](double mu) { return hg_phase(Float(mu), g); }, mu0, mu1, 64);
            for (int b = 0; b < kPhi; ++b) exp[size_t(a * kPhi + b)] = kN * p * 2 * M_PI / kPhi;
        }
        Chi2Result r = chi2_test(obs, exp);
        EXPECT_GT(r.p_value, 1e-4) << "g " << g << " chi2 " << r.statistic << " dof " << r.dof;
    }
}

// pbrt-v4's SampledGrid: node values at cell centres, trilinear between them, zero beyond the
// nodes (so a constant grid falls linearly to half its value at the boundary).
TEST(SampledGrid, InterpolatesBetweenCellCentres) {
    SampledGrid<Float> g;
    g.nx = 4, g.ny = 1, g.nz = 1;
    g.values = {1, 2, 3, 4};
    EXPECT_FLOAT_EQ(g.lookup(Point3(0.125f, 0.5f, 0.5f)), 1);
    EXPECT_FLOAT_EQ(g.lookup(Point3(0.25f, 0.5f, 0.5f)), 1.5f);
    EXPECT_FLOAT_EQ(g.lookup(Point3(0.875f, 0.5f, 0.5f)), 4);
    EXPECT_FLOAT_EQ(g.lookup(Point3(1.0f, 0.5f, 0.5f)), 2);  // half way to the zero beyond
    EXPECT_FLOAT_EQ(g.lookup(Point3(0.0f, 0.5f, 0.5f)), 0.5f);
}

/// A "uniformgrid" medium over [p0, p1] with the given density grid, purely absorbing
/// (sigma_a = 1 scaled by `scale`, sigma_s = 0).
GridMedium absorbing_grid(int nx, int ny, int nz, std::vector<Float> density, Point3 p0, Point3 p1,
                          Float scale) {
    GridMedium m;
    m.p0 = p0, m.p1 = p1;
    m.sigma_a = ConstantSpectrum{1};
    m.sigma_s = ConstantSpectrum{0};
    m.scale = scale;
    m.density.nx = nx, m.density.ny = ny, m.density.nz = nz;
    m.density.values = std::move(density);
    m.le_scale.values = {0};
    build_majorants(m);
    return m;
}

struct Estimate {
    double mean = 0, se = 0;
};

/// Ratio tracking (the weight sigma_n / sigma_maj at each tentative collision) and delta
/// tracking (1 if no real collision before t_max, else 0): two unbiased estimators of the
/// transmittance, n runs each.
std::pair<Estimate, Estimate> track(const Medium& m, const Ray& ray, Float t_max, int n) {
    SampledWavelengths lambda = SampledWavelengths::sample_visible(0.5f);
    double s[2] = {0, 0}, s2[2] = {0, 0};
    for (int i = 0; i < n; ++i) {
        Pcg32 rng(uint64_t(i), 11);
        SampledSpectrum tr(1);
        SampledSpectrum tm = sample_t_maj(
            m, ray, t_max, rng.next_float(), rng, lambda,
            [&](Point3, const MediumProperties& mp, SampledSpectrum sigma_maj, SampledSpectrum) {
                tr *= (sigma_maj - mp.sigma_a - mp.sigma_s) / sigma_maj[0];
                return true;
            });
        double r = double(tr[0] * tm[0] / tm[0]);
        bool hit = false;
        Pcg32 rng2(uint64_t(i), 12);
        sample_t_maj(
            m, ray, t_max, rng2.next_float(), rng2, lambda,
            [&](Point3, const MediumProperties& mp, SampledSpectrum sigma_maj, SampledSpectrum) {
                if (rng2.next_float() < mp.sigma_a[0] / sigma_maj[0]) {
                    hit = true;
                    return false;
                }
                return true;
            });
        double d = hit ? 0 : 1;
        s[0] += r, s2[0] += r * r, s[1] += d, s2[1] += d * d;
    }
    Estimate e[2];
    for (int k = 0; k < 2; ++k) {
        e[k].mean = s[k] / n;
        e[k].se = std::sqrt(std::max(0.0, s2[k] / n - e[k].mean * e[k].mean) / (n - 1));
    }
    return {e[0], e[1]};
}

TEST(GridMedium, TransmittanceThroughALinearRampIsExpOfTheOpticalDepth) {
    // Density values a + b x at the node centres x_i = (i + 0.5) / N of [0, 1] (a linear ramp),
    // interpolated linearly between nodes and to zero over the outer half cells; along the x
    // axis the optical depth is then, exactly, the trapezoids between the nodes plus 3/8 of
    // the end values times a cell width (the integral of v (x N + 1/2) over half a cell).
    constexpr int N = 10;
    const double a = 0.5, b = 3.0;
    std::vector<Float> v;
    for (int i = 0; i < N; ++i) v.push_back(Float(a + b * (i + 0.5) / N));
    const Float len = 2;  // the box is [0, 2] x [0, 1] x [0, 1]: x stretched by 2
    const Float scale = 0.7f;
    Medium m = absorbing_grid(N, 1, 1, v, Point3(0, 0, 0), Point3(len, 1, 1), scale);
    double tau = 3.0 / 8 * (v.front() + v.back());
    for (int i = 0; i + 1 < N; ++i) tau += 0.5 * (v[size_t(i)] + v[size_t(i) + 1]);
    tau *= double(len) / N * scale;
    const double expected = std::exp(-tau);
    // From outside the box, through it and beyond; the direction's length is not 1.
    Ray ray{Point3(-1, 0.5f, 0.5f), Vec3(4, 0, 0), kInfinity};
    auto [ratio, delta] = track(m, ray, Float(1.5), 40000);
    EXPECT_NEAR(ratio.mean, expected, 4.5 * ratio.se + 1e-6) << "se " << ratio.se;
    EXPECT_NEAR(delta.mean, expected, 4.5 * delta.se) << "se " << delta.se;
    // Stopping inside the box at x = 1 (half way): the first half of the ramp.
    double tau_half = 3.0 / 8 * v.front();
    for (int i = 0; i + 1 < N / 2; ++i) tau_half += 0.5 * (v[size_t(i)] + v[size_t(i) + 1]);
    tau_half += 0.5 * v[N / 2 - 1] * 0.5 + 0.5 * (0.5 * (v[N / 2 - 1] + v[N / 2])) * 0.5;
    tau_half *= double(len) / N * scale;
    auto [r2, d2] = track(m, ray, Float(0.5), 40000);
    EXPECT_NEAR(r2.mean, std::exp(-tau_half), 4.5 * r2.se + 1e-6);
    EXPECT_NEAR(d2.mean, std::exp(-tau_half), 4.5 * d2.se);
}

TEST(GridMedium, ObliqueRayThroughAHeterogeneousGridMatchesQuadrature) {
    // A 5 x 4 x 3 grid of varied densities in a rotated, translated box; the optical depth
    // along an oblique ray by Simpson quadrature of the interpolated density (independent of
    // the majorant grid and the DDA that tracking relies on).
    std::vector<Float> v;
    for (int i = 0; i < 60; ++i) v.push_back(Float((i * 37) % 11) * 0.4f);
    GridMedium g = absorbing_grid(5, 4, 3, v, Point3(-1, -1, -1), Point3(1, 2, 0.5f), 1);
    // medium_from_world: a rotation of 30 degrees about z and a translation.
    const Float c = std::cos(0.5236f), s = std::sin(0.5236f);
    g.medium_from_world.m = {c, s, 0, 0.2f, -s, c, 0, -0.1f, 0, 0, 1, 0.3f};
    Medium m = g;
    Ray ray{Point3(-3, -2, -1), Vec3(1, 0.8f, 0.4f), kInfinity};
    double tau = simpson_1d(
        [&](double t) {
            Point3 pm = g.medium_from_world.point(ray.at(Float(t)));
            Point3 u((pm.x + 1) / 2, (pm.y + 1) / 3, (pm.z + 1) / 1.5f);
            if (u.x < 0 || u.y < 0 || u.z < 0 || u.x > 1 || u.y > 1 || u.z > 1) return 0.0;
            return double(g.density.lookup(u)) * length(ray.d);
        },
        0, 8, 40000);
    ASSERT_GT(tau, 0.5);  // the ray does cross the medium
    auto [ratio, delta] = track(m, ray, kInfinity, 40000);
    EXPECT_NEAR(ratio.mean, std::exp(-tau), 4.5 * ratio.se + 1e-4) << "tau " << tau;
    EXPECT_NEAR(delta.mean, std::exp(-tau), 4.5 * delta.se + 1e-4) << "tau " << tau;
}

TEST(HomogeneousMedium, TrackingGivesBeerLambert) {
    HomogeneousMedium h;
    h.sigma_a = ConstantSpectrum{0.3f};
    h.sigma_s = ConstantSpectrum{0.5f};
    h.scale = 2;
    Medium m = h;
    Ray ray{Point3(0, 0, 0), Vec3(0, 0, 3), kInfinity};
    // 1.2 units of direction = 3.6 distance; sigma_t = 1.6: absorbed or scattered, delta
    // tracking treats both as real collisions here by counting sigma_a + sigma_s.
    SampledWavelengths lambda = SampledWavelengths::sample_visible(0.5f);
    constexpr int n = 40000;
    double sum = 0;
    for (int i = 0; i < n; ++i) {
        Pcg32 rng(uint64_t(i), 3);
        bool collided = false;
        sample_t_maj(m, ray, Float(1.2), rng.next_float(), rng, lambda,
                     [&](Point3, const MediumProperties&, SampledSpectrum, SampledSpectrum) {
                         collided = true;  // the majorant is sigma_t: every collision is real
                         return false;
                     });
        sum += collided ? 0 : 1;
    }
    double p = std::exp(-1.6 * 3.6);
    double mean = sum / n, se = std::sqrt(p * (1 - p) / n);
    EXPECT_NEAR(mean, p, 4.5 * se);
}

// ---- pbrt-v4's "cloud" ------------------------------------------------------------------

CloudMedium cloud(Float density, Float wispiness, Float frequency, Point3 p0, Point3 p1) {
    CloudMedium m;
    m.p0 = p0, m.p1 = p1;
    m.sigma_a = ConstantSpectrum{0.5f};
    m.sigma_s = ConstantSpectrum{2};
    m.density = density, m.wispiness = wispiness, m.frequency = frequency;
    build_majorants(m);
    return m;
}

Point3 scaled(Point3 p, double s) { return Point3(Float(p.x * s), Float(p.y * s), Float(p.z * s)); }

// pbrt-v4's CloudMedium::Density, term by term from its definition: the point times the
// frequency, displaced twice by 0.05 w 2^-i times the noise's forward differences at
// 10 x 1.99^i times it; five octaves 2^-(i+1) noise(1.99^i pp); (1 - y) 4.5 density times
// that, clamped to [0, 1], plus 2 max(0, 0.5 - y), clamped to [0, 1].
double cloud_by_hand(Point3 p, double density, double wispiness, double frequency) {
    Point3 pp = scaled(p, frequency);
    if (wispiness > 0) {
        pp = pp + perlin_noise_differences(scaled(pp, 10)) * Float(0.05 * wispiness);
        pp = pp + perlin_noise_differences(scaled(pp, 19.9)) * Float(0.025 * wispiness);
    }
    double n = 0;
    for (int i = 0; i < 5; ++i) n += std::pow(0.5, i + 1) * perlin_noise(scaled(pp, std::pow(1.99, i)));
    double d = std::clamp((1 - p.y) * 4.5 * density * n, 0.0, 1.0);
    return std::clamp(d + 2 * std::max(0.0, 0.5 - p.y), 0.0, 1.0);
}

TEST(CloudMedium, DensityIsPbrtV4sDefinition) {
    // Where the noise drops out (density 0): 2 max(0, 0.5 - y), clamped to 1.
    CloudMedium flat = cloud(0, 0, 5, Point3(-1, -1, -1), Point3(2, 2, 2));
    EXPECT_FLOAT_EQ(cloud_density(flat, Point3(0.3f, 0.3f, 0.7f)), 0.4f);
    EXPECT_FLOAT_EQ(cloud_density(flat, Point3(0.9f, 0.1f, 0.2f)), 0.8f);
    EXPECT_FLOAT_EQ(cloud_density(flat, Point3(0.5f, -0.2f, 0.5f)), 1);
    EXPECT_FLOAT_EQ(cloud_density(flat, Point3(0.5f, 0.7f, 0.5f)), 0);
    // At y = 1 the noise term vanishes for any density.
    CloudMedium dense = cloud(7, 1, 5, Point3(0, 0, 0), Point3(1, 1, 1));
    EXPECT_EQ(cloud_density(dense, Point3(0.37f, 1, 0.81f)), 0);
    // Elsewhere, the definition evaluated from the noise values (pbrt-v4's Noise: the same
    // permutation table, gradients and fade, core/noise.h).
    for (Float wisp : {0.0f, 1.0f, 2.5f})
        for (Float dens : {1.0f, 2.0f, -1.5f}) {
            CloudMedium m = cloud(dens, wisp, 5, Point3(-1, -1, -1), Point3(2, 2, 2));
            Pcg32 rng(uint64_t(wisp * 10 + dens * 100 + 1000), 4);
            for (int i = 0; i < 200; ++i) {
                Point3 p(rng.next_float() * 2 - 0.5f, rng.next_float() * 1.5f - 0.25f,
                         rng.next_float());
                // Tolerance: both evaluate the noise at float positions up to |pp| 1.99^4 ~
                // 160, whose ulp (1.5e-5) moves an octave of gradient <= 2 and weight 1/32
                // by ~1e-6 per rounding; the density multiplies the noise sum by up to
                // 4.5 |density| (1 - y) ~ 11, so a few roundings in a different order (gcc
                // and clang contract and order them differently) give up to ~3e-5.
                EXPECT_NEAR(cloud_density(m, p), cloud_by_hand(p, dens, wisp, 5), 5e-5)
                    << p.x << " " << p.y << " " << p.z;
            }
        }
    // pbrt-v4's DNoise: forward differences of step 0.01.
    Point3 q(1.3f, -0.7f, 2.2f);
    Vec3 dn = perlin_noise_differences(q);
    EXPECT_FLOAT_EQ(dn.y, (perlin_noise(q.x, q.y + 0.01f, q.z) - perlin_noise(q)) / 0.01f);
}

TEST(CloudMedium, MajorantBoundsTheDensityEverywhere) {
    struct Case {
        Float density, wispiness, frequency;
        Point3 p0, p1;
    };
    // Bounds across y = 0.5 and y = 1 (above 1 the density is positive where the noise is
    // negative), negative densities, strong wispiness.
    for (const Case& c : {Case{1, 1, 5, Point3(0, 0, 0), Point3(1, 1, 1)},
                          Case{2, 0, 3, Point3(-2, -0.5f, 1), Point3(3, 2.5f, 2)},
                          Case{-4, 3, 8, Point3(0, 0.9f, 0), Point3(1, 3, 1)},
                          Case{0.3f, 1, 5, Point3(0, 0.6f, 0), Point3(1, 1.2f, 1)}}) {
        CloudMedium m = cloud(c.density, c.wispiness, c.frequency, c.p0, c.p1);
        test::MajorantCheck r = test::check_majorant(
            m.majorant, m.p0, m.p1, [&](Point3 p) { return cloud_density(m, p); }, 100000, 5);
        EXPECT_EQ(r.violations, 0) << "density " << c.density;
        EXPECT_GT(r.largest, 0.05);  // the test looks where the cloud is
    }
}

TEST(CloudMedium, NothingScattersOutsideItsBounds) {
    CloudMedium c = cloud(2, 1, 5, Point3(0, 0, 0), Point3(1, 1, 1));
    // A translation: medium space = world - (3, 0, 0).
    c.medium_from_world.m = {1, 0, 0, -3, 0, 1, 0, 0, 0, 0, 1, 0};
    Medium m = c;
    SampledWavelengths lambda = SampledWavelengths::sample_visible(0.5f);
    // Below y = 0.5 inside, the density is at least 2 (0.5 - y) > 0...
    EXPECT_GT(medium_properties(m, Point3(3.5f, 0.2f, 0.5f), lambda).sigma_s[0], 0);
    // ...and outside the box (here where y < 0.5 would give density 1) it is 0.
    for (Point3 p : {Point3(0.5f, 0.2f, 0.5f), Point3(3.5f, -0.2f, 0.5f), Point3(4.01f, 0.2f, 0.5f)}) {
        MediumProperties mp = medium_properties(m, p, lambda);
        EXPECT_EQ(mp.sigma_a[0] + mp.sigma_s[0], 0) << p.x << " " << p.y;
    }
    // A ray that misses the box: no tentative collision, transmittance 1.
    Pcg32 rng(1, 1);
    int calls = 0;
    SampledSpectrum t = sample_t_maj(
        m, Ray{Point3(0, 0.2f, 0.5f), Vec3(1, 0, 0), kInfinity}, Float(2.9), rng.next_float(),
        rng, lambda, [&](Point3, const MediumProperties&, SampledSpectrum, SampledSpectrum) {
            ++calls;
            return true;
        });
    EXPECT_EQ(calls, 0);
    EXPECT_EQ(t[0], 1);
    // Through the box: every tentative collision lies inside it.
    for (int i = 0; i < 200; ++i)
        sample_t_maj(m, Ray{Point3(0, 0.2f, 0.5f), Vec3(1, 0, 0), kInfinity}, kInfinity,
                     rng.next_float(), rng, lambda,
                     [&](Point3 p, const MediumProperties&, SampledSpectrum, SampledSpectrum) {
                         EXPECT_TRUE(p.x >= 2.999f && p.x <= 4.001f) << p.x;
                         return true;
                     });
}

}  // namespace
}  // namespace sr
