#pragma once
/// Chooses a light for next-event estimation: by emitted power (V(lambda)-weighted), or
/// uniformly. pmf() is needed by MIS when a BSDF-sampled ray hits an emitter.
#include <vector>

#include "steradian/lights/light.h"
#include "steradian/sampling/distribution.h"

namespace sr {

class LightSampler {
public:
    LightSampler() = default;
    /// by_power: pmf proportional to light_phi_y (lights of zero power never chosen);
    /// otherwise uniform.
    void build(const std::vector<Light>& lights, bool by_power);
    bool empty() const { return m_alias.size() == 0; }
    /// Index of the chosen light (or -1 if there are none) and its probability.
    int sample(Float u, Float& pmf) const {
        if (empty()) {
            pmf = 0;
            return -1;
        }
        return m_alias.sample(u, pmf);
    }
    Float pmf(int light) const { return m_alias.pmf(light); }

private:
    AliasTable m_alias;
};

}  // namespace sr
