#include "steradian/lights/light_sampler.h"

namespace sr {

void LightSampler::build(const std::vector<Light>& lights, bool by_power) {
    m_alias = AliasTable();
    if (lights.empty()) return;
    // All-zero (or non-finite) powers fall back to uniform selection in the alias table.
    std::vector<Float> w(lights.size(), Float(1));
    if (by_power)
        for (size_t i = 0; i < lights.size(); ++i) {
            Float phi = light_phi_y(lights[i]);
            w[i] = std::isfinite(phi) ? std::max(Float(0), phi) : 0;
        }
    m_alias = AliasTable(w);
}

}  // namespace sr
