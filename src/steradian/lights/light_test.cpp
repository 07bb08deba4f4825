#include "steradian/lights/light.h"
#include "steradian/lights/light_sampler.h"

#include <gtest/gtest.h>

#include <cmath>
#include <memory>
#include <numbers>
#include <vector>

#include "steradian/sampling/rng.h"
#include "steradian/sampling/stats.h"
#include "steradian/sampling/warp.h"

namespace sr {
namespace {

constexpr double kPiD = std::numbers::pi;
// The statistical tests in this file (irradiance z-tests and one chi-square) share a 1%
// family level (Sidak). Fixed seeds: a pass is reproducible.
const double kAlpha = sidak_alpha(0.01, 8);

SampledWavelengths test_wavelengths() { return SampledWavelengths::sample_uniform(0.37f); }

TriangleMesh make_mesh(std::vector<Point3> p, std::vector<uint32_t> idx) {
    TriangleMesh m;
    p.push_back(Point3(0, 0, 0));  // padding, as the scene builder does
    m.p = std::make_shared<std::vector<Point3>>(std::move(p));
    m.n = std::make_shared<std::vector<Normal3>>();
    m.uv = std::make_shared<std::vector<Point2>>();
    m.indices = std::make_shared<std::vector<uint32_t>>(std::move(idx));
    return m;
}

struct Estimate {
    double mean = 0, se = 0;
    int n_valid = 0;
};

/// Monte Carlo irradiance at ctx (normal ctx.ng) from one light: the mean of
/// L cos(theta) / pdf_sa over n light samples (0 for a failed sample), with its standard
/// error. Also checks, per sample, that pdf_li_point reproduces the returned pdf.
Estimate irradiance(const DiffuseAreaLight& light, const LightSampleContext& ctx, int n,
                    uint64_t seed) {
    SampledWavelengths lambda = test_wavelengths();
    Pcg32 rng(seed, 21);
    double s = 0, s2 = 0;
    Estimate e;
    for (int k = 0; k < n; ++k) {
        auto ls = light.sample_li(ctx, {rng.next_float(), rng.next_float()}, lambda);
        double v = 0;
        if (ls) {
            ++e.n_valid;
            EXPECT_NEAR(length(ls->wi), 1, 1e-5);
            EXPECT_FALSE(ls->delta);
            double pdf = light.pdf_li_point(ctx, ls->p_light, ls->n_light);
            EXPECT_NEAR(pdf / ls->pdf_sa, 1, 1e-4) << "pdf_li_point disagrees with sample_li";
            v = ls->L[0] * std::max(0.0, double(dot(ctx.ng, ls->wi))) / ls->pdf_sa;
        }
        s += v;
        s2 += v * v;
    }
    e.mean = s / n;
    e.se = std::sqrt(std::max(0.0, s2 / n - e.mean * e.mean) / (n - 1));
    return e;
}

void expect_irradiance(const Estimate& e, double expected, const char* what) {
    EXPECT_GT(z_test_p(e.mean, expected, e.se), kAlpha)
        << what << ": estimate " << e.mean << " +- " << e.se << ", expected " << expected;
    // The test must have the power to see a 2% error.
    EXPECT_LT(e.se, 0.005 * expected) << what;
}

// ---- diffuse area lights -----------------------------------------------------------------------

TEST(DiffuseAreaLight, DiskIrradianceOnItsAxis) {
    // A Lambertian disk of radius R and radiance L, facing a point at height h on its axis:
    // E = pi L R^2 / (h^2 + R^2).
    const double R = 1.5, h = 2, Lv = 3;
    Disk d;
    d.radius = Float(R);
    // Normal +z rotated to -z, towards the receiver at the origin.
    d.world_from_object = Transform::translate({0, 0, h}) * Transform::rotate(180, {1, 0, 0});
    DiffuseAreaLight light;
    light.disk = &d;
    light.radiance = ConstantSpectrum{Float(Lv)};
    light.area = d.area();
    LightSampleContext ctx{{0, 0, 0}, {0, 0, 0}, {0, 0, 1}};
    double expected = kPiD * Lv * R * R / (h * h + R * R);
    Estimate e = irradiance(light, ctx, 100000, 1);
    EXPECT_EQ(e.n_valid, 100000);
    expect_irradiance(e, expected, "disk");

    // Facing away: a one-sided emitter sends nothing; two-sided, the same irradiance.
    Disk up = d;
    up.world_from_object = Transform::translate({0, 0, h});
    DiffuseAreaLight back = light;
    back.disk = &up;
    Estimate eb = irradiance(back, ctx, 1000, 2);
    EXPECT_EQ(eb.n_valid, 0);
    EXPECT_EQ(eb.mean, 0);
    back.two_sided = true;
    expect_irradiance(irradiance(back, ctx, 100000, 3), expected, "two-sided disk");
}

TEST(DiffuseAreaLight, SphereIrradianceFacingIt) {
    // A uniformly emitting sphere of radius r at distance d on the receiver's normal (fully
    // above its horizon): E = pi L sin^2(theta_max) = pi L (r / d)^2. Radius 2 scaled by 0.25.
    const double r = 0.5, dist = 3, Lv = 2;
    Sphere s;
    s.radius = 2;
    s.z_min = -2;  // the whole sphere
    s.z_max = 2;
    s.world_from_object = Transform::translate({1, 1, 1 + dist}) * Transform::scale({0.25, 0.25, 0.25});
    DiffuseAreaLight light;
    light.sphere = &s;
    light.radiance = ConstantSpectrum{Float(Lv)};
    light.area = s.area();
    EXPECT_NEAR(light.area, 4 * kPiD * r * r, 1e-5);
    LightSampleContext ctx{{1, 1, 1}, {0, 0, 0}, {0, 0, 1}};
    expect_irradiance(irradiance(light, ctx, 100000, 4), kPiD * Lv * r * r / (dist * dist),
                      "sphere");
    // Close to the sphere (theta_max = 60 degrees): still pi L sin^2 theta_max.
    LightSampleContext near{{1, 1, Float(1 + dist - 2 * r / std::sqrt(3.0))}, {0, 0, 0}, {0, 0, 1}};
    expect_irradiance(irradiance(light, near, 100000, 5), kPiD * Lv * 0.75, "sphere, close");
}

/// Irradiance from a uniformly emitting polygon (Lambert's formula): with u_i the unit vectors
/// from x to the vertices, E = L / 2 |sum_i acos(u_i . u_i+1) n . normalize(u_i x u_i+1)|,
/// for a polygon entirely above the horizon of n.
double polygon_irradiance(const std::vector<Vec3d>& v, Vec3d x, Vec3d n, double L) {
    double sum = 0;
    for (size_t i = 0; i < v.size(); ++i) {
        Vec3d a = normalize(v[i] - x), b = normalize(v[(i + 1) % v.size()] - x);
        double theta = std::acos(std::clamp(dot(a, b), -1.0, 1.0));
        sum += theta * dot(n, normalize(cross(a, b)));
    }
    return L / 2 * std::abs(sum);
}

TEST(DiffuseAreaLight, TriangleIrradianceMatchesLambertsFormula) {
    const double Lv = 4;
    // A tilted triangle above the receiver, wound so that its normal faces the origin.
    std::vector<Vec3d> v = {{-1, -0.5, 1.5}, {0, 1.2, 2.5}, {1.5, 0, 1.8}};
    Vec3d ng = cross(v[1] - v[0], v[2] - v[0]);
    ASSERT_LT(dot(ng, v[0]), 0) << "the test triangle must face the origin";
    TriangleMesh m = make_mesh({Point3(v[0]), Point3(v[1]), Point3(v[2])}, {0, 1, 2});
    DiffuseAreaLight light;
    light.triangle = m.triangle(0);
    light.radiance = ConstantSpectrum{Float(Lv)};
    light.area = m.triangle_area(0);
    for (Vec3d n : {Vec3d(0, 0, 1), normalize(Vec3d(0.3, -0.2, 1))}) {
        LightSampleContext ctx{{0, 0, 0}, {0, 0, 0}, Normal3(n)};
        expect_irradiance(irradiance(light, ctx, 100000, 6),
                          polygon_irradiance(v, {0, 0, 0}, n, Lv), "triangle");
    }
}

TEST(DiffuseAreaLight, PolygonFormulaAgreesWithTheDiskLimit) {
    // The helper above, checked against a closed form: a regular 720-gon of circumradius R
    // on the axis approaches the disk's pi L R^2 / (h^2 + R^2).
    std::vector<Vec3d> v;
    const int n = 720;
    for (int i = 0; i < n; ++i) {
        double phi = 2 * kPiD * i / n;
        v.push_back({1.5 * std::cos(phi), 1.5 * std::sin(phi), 2});
    }
    EXPECT_NEAR(polygon_irradiance(v, {0, 0, 0}, {0, 0, 1}, 3), kPiD * 3 * 2.25 / 6.25, 1e-4);
}

TEST(DiffuseAreaLight, EmissionIsOneSidedUnlessTwoSided) {
    DiffuseAreaLight light;
    light.radiance = ConstantSpectrum{2};
    light.scale = 1.5f;
    SampledWavelengths lambda = test_wavelengths();
    EXPECT_FLOAT_EQ(light.l({0, 0, 1}, {0, 0.6f, 0.8f}, lambda)[0], 3);
    EXPECT_EQ(light.l({0, 0, 1}, {0, 0.6f, -0.8f}, lambda)[0], 0);
    light.two_sided = true;
    EXPECT_FLOAT_EQ(light.l({0, 0, 1}, {0, 0.6f, -0.8f}, lambda)[0], 3);
}

TEST(DiffuseAreaLight, PowerIsPiLA) {
    // A Lambertian emitter's exitance is pi L, so Phi = pi L A (twice for two-sided), here
    // weighted by V(lambda): phi_y = scale pi A integral(L ybar).
    Disk d;
    d.radius = 2;
    DiffuseAreaLight light;
    light.disk = &d;
    light.radiance = ConstantSpectrum{1};
    light.scale = 0.5f;
    light.area = d.area();
    double y = spectrum_to_photometric(ConstantSpectrum{1});
    EXPECT_NEAR(y, kCieYIntegral, 1e-3);
    EXPECT_NEAR(light.phi_y(), 0.5 * kPiD * 4 * kPiD * y, 1e-3 * light.phi_y());
    light.two_sided = true;
    EXPECT_NEAR(light.phi_y(), kPiD * 4 * kPiD * y, 1e-3 * light.phi_y());
}

// ---- point and spot lights -----------------------------------------------------------------------

TEST(PointLight, InverseSquareLaw) {
    PointLight pl;
    pl.p = {1, 2, 3};
    pl.intensity = ConstantSpectrum{5};
    pl.scale = 0.7f;
    SampledWavelengths lambda = test_wavelengths();
    Pcg32 rng(8, 8);
    for (double d : {0.1, 1.0, 2.5, 40.0}) {
        Vec3d dir = normalize(Vec3d(sample_uniform_sphere({rng.next_float(), rng.next_float()})));
        Point3 ref = Point3(Vec3d(pl.p) - dir * d);
        auto s = pl.sample_li({ref, {0, 0, 0}, {0, 0, 0}}, {0.5f, 0.5f}, lambda);
        ASSERT_TRUE(s.has_value());
        EXPECT_NEAR(s->L[0], 5 * 0.7 / (d * d), 1e-5 * 3.5 / (d * d)) << d;  // E = I / d^2
        EXPECT_NEAR(dot(Vec3d(s->wi), dir), 1, 1e-6);
        EXPECT_TRUE(s->delta);
        EXPECT_EQ(s->pdf_sa, 1);
        EXPECT_EQ(s->p_light, pl.p);
    }
    EXPECT_FALSE(pl.sample_li({pl.p, {0, 0, 0}, {0, 0, 0}}, {0.5f, 0.5f}, lambda).has_value());
    // An isotropic source of intensity I emits 4 pi I.
    EXPECT_NEAR(pl.phi_y(), 4 * kPiD * 0.7 * 5 * kCieYIntegral, 1e-3 * pl.phi_y());
}

/// A spot at p whose axis points along -x (light space +z rotated by -90 degrees about y).
SpotLight make_spot(Point3 p, double start_deg, double end_deg) {
    SpotLight sl;
    sl.p = p;
    sl.light_from_world =
        (Transform::translate(Vec3d(p)) * Transform::rotate(-90, {0, 1, 0})).inverse();
    sl.intensity = ConstantSpectrum{2};
    sl.scale = 1.5f;
    sl.cos_falloff_start = Float(std::cos(start_deg * kPiD / 180));
    sl.cos_falloff_end = Float(std::cos(end_deg * kPiD / 180));
    return sl;
}

/// The spot's L at a point at angle theta (degrees) from the axis and distance d, or -1 if
/// sample_li returns nothing.
double spot_l(const SpotLight& sl, double theta_deg, double d, double azimuth = 0.7) {
    double th = theta_deg * kPiD / 180;
    // Axis -x; perpendicular directions +y and +z.
    Vec3d w = Vec3d(-std::cos(th), std::sin(th) * std::cos(azimuth), std::sin(th) * std::sin(azimuth));
    Point3 ref = Point3(Vec3d(sl.p) + w * d);
    auto s = sl.sample_li({ref, {0, 0, 0}, {0, 0, 0}}, {0.5f, 0.5f}, test_wavelengths());
    return s ? double(s->L[0]) : -1;
}

TEST(SpotLight, FalloffIsOneInsideZeroOutsideSmoothstepBetween) {
    SpotLight sl = make_spot({1, 2, 3}, 20, 30);
    const double full = 2 * 1.5;  // I scale
    for (double d : {0.5, 2.0}) {
        // Inside the inner cone: the full inverse-square value.
        for (double th : {0.0, 10.0, 19.9})
            EXPECT_NEAR(spot_l(sl, th, d), full / (d * d), 1e-5 * full / (d * d)) << th;
        // Outside the outer cone: no light (including straight behind).
        for (double th : {30.1, 45.0, 90.0, 179.0}) EXPECT_EQ(spot_l(sl, th, d), -1) << th;
        // Between: pbrt-v4's smoothstep of cos(theta) from cos(30) (0) to cos(20) (1).
        for (double th : {20.5, 22.0, 25.0, 28.0, 29.5}) {
            double c = std::cos(th * kPiD / 180);
            double t = (c - std::cos(30 * kPiD / 180)) / (std::cos(20 * kPiD / 180) - std::cos(30 * kPiD / 180));
            double ss = t * t * (3 - 2 * t);
            EXPECT_NEAR(spot_l(sl, th, d) * d * d / full, ss, 2e-4) << th;
        }
    }
    // Monotone and continuous across the transition.
    double prev = spot_l(sl, 19.99, 1);
    EXPECT_NEAR(prev, full, 1e-3 * full);
    for (double th = 20; th < 30; th += 0.25) {
        double v = spot_l(sl, th, 1);
        EXPECT_LE(v, prev + 1e-6) << th;
        prev = v;
    }
    EXPECT_LT(spot_l(sl, 29.99, 1), 1e-5 * full);
}

TEST(SpotLight, PowerIsTheIntegralOfTheFalloff) {
    // Phi = scale * I * integral over the sphere of the falloff, measured here from
    // sample_li itself (2 pi times a Simpson integral over cos theta), against phi_y.
    SpotLight sl = make_spot({0, 0, 0}, 15, 40);
    auto falloff = [&](double mu) {
        double th = std::acos(std::clamp(mu, -1.0, 1.0)) * 180 / kPiD;
        double v = spot_l(sl, th, 1);
        return v < 0 ? 0.0 : v / (2 * 1.5);
    };
    // Integrate piecewise so the kinks at the cone angles are nodes.
    double c15 = std::cos(15 * kPiD / 180), c40 = std::cos(40 * kPiD / 180);
    double integral = simpson_1d(falloff, c40, c15, 2000) + simpson_1d(falloff, c15, 1, 200);
    double y = spectrum_to_photometric(ConstantSpectrum{2});
    EXPECT_NEAR(sl.phi_y(), 1.5 * y * 2 * kPiD * integral, 1e-3 * sl.phi_y());
    // Closed form: 2 pi [(1 - cos_start) + (cos_start - cos_end) / 2].
    EXPECT_NEAR(integral, (1 - c15) + (c15 - c40) / 2, 1e-5);
}

// ---- distant and infinite lights -------------------------------------------------------------

TEST(DistantLight, ArrivesFromItsDirection) {
    DistantLight dl;
    dl.w_light = normalize(Vec3(1, 1, 1));
    dl.radiance = ConstantSpectrum{3};
    dl.scale = 2;
    dl.scene_radius = 10;
    auto s = dl.sample_li({{1, 2, 3}, {0, 0, 0}, {0, 0, 1}}, {0.2f, 0.9f}, test_wavelengths());
    ASSERT_TRUE(s.has_value());
    EXPECT_FLOAT_EQ(s->L[0], 6);
    EXPECT_EQ(s->wi, dl.w_light);
    EXPECT_TRUE(s->delta);
    EXPECT_TRUE(s->at_infinity);
    // The shadow-ray end point is outside the scene's bounding sphere.
    EXPECT_GT(distance(s->p_light, Point3(1, 2, 3)), 10);
}

TEST(UniformInfiniteLight, PdfIsUniformAndIrradianceIsPiL) {
    UniformInfiniteLight il;
    il.radiance = ConstantSpectrum{2};
    il.scale = 0.5f;
    il.scene_radius = 5;
    LightSampleContext ctx{{0, 0, 0}, {0, 0, 0}, {0, 0, 1}};
    SampledWavelengths lambda = test_wavelengths();
    Pcg32 rng(9, 9);
    const int n = 100000;
    double s = 0, s2 = 0, pdf_sum = 0;
    std::vector<double> obs(100, 0.0), expected(100, n / 100.0);
    for (int k = 0; k < n; ++k) {
        auto ls = il.sample_li(ctx, {rng.next_float(), rng.next_float()}, lambda);
        ASSERT_TRUE(ls.has_value());
        ASSERT_NEAR(length(ls->wi), 1, 1e-5);
        ASSERT_EQ(ls->pdf_sa, il.pdf_li(ctx, ls->wi));
        EXPECT_TRUE(ls->at_infinity);
        double v = ls->L[0] * std::max(0.0, double(ls->wi.z)) / ls->pdf_sa;
        s += v;
        s2 += v * v;
        // Uniform on the sphere: z and phi uniform.
        int iz = std::clamp(int((ls->wi.z + 1) / 2 * 10), 0, 9);
        double phi = std::atan2(ls->wi.y, ls->wi.x) + kPiD;
        int ip = std::clamp(int(phi / (2 * kPiD) * 10), 0, 9);
        obs[size_t(iz * 10 + ip)] += 1;
        // Integral of the pdf over the sphere, estimated with independent uniform directions.
        Vec3 w = sample_uniform_sphere({rng.next_float(), rng.next_float()});
        pdf_sum += il.pdf_li(ctx, w) * 4 * kPiD;
    }
    EXPECT_NEAR(pdf_sum / n, 1, 1e-5);
    EXPECT_GT(chi2_test(obs, expected).p_value, kAlpha);
    // Irradiance from a uniform sky on a plane: E = pi L.
    double mean = s / n, se = std::sqrt((s2 / n - mean * mean) / (n - 1));
    EXPECT_GT(z_test_p(mean, kPiD * 2 * 0.5, se), kAlpha) << mean << " +- " << se;
    EXPECT_LT(se, 0.01 * kPiD);
    // The radiance seen along any escaping ray.
    EXPECT_FLOAT_EQ(il.le({0, 1, 0}, lambda)[0], 1);
}

TEST(Light, VariantDispatchMatchesTheAlternative) {
    PointLight pl;
    pl.p = {0, 0, 2};
    pl.intensity = ConstantSpectrum{1};
    Light l = pl;
    LightSampleContext ctx{{0, 0, 0}, {0, 0, 0}, {0, 0, 1}};
    auto a = sample_li(l, ctx, {0.1f, 0.2f}, test_wavelengths());
    ASSERT_TRUE(a.has_value());
    EXPECT_FLOAT_EQ(a->L[0], 0.25f);
    EXPECT_FLOAT_EQ(light_phi_y(l), pl.phi_y());
}

// pbrt-v4's BVHLightSampler gives lights at infinity (infinite, distant) probability
// 1 / (n_infinite + 1) each when there are bounded lights; ours ("bvh") then shares the rest
// among the bounded lights by power: point lights of intensity 1 and 3 (power 4 pi I).
TEST(LightSampler, BvhGivesEachLightAtInfinityItsShare) {
    auto point = [](Float i) {
        PointLight pl;
        pl.intensity = ConstantSpectrum{1};
        pl.scale = i;
        return Light(pl);
    };
    UniformInfiniteLight sky;
    sky.radiance = ConstantSpectrum{1};
    sky.scene_radius = 1000;  // a sky whose power dwarfs the lamps'
    DistantLight sun;
    sun.w_light = {0, 0, 1};
    sun.radiance = ConstantSpectrum{1};
    std::vector<Light> lights{point(1), Light(sky), point(3), Light(sun)};
    LightSampler s;
    s.build(lights, LightSamplerKind::InfiniteShare);
    EXPECT_NEAR(s.pmf(1), 1.0 / 3, 1e-6);
    EXPECT_NEAR(s.pmf(3), 1.0 / 3, 1e-6);
    EXPECT_NEAR(s.pmf(0), 1.0 / 3 * 1 / 4, 1e-6);
    EXPECT_NEAR(s.pmf(2), 1.0 / 3 * 3 / 4, 1e-6);
    // "power": the sky takes nearly everything; "uniform": a quarter each.
    s.build(lights, LightSamplerKind::Power);
    EXPECT_GT(s.pmf(1), 0.99);
    s.build(lights, LightSamplerKind::Uniform);
    for (int i = 0; i < 4; ++i) EXPECT_NEAR(s.pmf(i), 0.25, 1e-6);
    // Only lights at infinity: they share everything equally.
    s.build({Light(sky), Light(sun)}, LightSamplerKind::InfiniteShare);
    EXPECT_NEAR(s.pmf(0), 0.5, 1e-6);
    EXPECT_NEAR(s.pmf(1), 0.5, 1e-6);
}

}  // namespace
}  // namespace sr
