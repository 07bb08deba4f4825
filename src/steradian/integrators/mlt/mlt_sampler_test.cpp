// The Metropolis sampler of Integrator "mlt" on a target with a closed-form integral: the
// bootstrap's b estimates the integral of f, the chains' states are distributed as f / int f
// (Pearson chi-square on thinned states), and the expected-value splats of metropolis_step()
// estimate the integral of f over each cell (z-scores from the spread of independent chains).
// Seeds are fixed, so the tests are deterministic; tolerances come from estimated variances.
#include "steradian/integrators/mlt/mlt_sampler.h"

#include <gtest/gtest.h>

#include <cmath>
#include <vector>

#include "steradian/core/error.h"
#include "steradian/sampling/distribution.h"
#include "steradian/sampling/stats.h"

namespace sr {
namespace {

constexpr double kTwoPi = 6.283185307179586;

// f(x, y) = g(x) h(y) on [0, 1)^2: g(x) = x^2 + 0.1 except on the gap [0.4, 0.5) where it is
// 0 (the chains must cross it: by a large step, or by a small step from its edge), and
// h(y) = 1 + 0.9 sin(2 pi y), which is continuous across y = 0 = 1 (the small steps wrap).
double g(double x) { return x >= 0.4 && x < 0.5 ? 0 : x * x + 0.1; }
double h(double y) { return 1 + 0.9 * std::sin(kTwoPi * y); }
// Their integrals over [a, b].
double g_int(double a, double b) {
    auto G = [](double x) { return x * x * x / 3 + 0.1 * x; };
    double v = G(b) - G(a);
    const double lo = std::max(a, 0.4), hi = std::min(b, 0.5);
    if (hi > lo) v -= G(hi) - G(lo);
    return v;
}
double h_int(double a, double b) {
    return (b - a) + 0.9 * (std::cos(kTwoPi * a) - std::cos(kTwoPi * b)) / kTwoPi;
}

struct State {
    Float c = 0;
    double x = 0, y = 0;
};

// x is number 0 of stream 0, y number 1 of stream 2 (a number of stream 1 is read and
// ignored between them, as a path reads numbers it does not use).
void evaluate(MltSampler& s, State& st) {
    MltStream a(s, 0), b(s, 1), c(s, 2);
    st.x = a.get_1d();
    (void)b.get_1d();
    (void)c.get_1d();
    st.y = c.get_1d();
    st.c = Float(g(st.x) * h(st.y));
}

constexpr int kCells = 8;  // kCells x kCells cells
int cell(const State& st) {
    return std::min(kCells - 1, int(st.x * kCells)) * kCells + std::min(kCells - 1, int(st.y * kCells));
}
double cell_integral(int i) {
    const int cx = i / kCells, cy = i % kCells;
    return g_int(double(cx) / kCells, double(cx + 1) / kCells) *
           h_int(double(cy) / kCells, double(cy + 1) / kCells);
}
const double kIntegral = g_int(0, 1) * h_int(0, 1);  // 0.403

void check_chains(Float sigma, Float large_step) {
    SCOPED_TRACE(testing::Message() << "sigma " << sigma << ", large steps " << large_step);
    // Bootstrap: b, the mean of f over independent uniform states, estimates its integral.
    constexpr int kBoot = 20000;
    constexpr uint64_t kSeed = 7;
    std::vector<Float> w(kBoot);
    double sum = 0, sum2 = 0;
    for (int i = 0; i < kBoot; ++i) {
        MltSampler s(sigma, large_step, 3, uint64_t(i), kSeed);
        State st;
        evaluate(s, st);
        w[size_t(i)] = st.c;
        sum += st.c;
        sum2 += double(st.c) * st.c;
    }
    const double b = sum / kBoot;
    const double se_b = std::sqrt((sum2 / kBoot - b * b) / (kBoot - 1));
    EXPECT_LT(std::abs(b - kIntegral) / se_b, 4.0) << "b " << b << " +- " << se_b;
    const AliasTable table(w);

    // Chains started from bootstrap states drawn in proportion to f.
    constexpr int kChains = 64, kSteps = 20000, kThin = 100;
    std::vector<double> counts(kCells * kCells, 0);
    std::vector<std::vector<double>> est(kChains, std::vector<double>(kCells * kCells, 0));
    int accepted = 0;
    for (int k = 0; k < kChains; ++k) {
        Pcg32 rng(uint64_t(k), 99);
        const int index = table.sample(rng.next_float());
        MltSampler s(sigma, large_step, 3, uint64_t(index), kSeed);
        State cur, prop;
        evaluate(s, cur);
        EXPECT_EQ(cur.c, w[size_t(index)]);  // the chain starts from the bootstrap state
        s.reseed(uint64_t(kBoot + k), kSeed);
        auto eval = [&](State& st) { evaluate(s, st); };
        auto splat = [&](const State& st, Float wt) {
            est[size_t(k)][size_t(cell(st))] += double(wt) * st.c / kSteps;
        };
        for (int j = 1; j <= kSteps; ++j) {
            accepted += metropolis_step(s, rng, cur, prop, eval, splat);
            if (j % kThin == 0) counts[size_t(cell(cur))] += 1;
        }
    }
    const double rate = double(accepted) / (double(kChains) * kSteps);
    EXPECT_GT(rate, 0.05);
    EXPECT_LT(rate, 0.999);

    // (a) Thinned states (100 steps apart: with large steps, far beyond the chains'
    // correlation) against f / int f.
    std::vector<double> expected(kCells * kCells);
    const double n = double(kChains) * (kSteps / kThin);
    for (int i = 0; i < kCells * kCells; ++i) expected[size_t(i)] = n * cell_integral(i) / kIntegral;
    const Chi2Result chi = chi2_test(counts, expected);
    EXPECT_GT(chi.p_value, 1e-3) << "chi2 " << chi.statistic << " dof " << chi.dof;

    // (b) The expected-value splats: each chain's cell sums estimate int_cell f / int f;
    // their mean over chains against the closed form, z from the chains' spread. With the
    // variance estimated from K chains each z^2 is F(1, K - 1) distributed, of mean
    // (K - 1) / (K - 3); the sum is rescaled to a chi-square's mean.
    double stat = 0;
    for (int i = 0; i < kCells * kCells; ++i) {
        double m = 0, v = 0;
        for (int k = 0; k < kChains; ++k) m += est[size_t(k)][size_t(i)] / kChains;
        for (int k = 0; k < kChains; ++k) v += sqr(est[size_t(k)][size_t(i)] - m);
        const double se = std::sqrt(v / (kChains - 1) / kChains);
        const double p = cell_integral(i) / kIntegral;
        if (p == 0) {
            EXPECT_EQ(m, 0) << "cell " << i;  // nothing splatted into the gap
            continue;
        }
        ASSERT_GT(se, 0) << "cell " << i;
        stat += sqr((m - p) / se);
        // And b times it estimates the cell's integral of f itself.
        EXPECT_LT(std::abs(b * m - cell_integral(i)) / (b * se + m * se_b), 5.0) << "cell " << i;
    }
    const int dof = kCells * kCells - kCells;  // less the gap's cells (one column of x)
    stat *= double(kChains - 3) / double(kChains - 1);
    EXPECT_GT(chi2_sf(stat, dof), 1e-3) << "stat " << stat << " dof " << dof;
}

TEST(MltSampler, ChainsSampleTheTargetAndSplatItsIntegral) {
    check_chains(0.01f, 0.3f);  // pbrt-v4's defaults
    check_chains(0.1f, 0.05f);  // mostly small steps, which must cross the gap and wrap
}

// A rejected proposal restores every number it changed; an accepted one is the new state.
TEST(MltSampler, RejectRestoresAndAcceptKeeps) {
    for (const Float large : {0.0f, 0.5f, 1.0f}) {
        MltSampler s(0.05f, large, 2, 3, 1);
        std::vector<Float> state;
        for (int k = 0; k < 6; ++k) state.push_back(s.get(k % 2, k / 2));
        for (int it = 0; it < 200; ++it) {
            s.start_iteration();
            std::vector<Float> prop;
            // (Only some numbers are read by some proposals, as paths of other lengths do. A
            // large step replaces the numbers it does not read too: they are drawn afresh when
            // next read, so they are read here to know the state.)
            const int n = s.large_step() ? 6 : 2 + it % 5;
            for (int k = 0; k < n; ++k) prop.push_back(s.get(k % 2, k / 2));
            for (Float v : prop) {
                EXPECT_GE(v, 0);
                EXPECT_LT(v, 1);
            }
            if (it % 3 == 0) {
                s.accept();
                for (int k = 0; k < n; ++k) state[size_t(k)] = prop[size_t(k)];
            } else {
                s.reject();
            }
            for (int k = 0; k < 6; ++k)
                ASSERT_EQ(s.value(k % 2, k / 2), state[size_t(k)]) << "iteration " << it << " k " << k;
        }
    }
}

}  // namespace
}  // namespace sr

namespace sr {
namespace {

// A chain moved between processes (docs/distributed.md) continues exactly as it would have
// in place: a sampler saved after some steps and loaded into another (of other settings,
// and reading other numbers) gives, from then on, the same numbers, proposals and
// acceptances as the original, to the bit.
TEST(MltSampler, SavedAndLoadedContinuesExactly) {
    MltSampler a(0.01f, 0.3f, 3, 7, 42);
    Pcg32 rng(3, 9);
    auto step = [](MltSampler& s, Pcg32& r, std::vector<Float>& seen) {
        s.start_iteration();
        // Streams read to different lengths, as subpaths of different lengths do.
        for (int k = 0; k < 5; ++k) seen.push_back(s.get(0, k));
        for (int k = 0; k < 3; ++k) seen.push_back(s.get(1, k));
        seen.push_back(s.get(2, 0));
        if (r.next_float() < 0.5f)
            s.accept();
        else
            s.reject();
    };
    std::vector<Float> ignore;
    for (int i = 0; i < 50; ++i) step(a, rng, ignore);
    std::vector<char> msg;
    ByteWriter bw(msg);
    a.save(bw);
    bw.put(rng);
    MltSampler b(0.5f, 0.9f, 1, 0, 0);
    (void)b.get(0, 20);
    ByteReader br(msg.data(), msg.size());
    b.load(br);
    Pcg32 rng_b = br.get<Pcg32>();
    EXPECT_EQ(br.left(), 0u);
    std::vector<Float> seen_a, seen_b;
    for (int i = 0; i < 200; ++i) {
        step(a, rng, seen_a);
        step(b, rng_b, seen_b);
    }
    EXPECT_EQ(seen_a, seen_b);
    EXPECT_EQ(a.size(), b.size());
    // A truncated state is an error, not a sampler.
    ByteReader cut(msg.data(), msg.size() / 2);
    MltSampler c(0.01f, 0.3f, 3, 0, 0);
    EXPECT_THROW(c.load(cut), Error);
}

}  // namespace
}  // namespace sr
