#include "steradian/sampling/warp.h"

#include <gtest/gtest.h>

#include <cmath>
#include <functional>
#include <string>
#include <vector>

#include "steradian/sampling/rng.h"
#include "steradian/sampling/stats.h"

namespace sr {
namespace {

// Each chi-square test below is one of about a dozen in this file: Sidak-correct a 1% family
// level. The tests are deterministic (fixed seeds), so a pass is reproducible.
const double kAlpha = sidak_alpha(0.01, 12);
constexpr double kPiD = 3.14159265358979323846;

// ---- helpers ---------------------------------------------------------------------------------

/// Chi-square test of samples against a density on a 2D parameter rectangle
/// [a0, a1] x [b0, b1], split into na x nb cells. `sample` draws a parameter point from two
/// uniforms; `density` is the density in that parametrization (the pdf times the Jacobian of
/// the parametrization, e.g. pdf_sa * sin(theta) for (theta, phi)). Expected counts are the
/// density integrated over each cell with a composite Simpson rule.
struct Grid2 {
    double a0, a1, b0, b1;
    int na, nb;
};

double chi2_p_value_2d(const Grid2& g, const std::function<Vec2d(Point2)>& sample,
                       const std::function<double(double, double)>& density, int n_samples,
                       uint64_t seed) {
    std::vector<double> observed(std::size_t(g.na * g.nb), 0.0), expected(observed.size(), 0.0);
    Pcg32 rng(seed);
    double da = (g.a1 - g.a0) / g.na, db = (g.b1 - g.b0) / g.nb;
    for (int s = 0; s < n_samples; ++s) {
        Float ux = rng.next_float();
        Vec2d p = sample({ux, rng.next_float()});
        int ia = int(std::floor((p.x - g.a0) / da)), ib = int(std::floor((p.y - g.b0) / db));
        // Float round-off may put a sample on the far side of a domain edge by an ulp or so.
        if (ia == g.na && p.x < g.a1 + 1e-6 * (g.a1 - g.a0)) ia = g.na - 1;
        if (ib == g.nb && p.y < g.b1 + 1e-6 * (g.b1 - g.b0)) ib = g.nb - 1;
        // A sample outside the domain is a failure of the map: count it in an impossible cell.
        if (ia < 0 || ia >= g.na || ib < 0 || ib >= g.nb) {
            ADD_FAILURE() << "sample (" << p.x << ", " << p.y << ") outside the domain";
            return 0;
        }
        observed[std::size_t(ib * g.na + ia)] += 1;
    }
    double total = 0;
    for (int ib = 0; ib < g.nb; ++ib) {
        for (int ia = 0; ia < g.na; ++ia) {
            double mass = simpson_2d(density, g.a0 + ia * da, g.a0 + (ia + 1) * da, g.b0 + ib * db,
                                     g.b0 + (ib + 1) * db, 8, 8);
            expected[std::size_t(ib * g.na + ia)] = mass * n_samples;
            total += mass;
        }
    }
    EXPECT_NEAR(total, 1.0, 1e-4) << "density does not integrate to 1 over the grid";
    return chi2_test(observed, expected).p_value;
}

/// Same for 1D: cells over [a0, a1]; the domain may be cut at a1 with the tail mass put in a
/// last cell (for unbounded densities).
double chi2_p_value_1d(double a0, double a1, int n, const std::function<double(Float)>& sample,
                       const std::function<double(double)>& density, int n_samples, uint64_t seed,
                       bool tail_cell = false) {
    std::vector<double> observed(std::size_t(n + (tail_cell ? 1 : 0)), 0.0);
    std::vector<double> expected(observed.size(), 0.0);
    Pcg32 rng(seed);
    double d = (a1 - a0) / n;
    for (int s = 0; s < n_samples; ++s) {
        double x = sample(rng.next_float());
        int i = int(std::floor((x - a0) / d));
        if (tail_cell && x >= a1) i = n;
        if (i < 0 || i >= int(observed.size())) {
            ADD_FAILURE() << "sample " << x << " outside the domain";
            return 0;
        }
        observed[std::size_t(i)] += 1;
    }
    double total = 0;
    for (int i = 0; i < n; ++i) {
        double mass = simpson_1d(density, a0 + i * d, a0 + (i + 1) * d, 16);
        expected[std::size_t(i)] = mass * n_samples;
        total += mass;
    }
    if (tail_cell) expected[std::size_t(n)] = (1 - total) * n_samples;
    return chi2_test(observed, expected).p_value;
}

/// (theta, phi) of a unit direction, phi in [0, 2 pi).
Vec2d spherical_coords(Vec3 w) {
    // atan2 rather than acos: well conditioned near the poles.
    double theta = std::atan2(std::hypot(double(w.x), double(w.y)), double(w.z));
    double phi = std::atan2(double(w.y), double(w.x));
    if (phi < 0) phi += 2 * kPiD;
    return {theta, phi};
}

Vec3 direction(double theta, double phi) {
    return Vec3(Float(std::sin(theta) * std::cos(phi)), Float(std::sin(theta) * std::sin(phi)),
                Float(std::cos(theta)));
}

/// Distance on the circle [0, 1) (for azimuth-like coordinates that wrap).
double wrapped_distance(double a, double b) {
    double d = std::abs(a - b);
    return std::min(d, 1 - d);
}

/// Area of the parallelogram spanned by the partial derivatives of a direction map u -> w by
/// central differences: the solid angle per unit area of [0,1)^2, i.e. 1 / pdf_sa.
double direction_jacobian(const std::function<Vec3(Point2)>& f, Point2 u, double h = 1e-3) {
    auto dd = [&](Point2 a, Point2 b) {
        Vec3d wa(f(a)), wb(f(b));
        return (wb - wa) / (2 * h);
    };
    Float hf = Float(h);
    Vec3d du = dd({u.x - hf, u.y}, {u.x + hf, u.y});
    Vec3d dv = dd({u.x, u.y - hf}, {u.x, u.y + hf});
    return length(cross(du, dv));
}

/// |det J| of a planar map by central differences.
double planar_jacobian(const std::function<Vec2d(Point2)>& f, Point2 u, double h = 1e-3) {
    Float hf = Float(h);
    Vec2d du = (f({u.x + hf, u.y}) - f({u.x - hf, u.y})) / (2 * h);
    Vec2d dv = (f({u.x, u.y + hf}) - f({u.x, u.y - hf})) / (2 * h);
    return std::abs(du.x * dv.y - du.y * dv.x);
}

Vec2d to_d(Point2 p) { return {double(p.x), double(p.y)}; }

/// Random u in [margin, 1 - margin)^2.
Point2 inner_u(Pcg32& rng, Float margin = 0.01f) {
    Float a = rng.next_float(), b = rng.next_float();
    return {margin + (1 - 2 * margin) * a, margin + (1 - 2 * margin) * b};
}

// ---- disk ------------------------------------------------------------------------------------

TEST(Warp, ConcentricDiskChi2) {
    Grid2 g{0, 1, 0, 2 * kPiD, 12, 24};  // (r, phi): area element r dr dphi
    auto sample = [](Point2 u) {
        Point2 p = sample_uniform_disk_concentric(u);
        double r = std::hypot(double(p.x), double(p.y));
        double phi = std::atan2(double(p.y), double(p.x));
        return Vec2d(r, phi < 0 ? phi + 2 * kPiD : phi);
    };
    auto density = [](double r, double) { return double(uniform_disk_pdf()) * r; };
    EXPECT_GT(chi2_p_value_2d(g, sample, density, 500000, 1), kAlpha);
}

TEST(Warp, PolarDiskChi2) {
    Grid2 g{0, 1, 0, 2 * kPiD, 12, 24};
    auto sample = [](Point2 u) {
        Point2 p = sample_uniform_disk_polar(u);
        double r = std::hypot(double(p.x), double(p.y));
        double phi = std::atan2(double(p.y), double(p.x));
        return Vec2d(r, phi < 0 ? phi + 2 * kPiD : phi);
    };
    auto density = [](double r, double) { return double(uniform_disk_pdf()) * r; };
    EXPECT_GT(chi2_p_value_2d(g, sample, density, 500000, 2), kAlpha);
}

TEST(Warp, DiskRoundTripAndJacobian) {
    Pcg32 rng(10);
    for (int i = 0; i < 20000; ++i) {
        Point2 u = inner_u(rng, 0);
        Point2 p = sample_uniform_disk_concentric(u);
        ASSERT_LE(p.x * p.x + p.y * p.y, 1.0f + 1e-6f);
        Point2 v = invert_uniform_disk_concentric(p);
        EXPECT_NEAR(v.x, u.x, 1e-4);
        EXPECT_NEAR(v.y, u.y, 1e-4);

        Point2 q = sample_uniform_disk_polar(u);
        Point2 w = invert_uniform_disk_polar(q);
        EXPECT_NEAR(w.x, u.x, 1e-4);
        EXPECT_LT(wrapped_distance(w.y, u.y), 1e-4);
    }
    // Both maps are area preserving up to the constant: |det J| * pdf_area = 1. The concentric
    // map has kinks on the square's diagonals; stay off them.
    for (int i = 0; i < 2000; ++i) {
        Point2 u = inner_u(rng, 0.02f);
        double ox = 2.0 * u.x - 1, oy = 2.0 * u.y - 1;
        if (std::abs(std::abs(ox) - std::abs(oy)) < 0.01) continue;
        double jc =
            planar_jacobian([](Point2 a) { return to_d(sample_uniform_disk_concentric(a)); }, u);
        EXPECT_NEAR(jc * uniform_disk_pdf(), 1.0, 1e-2);
        if (u.x < 0.05f) continue;  // polar map: dr/du = 1 / (2 sqrt(u)) is steep near 0
        double jp = planar_jacobian([](Point2 a) { return to_d(sample_uniform_disk_polar(a)); }, u);
        EXPECT_NEAR(jp * uniform_disk_pdf(), 1.0, 1e-2);
    }
    EXPECT_EQ(sample_uniform_disk_concentric({0.5f, 0.5f}), Point2(0, 0));
}

TEST(Warp, DiskPdfIntegratesToOne) {
    double total = simpson_2d([](double r, double) { return double(uniform_disk_pdf()) * r; }, 0, 1,
                              0, 2 * kPiD, 8, 8);
    EXPECT_NEAR(total, 1.0, 1e-6);  // kInvPi is a float
}

// ---- hemisphere, sphere, cone ---------------------------------------------------------------

TEST(Warp, UniformHemisphereChi2) {
    Grid2 g{0, kPiD / 2, 0, 2 * kPiD, 10, 20};
    auto sample = [](Point2 u) {
        Vec3 w = sample_uniform_hemisphere(u);
        EXPECT_NEAR(length(w), 1.0f, 1e-5f);
        return spherical_coords(w);
    };
    auto density = [](double theta, double) {
        return double(uniform_hemisphere_pdf()) * std::sin(theta);
    };
    EXPECT_GT(chi2_p_value_2d(g, sample, density, 500000, 3), kAlpha);
}

TEST(Warp, CosineHemisphereChi2) {
    Grid2 g{0, kPiD / 2, 0, 2 * kPiD, 10, 20};
    auto sample = [](Point2 u) {
        Vec3 w = sample_cosine_hemisphere(u);
        EXPECT_NEAR(length(w), 1.0f, 1e-5f);
        EXPECT_GE(w.z, 0.0f);
        return spherical_coords(w);
    };
    auto density = [](double theta, double phi) {
        return double(cosine_hemisphere_pdf(direction(theta, phi).z)) * std::sin(theta);
    };
    EXPECT_GT(chi2_p_value_2d(g, sample, density, 500000, 4), kAlpha);
}

TEST(Warp, UniformSphereChi2) {
    Grid2 g{0, kPiD, 0, 2 * kPiD, 16, 20};
    auto sample = [](Point2 u) {
        Vec3 w = sample_uniform_sphere(u);
        EXPECT_NEAR(length(w), 1.0f, 1e-5f);
        return spherical_coords(w);
    };
    auto density = [](double theta, double) {
        return double(uniform_sphere_pdf()) * std::sin(theta);
    };
    EXPECT_GT(chi2_p_value_2d(g, sample, density, 500000, 5), kAlpha);
}

TEST(Warp, UniformConeChi2) {
    for (Float cos_max : {0.7f, -0.3f, 0.995f}) {
        double theta_max = std::acos(double(cos_max));
        Grid2 g{0, theta_max, 0, 2 * kPiD, 10, 16};
        auto sample = [cos_max](Point2 u) {
            Vec3 w = sample_uniform_cone(u, cos_max);
            EXPECT_NEAR(length(w), 1.0f, 1e-5f);
            return spherical_coords(w);
        };
        auto density = [cos_max](double theta, double) {
            return double(uniform_cone_pdf(cos_max)) * std::sin(theta);
        };
        EXPECT_GT(chi2_p_value_2d(g, sample, density, 300000, 6), kAlpha) << cos_max;
    }
}

TEST(Warp, DirectionalPdfsIntegrateToOne) {
    // In (theta, phi) with d omega = sin(theta) d theta d phi; the hemisphere densities over
    // the upper and lower hemispheres separately (Simpson needs smooth integrands).
    auto over = [](double t0, double t1, const std::function<double(Vec3)>& pdf_sa) {
        return simpson_2d([&](double t, double p) { return pdf_sa(direction(t, p)) * std::sin(t); },
                          t0, t1, 0, 2 * kPiD, 200, 16);
    };
    auto hemi = [](Vec3 w) { return w.z >= 0 ? double(uniform_hemisphere_pdf()) : 0.0; };
    auto cosine = [](Vec3 w) { return double(cosine_hemisphere_pdf(w.z)); };
    EXPECT_NEAR(over(0, kPiD / 2, hemi), 1.0, 1e-6);
    EXPECT_NEAR(over(kPiD / 2 + 1e-9, kPiD, hemi), 0.0, 1e-12);
    EXPECT_NEAR(over(0, kPiD / 2, cosine), 1.0, 1e-6);
    EXPECT_NEAR(over(kPiD / 2 + 1e-9, kPiD, cosine), 0.0, 1e-12);
    EXPECT_NEAR(over(0, kPiD, [](Vec3) { return double(uniform_sphere_pdf()); }), 1.0, 1e-6);
    // The cone pdf is constant inside the cone: integrate over its (theta, phi) extent.
    for (Float cos_max : {0.7f, -0.3f, 0.999f}) {
        double theta_max = std::acos(double(cos_max));
        double total = simpson_2d(
            [&](double t, double) { return double(uniform_cone_pdf(cos_max)) * std::sin(t); }, 0,
            theta_max, 0, 2 * kPiD, 64, 4);
        EXPECT_NEAR(total, 1.0, 1e-4) << cos_max;
    }
    EXPECT_EQ(cosine_hemisphere_pdf(-0.5f), 0.0f);
}

TEST(Warp, DirectionalRoundTrips) {
    Pcg32 rng(11);
    for (int i = 0; i < 20000; ++i) {
        Point2 u = inner_u(rng, 0);
        Point2 v = invert_uniform_hemisphere(sample_uniform_hemisphere(u));
        EXPECT_NEAR(v.x, u.x, 1e-4);
        EXPECT_LT(wrapped_distance(v.y, u.y), 1e-4);

        v = invert_cosine_hemisphere(sample_cosine_hemisphere(u));
        EXPECT_NEAR(v.x, u.x, 1e-4);
        EXPECT_NEAR(v.y, u.y, 1e-4);

        v = invert_uniform_sphere(sample_uniform_sphere(u));
        EXPECT_NEAR(v.x, u.x, 1e-4);
        EXPECT_LT(wrapped_distance(v.y, u.y), 1e-4);

        for (Float cos_max : {0.9f, 0.0f, -0.8f}) {
            v = invert_uniform_cone(sample_uniform_cone(u, cos_max), cos_max);
            EXPECT_NEAR(v.x, u.x, 1e-4);
            EXPECT_LT(wrapped_distance(v.y, u.y), 1e-4);
        }
    }
}

TEST(Warp, DirectionalJacobiansMatchPdfs) {
    // Solid angle per unit square area equals 1 / pdf_sa for a bijective map.
    Pcg32 rng(12);
    for (int i = 0; i < 2000; ++i) {
        Point2 u = inner_u(rng, 0.02f);
        Vec3 w = sample_uniform_hemisphere(u);
        EXPECT_NEAR(direction_jacobian(sample_uniform_hemisphere, u) * uniform_hemisphere_pdf(),
                    1.0, 1e-2);
        EXPECT_NEAR(direction_jacobian(sample_uniform_sphere, u) * uniform_sphere_pdf(), 1.0, 1e-2);
        for (Float cos_max : {0.9f, -0.5f}) {
            auto f = [cos_max](Point2 a) { return sample_uniform_cone(a, cos_max); };
            EXPECT_NEAR(direction_jacobian(f, u) * uniform_cone_pdf(cos_max), 1.0, 1e-2);
        }
        // Cosine map: kinks on the diagonals (inherited from the disk map), steep at the rim.
        double ox = 2.0 * u.x - 1, oy = 2.0 * u.y - 1;
        if (std::abs(std::abs(ox) - std::abs(oy)) < 0.01 ||
            std::max(std::abs(ox), std::abs(oy)) > 0.9)
            continue;
        w = sample_cosine_hemisphere(u);
        EXPECT_NEAR(direction_jacobian(sample_cosine_hemisphere, u) * cosine_hemisphere_pdf(w.z),
                    1.0, 1e-2);
    }
}

// ---- triangle --------------------------------------------------------------------------------

TEST(Warp, TriangleChi2) {
    // Parametrize the barycentric triangle by s = b0 in [0,1], t = b1 / (1 - b0) in [0,1]:
    // area element (1 - s) ds dt, so cells align with the triangle's edges.
    Grid2 g{0, 1, 0, 1, 16, 16};
    auto sample = [](Point2 u) {
        auto b = sample_uniform_triangle(u);
        EXPECT_GE(b[0], 0.0f);
        EXPECT_GE(b[1], 0.0f);
        EXPECT_GE(b[2], -1e-6f);
        EXPECT_NEAR(b[0] + b[1] + b[2], 1.0f, 1e-6f);
        double s = b[0];
        return Vec2d(s, s < 1 ? double(b[1]) / (1 - s) : 0.0);
    };
    // Uniform: density 2 per unit barycentric area (the triangle has area 1/2).
    auto density = [](double s, double) { return 2 * (1 - s); };
    EXPECT_GT(chi2_p_value_2d(g, sample, density, 500000, 7), kAlpha);
}

TEST(Warp, TriangleRoundTripAndJacobian) {
    Pcg32 rng(13);
    for (int i = 0; i < 20000; ++i) {
        Point2 u = inner_u(rng, 0);
        Point2 v = invert_uniform_triangle(sample_uniform_triangle(u));
        EXPECT_NEAR(v.x, u.x, 1e-4);
        EXPECT_NEAR(v.y, u.y, 1e-4);
    }
    for (int i = 0; i < 2000; ++i) {
        Point2 u = inner_u(rng, 0.01f);
        if (std::abs(u.x - u.y) < 0.01f) continue;  // the map's seam
        double j = planar_jacobian(
            [](Point2 a) {
                auto b = sample_uniform_triangle(a);
                return Vec2d(b[0], b[1]);
            },
            u);
        EXPECT_NEAR(j, 0.5, 5e-3);  // area preserving: triangle area / square area
    }
}

// ---- 1D and bilinear -------------------------------------------------------------------------

TEST(Warp, LinearChi2RoundTripAndNormalization) {
    for (auto [a, b] : {std::pair{0.3f, 2.0f}, std::pair{2.0f, 0.0f}, std::pair{1.0f, 1.0f}}) {
        auto density = [a = a, b = b](double x) { return double(linear_pdf(Float(x), a, b)); };
        EXPECT_NEAR(simpson_1d(density, 0, 1, 2), 1.0, 1e-6);
        auto sample = [a = a, b = b](Float u) { return double(sample_linear(u, a, b)); };
        EXPECT_GT(chi2_p_value_1d(0, 1, 40, sample, density, 200000, 14), kAlpha) << a << " " << b;
        Pcg32 rng(15);
        for (int i = 0; i < 1000; ++i) {
            Float u = rng.next_float();
            Float x = sample_linear(u, a, b);
            EXPECT_NEAR(invert_linear(x, a, b), u, 1e-4);
        }
    }
    EXPECT_EQ(linear_pdf(-0.1f, 1, 1), 0.0f);
}

TEST(Warp, BilinearChi2RoundTripAndJacobian) {
    std::array<Float, 4> w = {0.2f, 1.5f, 3.0f, 0.7f};
    Grid2 g{0, 1, 0, 1, 16, 16};
    auto sample = [&](Point2 u) { return to_d(sample_bilinear(u, w)); };
    auto density = [&](double x, double y) {
        return double(bilinear_pdf({Float(x), Float(y)}, w));
    };
    EXPECT_GT(chi2_p_value_2d(g, sample, density, 400000, 16), kAlpha);
    Pcg32 rng(17);
    for (int i = 0; i < 5000; ++i) {
        Point2 u = inner_u(rng, 0.01f);
        Point2 p = sample_bilinear(u, w);
        Point2 v = invert_bilinear(p, w);
        EXPECT_NEAR(v.x, u.x, 1e-4);
        EXPECT_NEAR(v.y, u.y, 1e-4);
        double j = planar_jacobian([&](Point2 a) { return to_d(sample_bilinear(a, w)); }, u);
        EXPECT_NEAR(j * bilinear_pdf(p, w), 1.0, 1e-2);
    }
}

TEST(Warp, ExponentialChi2AndRoundTrip) {
    const Float a = 2.5f;
    auto density = [a](double x) { return double(exponential_pdf(Float(x), a)); };
    auto sample = [a](Float u) { return double(sample_exponential(u, a)); };
    // Cells over [0, 3], the tail beyond 3 (mass exp(-7.5)) in one extra cell.
    EXPECT_GT(chi2_p_value_1d(0, 3, 30, sample, density, 200000, 18, /*tail_cell=*/true), kAlpha);
    // Normalization: the integral over [0, 20/a] plus the analytic tail exp(-20).
    EXPECT_NEAR(simpson_1d(density, 0, 20 / a, 2000) + std::exp(-20.0), 1.0, 1e-6);
    Pcg32 rng(19);
    for (int i = 0; i < 1000; ++i) {
        Float u = rng.next_float();
        EXPECT_NEAR(invert_exponential(sample_exponential(u, a), a), u, 1e-4);
    }
}

TEST(Warp, TentChi2AndRoundTrip) {
    const Float r = 1.5f;
    auto density = [r](double x) { return double(tent_pdf(Float(x), r)); };
    auto sample = [r](Float u) { return double(sample_tent(u, r)); };
    EXPECT_NEAR(simpson_1d(density, -r, 0, 2) + simpson_1d(density, 0, r, 2), 1.0, 1e-6);
    EXPECT_GT(chi2_p_value_1d(-r, r, 30, sample, density, 200000, 20), kAlpha);
    Pcg32 rng(21);
    for (int i = 0; i < 1000; ++i) {
        Float u = rng.next_float();
        EXPECT_NEAR(invert_tent(sample_tent(u, r), r), u, 1e-4);
    }
}

}  // namespace
}  // namespace sr

namespace sr {
namespace {

// The equal-area octahedral map and its inverse round-trip, and uniform points on the
// square map to uniformly distributed directions: E[z] = 0, E[z^2] = 1/3, E[x y] = 0, and
// each octant receives 1/8 of the points (binomial tolerance).
TEST(EqualAreaMap, RoundTripAndUniformity) {
    Pcg32 rng(7);
    const int n = 200000;
    double sz = 0, sz2 = 0, sxy = 0;
    int octant[8] = {};
    for (int i = 0; i < n; ++i) {
        Point2 p(rng.next_float(), rng.next_float());
        Vec3 w = equal_area_square_to_sphere(p);
        ASSERT_NEAR(length(w), 1, 1e-5);
        Point2 q = equal_area_sphere_to_square(w);
        ASSERT_NEAR(q.x, p.x, 2e-4) << p.x << " " << p.y;
        ASSERT_NEAR(q.y, p.y, 2e-4) << p.x << " " << p.y;
        sz += w.z;
        sz2 += w.z * w.z;
        sxy += w.x * w.y;
        ++octant[(w.x > 0) + 2 * (w.y > 0) + 4 * (w.z > 0)];
    }
    // Standard errors: sd(z) = 1/sqrt(3), sd(z^2) = sqrt(4/45), sd(xy) = sqrt(1/15).
    EXPECT_NEAR(sz / n, 0, 4.5 * std::sqrt(1.0 / 3 / n));
    EXPECT_NEAR(sz2 / n, 1.0 / 3, 4.5 * std::sqrt(4.0 / 45 / n));
    EXPECT_NEAR(sxy / n, 0, 4.5 * std::sqrt(1.0 / 15 / n));
    for (int o = 0; o < 8; ++o) EXPECT_NEAR(octant[o], n / 8.0, 4.5 * std::sqrt(n * (1.0 / 8) * (7.0 / 8)));
    // Poles and the equator: (0.5, 0.5) is +z, the corners are -z, edge midpoints on the equator.
    EXPECT_NEAR(equal_area_square_to_sphere(Point2(0.5f, 0.5f)).z, 1, 1e-6);
    EXPECT_NEAR(equal_area_square_to_sphere(Point2(0, 0)).z, -1, 1e-6);
    EXPECT_NEAR(equal_area_square_to_sphere(Point2(1, 0.5f)).x, 1, 1e-6);
}

}  // namespace
}  // namespace sr
