#include "steradian/bsdf/bsdf.h"

#include <gtest/gtest.h>

#include "steradian/sampling/rng.h"
#include "steradian/sampling/warp.h"

namespace sr {
namespace {

// With a shading normal ns that differs from the geometric normal ng, light transported
// along a path must carry the same throughput whichever end the path is traced from
// (Veach 1997, sec. 5.3.4): per unit geometric measure, the radiance kernel
// f(wo -> wi) |wi . ns| / |wi . ng| equals the importance kernel at the same vertex traced
// the other way, f*(wi -> wo) |wo . ns| / |wo . ng|. For a reciprocal (Lambertian) lobe
// that holds only with the adjoint correction.
TEST(BsdfAdjoint, ShadingNormalCorrectionBalancesBothDirections) {
    Pcg32 rng(3);
    const Normal3 ng(0, 0, 1);
    for (int trial = 0; trial < 200; ++trial) {
        // A shading normal tilted up to ~50 deg from ng.
        Vec3 ns = normalize(Vec3(rng.next_float() - 0.5f, rng.next_float() - 0.5f, 0.6f));
        Bsdf b(Frame::from_z(ns), ng, LambertLobe{SampledSpectrum(0.7f)});
        Vec3 wo = sample_uniform_hemisphere(Point2(rng.next_float(), rng.next_float()));
        Vec3 wi = sample_uniform_hemisphere(Point2(rng.next_float(), rng.next_float()));
        if (dot(wo, ns) <= 0.05f || dot(wi, ns) <= 0.05f) continue;
        double rad = b.f(wo, wi, TransportMode::Radiance)[0] * absdot(wi, ns) / absdot(wi, ng);
        double imp = b.f(wi, wo, TransportMode::Importance)[0] * absdot(wo, ns) / absdot(wo, ng);
        EXPECT_NEAR(imp, rad, 1e-5 * rad) << trial;
        // evaluate() and sample() apply the same factor.
        Bsdf::Eval e = b.evaluate(wi, wo, TransportMode::Importance);
        EXPECT_NEAR(e.f[0], b.f(wi, wo, TransportMode::Importance)[0], 1e-6);
        auto s = b.sample(wi, 0.5f, Point2(rng.next_float(), rng.next_float()), TransportMode::Importance);
        ASSERT_TRUE(s);
        EXPECT_NEAR(s->f[0], b.f(wi, s->wi, TransportMode::Importance)[0], 1e-5 * s->f[0] + 1e-7);
    }
    // With ns = ng the correction is 1.
    Bsdf flat(Frame::from_z(ng), ng, LambertLobe{SampledSpectrum(0.7f)});
    Vec3 a = normalize(Vec3(0.3f, 0.1f, 0.9f)), c = normalize(Vec3(-0.5f, 0.2f, 0.7f));
    EXPECT_FLOAT_EQ(flat.f(a, c, TransportMode::Importance)[0], flat.f(a, c, TransportMode::Radiance)[0]);
}

// A lobe that declares kIgnoresUc lets the path skip computing uc (Bsdf::uses_uc): its
// sample() must then be the same whatever uc is. A lobe that chooses between components
// with uc (a dielectric's reflection or transmission) must report that it uses it.
TEST(BsdfUsesUc, LobesThatSayTheyIgnoreUcSampleTheSameForAnyUc) {
    Pcg32 rng(11);
    const Frame frame = Frame::from_z(Vec3(0, 0, 1));
    const Normal3 ng(0, 0, 1);
    const TrowbridgeReitz rough{0.3f, 0.2f}, smooth{0, 0};
    std::vector<Bsdf> ignoring = {
        Bsdf(frame, ng, LambertLobe{SampledSpectrum(0.6f)}),
        Bsdf(frame, ng, ConductorLobe{SampledSpectrum(0.2f), SampledSpectrum(3.9f), rough}),
        Bsdf(frame, ng, ConductorLobe{SampledSpectrum(0.2f), SampledSpectrum(3.9f), smooth}),
    };
    for (const Bsdf& b : ignoring) {
        EXPECT_FALSE(b.uses_uc());
        for (int trial = 0; trial < 200; ++trial) {
            Vec3 wo = sample_uniform_sphere(Point2(rng.next_float(), rng.next_float()));
            Point2 u(rng.next_float(), rng.next_float());
            auto a = b.sample(wo, 0.01f, u), c = b.sample(wo, 0.99f, u);
            ASSERT_EQ(bool(a), bool(c)) << trial;
            if (!a) continue;
            EXPECT_EQ(a->wi, c->wi) << trial;
            EXPECT_EQ(a->pdf_sa, c->pdf_sa) << trial;
            for (int i = 0; i < kSpectrumSamples; ++i) EXPECT_EQ(a->f[i], c->f[i]) << trial;
        }
    }
    Bsdf glass(frame, ng, DielectricLobe{1.5f, smooth});
    EXPECT_TRUE(glass.uses_uc());
    // At normal incidence F = ((1.5 - 1) / (1.5 + 1))^2 = 0.04: uc below F reflects,
    // above it transmits.
    Vec3 wo(0, 0, 1);
    auto r = glass.sample(wo, 0.01f, Point2(0.5f, 0.5f));
    auto t = glass.sample(wo, 0.5f, Point2(0.5f, 0.5f));
    ASSERT_TRUE(r && t);
    EXPECT_GT(r->wi.z, 0);
    EXPECT_LT(t->wi.z, 0);
}


// pbrt-v4's TrowbridgeReitzDistribution::Regularize: an alpha below 0.3 becomes
// clamp(2 alpha, 0.1, 0.3), per axis; Bsdf::regularize applies it to dielectric and conductor
// lobes and to both layers of a coated conductor, and leaves a Lambertian lobe alone.
TEST(BsdfRegularize, AlphaIsDoubledAndClampedAsPbrtV4) {
    TrowbridgeReitz mf{0.0f, 0.12f};
    mf.regularize();
    EXPECT_FLOAT_EQ(mf.alpha_x, 0.1f);
    EXPECT_FLOAT_EQ(mf.alpha_y, 0.24f);
    mf = TrowbridgeReitz{0.2f, 0.5f};
    mf.regularize();
    EXPECT_FLOAT_EQ(mf.alpha_x, 0.3f);
    EXPECT_FLOAT_EQ(mf.alpha_y, 0.5f);

    const Frame frame = Frame::from_z(Vec3(0, 0, 1));
    DielectricLobe glass;
    glass.eta = 1.5f;
    Bsdf b(frame, Normal3(0, 0, 1), glass);
    EXPECT_TRUE(b.is_specular_only());
    b.regularize();
    EXPECT_FALSE(b.is_specular_only());
    EXPECT_FLOAT_EQ(std::get<DielectricLobe>(b.lobe()).mf.alpha_x, 0.1f);

    CoatedConductorLobe coated;
    coated.top.eta = 1.5f;
    coated.bottom.mf = TrowbridgeReitz{0.05f, 0.05f};
    Bsdf c(frame, Normal3(0, 0, 1), coated);
    c.regularize();
    EXPECT_FLOAT_EQ(std::get<CoatedConductorLobe>(c.lobe()).top.mf.alpha_y, 0.1f);
    EXPECT_FLOAT_EQ(std::get<CoatedConductorLobe>(c.lobe()).bottom.mf.alpha_x, 0.1f);

    Bsdf d(frame, Normal3(0, 0, 1), LambertLobe{SampledSpectrum(0.5f)});
    const uint8_t before = d.flags();
    d.regularize();
    EXPECT_EQ(d.flags(), before);
}

}  // namespace
}  // namespace sr
