// Per-lobe BSDF costs, through the world-space Bsdf wrapper an integrator calls (change of
// frame + std::visit): ns per sample() and ns per f() + pdf() pair, for every alternative of
// LobeVariant (an alternative without an instance here is reported as a skipped benchmark
// "BM_BsdfMissing/<index>"). Inputs are pre-drawn (4096 random triples and directions), so
// the random number generator is not timed. Run:
//   build/release/steradian_bench --benchmark_filter='BM_Bsdf'
#include <benchmark/benchmark.h>

#include <string>
#include <vector>

#include "steradian/bsdf/bsdf.h"
#include "steradian/sampling/rng.h"
#include "steradian/sampling/warp.h"
#include "support/measured_standin.h"

namespace sr {
namespace {

struct Instance {
    std::string name;
    LobeVariant lobe;
};

/// Stand-ins of the RGL database's tables (tests/support/measured_standin.h) at the database's
/// usual resolution: GGX alpha 0.3 (isotropic) or (0.15, 0.4) with 9 phi_i.
const MeasuredBrdf& standin(bool anisotropic) {
    auto make = [](bool aniso) {
        test::StandinSpec s;
        if (aniso) {
            s.alpha_x = 0.15f;
            s.alpha_y = 0.4f;
            s.anisotropic = true;
        }
        return parse_measured_brdf(test::standin_bytes(s), "standin.bsdf");
    };
    static const MeasuredBrdf iso = make(false), aniso = make(true);
    return anisotropic ? aniso : iso;
}
SampledWavelengths standin_lambda() {
    SampledWavelengths w;
    w.lambda = {420, 510, 590, 680};
    w.pdf = {1, 1, 1, 1};
    return w;
}

std::vector<Instance> instances() {
    LafortuneLobe laf1;
    laf1.rho_d = SampledSpectrum(0.3f);
    laf1.lobes[0] = {-1, -1, 1, 20, 2.5f};
    laf1.count = 1;
    LafortuneLobe laf3 = laf1;
    laf3.lobes[1] = {0, 0, 1, 3, 0.3f};
    laf3.lobes[2] = {0.8f, 0.8f, 0.9f, 6, 0.3f};
    laf3.count = 3;
    SampledSpectrum gold_eta({0.2f, 0.4f, 0.9f, 1.3f}), gold_k({3.5f, 2.9f, 2.2f, 1.9f});
    // pbrt-v4's coated defaults: smooth interface of eta 1.5, thickness 0.01, no medium albedo.
    CoatedDiffuseLobe coated_diffuse;
    coated_diffuse.top = DielectricLobe{1.5f, {}};
    coated_diffuse.bottom = LambertLobe{SampledSpectrum(0.5f)};
    coated_diffuse.albedo = SampledSpectrum(0);
    coated_diffuse.thickness = 0.01f;
    CoatedConductorLobe coated_conductor;
    coated_conductor.top = DielectricLobe{1.5f, {}};
    coated_conductor.bottom =
        ConductorLobe{gold_eta * (1 / 1.5f), gold_k * (1 / 1.5f), {0.3f, 0.3f}};
    coated_conductor.albedo = SampledSpectrum(0);
    coated_conductor.thickness = 0.01f;
    return {
        {"Lambert", LambertLobe{SampledSpectrum(0.5f)}},
        {"DielectricSmooth", DielectricLobe{1.5f, {}}},
        {"DielectricRough", DielectricLobe{1.5f, {0.3f, 0.3f}}},
        {"ThinDielectric", ThinDielectricLobe{1.5f}},
        {"ConductorSmooth", ConductorLobe{gold_eta, gold_k, {}}},
        {"ConductorRough", ConductorLobe{gold_eta, gold_k, {0.3f, 0.3f}}},
        {"ConductorRoughAniso", ConductorLobe{gold_eta, gold_k, {0.1f, 0.4f}}},
        {"DiffuseTransmission",
         DiffuseTransmissionLobe{SampledSpectrum(0.4f), SampledSpectrum(0.4f)}},
        {"Phong", PhongLobe{SampledSpectrum(0.4f), SampledSpectrum(0.5f), 30, false}},
        {"ModifiedPhong", PhongLobe{SampledSpectrum(0.4f), SampledSpectrum(0.5f), 30, true}},
        {"Lafortune1Lobe", laf1},
        {"Lafortune3Lobes", laf3},
        {"WardIso", WardLobe{SampledSpectrum(0.3f), SampledSpectrum(0.6f), 0.2f, 0.2f}},
        {"WardAniso", WardLobe{SampledSpectrum(0.3f), SampledSpectrum(0.6f), 0.05f, 0.4f}},
        {"CoatedDiffuse", coated_diffuse},
        {"CoatedConductorRough", coated_conductor},
        {"MeasuredIso", MeasuredLobe{&standin(false), standin_lambda()}},
        {"MeasuredAniso", MeasuredLobe{&standin(true), standin_lambda()}},
    };
}

constexpr size_t kN = 4096;  // pre-drawn inputs, cycled

struct Inputs {
    std::vector<Float> uc;
    std::vector<Point2> u;
    std::vector<Vec3> wi;  // world space, mostly in the upper hemisphere
};
const Inputs& inputs() {
    static const Inputs in = [] {
        Inputs r;
        Pcg32 rng(3, 7);
        for (size_t i = 0; i < kN; ++i) {
            r.uc.push_back(rng.next_float());
            r.u.push_back({rng.next_float(), rng.next_float()});
            Vec3 w = sample_cosine_hemisphere({rng.next_float(), rng.next_float()});
            if (i % 8 == 0) w.z = -w.z;  // some transmission / opposite-side queries
            r.wi.push_back(w);
        }
        return r;
    }();
    return in;
}

Bsdf make_bsdf_of(const LobeVariant& lobe) {
    // A slightly tilted shading frame, so the change of frame is not trivial.
    return Bsdf(Frame::from_z(normalize(Vec3(0.1f, 0.2f, 1))), Vec3(0, 0, 1), lobe);
}
const Vec3 kWo = normalize(Vec3(0.4f, -0.3f, 0.8f));

void bm_sample(benchmark::State& state, LobeVariant lobe) {
    Bsdf b = make_bsdf_of(lobe);
    const Inputs& in = inputs();
    size_t i = 0;
    for (auto _ : state) {
        auto s = b.sample(kWo, in.uc[i], in.u[i]);
        benchmark::DoNotOptimize(s);
        i = (i + 1) & (kN - 1);
    }
    state.SetItemsProcessed(state.iterations());
}

void bm_eval(benchmark::State& state, LobeVariant lobe) {
    Bsdf b = make_bsdf_of(lobe);
    const Inputs& in = inputs();
    size_t i = 0;
    for (auto _ : state) {
        benchmark::DoNotOptimize(b.f(kWo, in.wi[i]));
        benchmark::DoNotOptimize(b.pdf(kWo, in.wi[i]));
        i = (i + 1) & (kN - 1);
    }
    state.SetItemsProcessed(state.iterations());
}

void bm_missing(benchmark::State& state, size_t index) {
    std::string msg =
        "no instance in bsdf_bench.cpp for LobeVariant alternative " + std::to_string(index);
    state.SkipWithError(msg.c_str());
    for (auto _ : state) {
    }
}

[[maybe_unused]] const bool kRegistered = [] {
    std::vector<bool> covered(std::variant_size_v<LobeVariant>, false);
    for (const Instance& in : instances()) {
        covered[in.lobe.index()] = true;
        benchmark::RegisterBenchmark(("BM_BsdfSample/" + in.name).c_str(), bm_sample, in.lobe);
        benchmark::RegisterBenchmark(("BM_BsdfEval/" + in.name).c_str(), bm_eval, in.lobe);
    }
    for (size_t k = 0; k < covered.size(); ++k)
        if (!covered[k])
            benchmark::RegisterBenchmark(("BM_BsdfMissing/" + std::to_string(k)).c_str(),
                                         bm_missing, k);
    return true;
}();

}  // namespace
}  // namespace sr
