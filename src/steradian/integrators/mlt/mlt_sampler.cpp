#include "steradian/integrators/mlt/mlt_sampler.h"

#include <cmath>
#include <type_traits>

#include "steradian/core/error.h"
#include "steradian/sampling/hash.h"

namespace sr {

MltSampler::MltSampler(Float sigma, Float large_step_probability, int streams,
                       uint64_t rng_index, uint64_t seed)
    : m_sigma(sigma), m_large_step_probability(large_step_probability), m_streams(streams) {
    reseed(rng_index, seed);
}

void MltSampler::reseed(uint64_t rng_index, uint64_t seed) {
    m_rng.set_sequence(mix_bits(rng_index) ^ mix_bits(seed ^ 0x6d6c74ULL), mix_bits(seed + rng_index));
}

void MltSampler::save(ByteWriter& bw) const {
    static_assert(std::is_trivially_copyable_v<Pcg32> &&
                  std::is_trivially_copyable_v<PrimarySample>);
    bw.put(m_rng);
    bw.put(m_sigma);
    bw.put(m_large_step_probability);
    bw.put(int32_t(m_streams));
    bw.put(m_iteration);
    bw.put(uint8_t(m_large_step));
    bw.put(m_last_large_step);
    bw.put(uint64_t(m_x.size()));
    bw.put_array(m_x.data(), m_x.size());
}

void MltSampler::load(ByteReader& br) {
    m_rng = br.get<Pcg32>();
    m_sigma = br.get<Float>();
    m_large_step_probability = br.get<Float>();
    m_streams = br.get<int32_t>();
    m_iteration = br.get<int64_t>();
    m_large_step = br.get<uint8_t>() != 0;
    m_last_large_step = br.get<int64_t>();
    const uint64_t n = br.get<uint64_t>();
    if (m_streams < 1 || n > br.left() / sizeof(PrimarySample))
        throw Error("distributed: a malformed Metropolis sampler state");
    m_x.resize(size_t(n));
    br.get_array(m_x.data(), m_x.size());
}

void MltSampler::start_iteration() {
    ++m_iteration;
    m_large_step = m_rng.next_float() < m_large_step_probability;
}

void MltSampler::accept() {
    if (m_large_step) m_last_large_step = m_iteration;
}

void MltSampler::reject() {
    for (PrimarySample& x : m_x)
        if (x.modified == m_iteration) x.value = x.backup, x.modified = x.modified_backup;
    --m_iteration;
}

Float MltSampler::get(int stream, int k) {
    const size_t index = size_t(stream) + size_t(m_streams) * size_t(k);
    ensure_ready(index);
    return m_x[index].value;
}

void MltSampler::ensure_ready(size_t index) {
    if (index >= m_x.size()) m_x.resize(index + 1);
    PrimarySample& x = m_x[index];
    if (x.modified == m_iteration) return;  // already brought up to this proposal
    // A large step accepted since this number was last read replaced it.
    if (x.modified < m_last_large_step) {
        x.value = m_rng.next_float();
        x.modified = m_last_large_step;
    }
    x.backup = x.value;
    x.modified_backup = x.modified;
    if (m_large_step) {
        x.value = m_rng.next_float();
    } else {
        // The small steps since it was last modified, at once: a sum of n normal steps of
        // deviation sigma is normal with deviation sigma sqrt(n) (Box-Muller, in double).
        const double n = double(m_iteration - x.modified);
        const double u1 = 1 - m_rng.next_double(), u2 = m_rng.next_double();
        const double z = std::sqrt(-2 * std::log(u1)) * std::cos(2 * 3.14159265358979323846 * u2);
        double v = double(x.value) + double(m_sigma) * std::sqrt(n) * z;
        v -= std::floor(v);
        x.value = Float(v);
        if (!(x.value < 1)) x.value = 0;  // (v just below 1 rounded up to 1 in float)
    }
    x.modified = m_iteration;
}

}  // namespace sr
