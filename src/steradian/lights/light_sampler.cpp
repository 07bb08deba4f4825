#include "steradian/lights/light_sampler.h"

namespace sr {

void LightSampler::build(const std::vector<Light>& lights, bool by_power) {
    m_pmf.clear();
    if (lights.empty()) return;
    std::vector<Float> w(lights.size());
    double total = 0;
    for (size_t i = 0; i < lights.size(); ++i) {
        w[i] = by_power ? std::max(Float(0), light_phi_y(lights[i])) : 1;
        if (!std::isfinite(w[i])) w[i] = 0;
        total += w[i];
    }
    if (total == 0) std::fill(w.begin(), w.end(), Float(1)), total = double(w.size());
    m_pmf.resize(w.size());
    for (size_t i = 0; i < w.size(); ++i) m_pmf[i] = Float(w[i] / total);
    m_alias = AliasTable(w);
}

int LightSampler::sample(Float u, Float& pmf) const {
    if (m_pmf.empty()) {
        pmf = 0;
        return -1;
    }
    Float p;
    int i = m_alias.sample(u, &p, nullptr);
    pmf = m_pmf[i];
    return i;
}

}  // namespace sr
