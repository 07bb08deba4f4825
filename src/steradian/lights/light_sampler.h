#pragma once
/// Chooses a light for next-event estimation: by emitted power (V(lambda)-weighted),
/// uniformly, or with pbrt-v4's "bvh" split between lights at infinity and the others.
/// pmf() is needed by MIS when a BSDF-sampled ray hits an emitter.
#include <vector>

#include "steradian/lights/light.h"
#include "steradian/sampling/distribution.h"

namespace sr {

enum class LightSamplerKind {
    /// Every light with the same probability (pbrt-v4's "uniform").
    Uniform,
    /// Probability proportional to light_phi_y (pbrt-v4's "power"): lights at infinity count
    /// with the power they send through the scene's bounding sphere.
    Power,
    /// pbrt-v4's "bvh" (its default) without the spatial part: each light at infinity
    /// (infinite, environment, distant) has probability 1 / (n_infinite + 1) when the scene
    /// has other lights (pbrt-v4's BVHLightSampler gives them that share), and those other
    /// lights share the rest by power. pbrt-v4 then picks among them by each light's
    /// importance at the shading point; we pick by power alone (docs/pbrt-support.md). Unlike
    /// "power", a small lamp is not drowned by a sky whose power grows with the scene's size.
    InfiniteShare,
};

class LightSampler {
public:
    LightSampler() = default;
    /// Lights of zero power are never chosen by Power and InfiniteShare.
    void build(const std::vector<Light>& lights, LightSamplerKind kind);
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
