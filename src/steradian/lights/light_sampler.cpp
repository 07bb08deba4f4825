#include "steradian/lights/light_sampler.h"

namespace sr {

namespace {

/// Lights with radiance arriving from infinity, which pbrt-v4's BVH leaves out (no bounds).
bool at_infinity(const Light& l) {
    return std::holds_alternative<UniformInfiniteLight>(l) ||
           std::holds_alternative<ImageInfiniteLight>(l) ||
           std::holds_alternative<DistantLight>(l);
}

Float power_of(const Light& l) {
    Float phi = light_phi_y(l);
    return std::isfinite(phi) ? std::max(Float(0), phi) : 0;
}

}  // namespace

void LightSampler::build(const std::vector<Light>& lights, LightSamplerKind kind) {
    m_alias = AliasTable();
    if (lights.empty()) return;
    // All-zero (or non-finite) powers fall back to uniform selection in the alias table.
    std::vector<Float> w(lights.size(), Float(1));
    if (kind == LightSamplerKind::Power)
        for (size_t i = 0; i < lights.size(); ++i) w[i] = power_of(lights[i]);
    if (kind == LightSamplerKind::InfiniteShare) {
        size_t n_inf = 0;
        double bounded_power = 0;
        for (const Light& l : lights) {
            if (at_infinity(l))
                ++n_inf;
            else
                bounded_power += power_of(l);
        }
        const bool has_bounded = bounded_power > 0;
        const double p_each_infinite = 1.0 / double(n_inf + (has_bounded ? 1 : 0));
        for (size_t i = 0; i < lights.size(); ++i) {
            if (at_infinity(lights[i]))
                w[i] = Float(p_each_infinite);
            else
                w[i] = has_bounded ? Float((1 - double(n_inf) * p_each_infinite) *
                                           power_of(lights[i]) / bounded_power)
                                   : 0;
        }
    }
    m_alias = AliasTable(w);
}

}  // namespace sr
