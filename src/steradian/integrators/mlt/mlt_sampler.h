#pragma once
/// Primary-sample-space Metropolis sampling (Kelemen, Szirmay-Kalos, Antal and Csonka 2002,
/// "A simple and robust mutation strategy for the Metropolis light transport algorithm",
/// Computer Graphics Forum 21(3)), as pbrt-v4's MLTSampler configures it: a state is a
/// vector of uniform numbers in [0, 1), created lazily as a path asks for them; a large step
/// replaces every number by a fresh uniform one, a small step adds to each a normal
/// perturbation of standard deviation `sigma`, wrapped into [0, 1). Numbers are organised in
/// interleaved streams (a stream per subpath, so that a change in one subpath's length does
/// not shift the numbers another one reads). A number not read for n iterations is brought
/// up to date when next read: a fresh uniform number if a large step was accepted since,
/// else n small steps at once (one normal of deviation sigma sqrt(n)).
///
/// metropolis_step() is one step of a chain with Veach's expected-value splatting (both the
/// current and the proposed state contribute, weighted by the acceptance probability); the
/// integrator (mlt.cpp) and the sampler's statistical test use it alike.
#include <algorithm>
#include <cstdint>
#include <memory>
#include <string>
#include <vector>

#include "steradian/integrators/distributed.h"
#include "steradian/sampling/rng.h"
#include "steradian/sampling/sampler.h"

namespace sr {

class MltSampler {
public:
    /// The state's uniform numbers are drawn from PCG32 stream (rng_index, seed): the same
    /// index and seed give the same first state (the bootstrap's sample `rng_index` and the
    /// chain started from it agree).
    MltSampler(Float sigma, Float large_step_probability, int streams, uint64_t rng_index,
               uint64_t seed);

    /// Continues the generator of the mutations on another PCG32 stream (a chain's own, so
    /// that chains started from the same bootstrap sample do not mutate alike).
    void reseed(uint64_t rng_index, uint64_t seed);

    /// Starts a proposal: a large step with probability large_step_probability.
    void start_iteration();
    /// The proposal became the state / was rejected (the state's numbers restored).
    void accept();
    void reject();

    /// Number k of stream `stream` (0 <= stream < streams()) of the current proposal.
    Float get(int stream, int k);

    /// Number k of stream `stream` of the state as it is (no mutation; 0 if never read).
    Float value(int stream, int k) const {
        const size_t i = size_t(stream) + size_t(m_streams) * size_t(k);
        return i < m_x.size() ? m_x[i].value : 0;
    }
    int streams() const { return m_streams; }
    bool large_step() const { return m_large_step; }
    /// How many numbers the state holds (the largest index read, plus one).
    size_t size() const { return m_x.size(); }

    /// The whole state (numbers, generator, iteration counts) into a message, and back
    /// (distributed chains move between processes: docs/distributed.md); a loaded sampler
    /// continues exactly as the saved one would have. load throws sr::Error on a malformed
    /// message.
    void save(ByteWriter& bw) const;
    void load(ByteReader& br);

private:
    struct PrimarySample {
        Float value = 0, backup = 0;
        /// The iteration that last changed it; -1: never read (the first read draws it).
        int64_t modified = -1, modified_backup = -1;
    };
    void ensure_ready(size_t index);

    Pcg32 m_rng;
    Float m_sigma, m_large_step_probability;
    int m_streams;
    std::vector<PrimarySample> m_x;
    int64_t m_iteration = 0;
    bool m_large_step = true;  ///< the first state is a large step from nothing
    int64_t m_last_large_step = 0;
};

/// One stream of an MltSampler as a Sampler, for code that draws its numbers from one (the
/// bidirectional kernels). get_1d / get_2d read the stream's next numbers; the pixel
/// dimensions are not used by Metropolis sampling (the film position is a number of the
/// camera stream) and read the next numbers too. reset() starts the stream again at its
/// number 0, as each evaluation of a proposal does.
class MltStream final : public Sampler {
public:
    MltStream(MltSampler& sampler, int stream) : Sampler(1), m_s(&sampler), m_stream(stream) {}
    void reset() { m_next = 0; }
    void start_pixel_sample(Vec2i, int, int) override { m_next = 0; }
    Float get_1d() override { return m_s->get(m_stream, m_next++); }
    Point2 get_2d() override {
        const Float a = get_1d();
        return Point2(a, get_1d());
    }
    void skip_1d() override { ++m_next; }
    void skip_2d() override { m_next += 2; }
    Point2 get_pixel_2d() override { return get_2d(); }
    Float get_pixel_1d() override { return get_1d(); }
    std::unique_ptr<Sampler> clone() const override { return std::make_unique<MltStream>(*this); }
    std::string name() const override { return "mlt"; }

private:
    MltSampler* m_s;
    int m_stream;
    int m_next = 0;
};

/// A chain's state for metropolis_step: anything with a scalar contribution `c` >= 0 (the
/// function whose normalised form the chain samples).
template <class State>
concept MetropolisState = requires(const State& s) {
    { s.c } -> std::convertible_to<Float>;
};

/// One Metropolis-Hastings step of a chain in primary sample space (pbrt-v4's
/// MLTIntegrator::Render loop body): `evaluate(proposed)` fills the proposal from the
/// sampler's numbers after start_iteration(); both states are splatted with Veach's expected
/// values, `splat(state, w)` with w = a / c(proposed) for the proposal and (1 - a) / c(current)
/// for the current state, a = min(1, c(proposed) / c(current)); then the proposal is accepted
/// with probability a (the uniform number from `rng`), swapped into `current`. Returns
/// whether it was accepted.
template <MetropolisState State, class Evaluate, class Splat>
bool metropolis_step(MltSampler& sampler, Pcg32& rng, State& current, State& proposed,
                     Evaluate&& evaluate, Splat&& splat) {
    sampler.start_iteration();
    evaluate(proposed);
    const Float cp = proposed.c, cc = current.c;
    // (A chain starts from a state with c > 0; should one have none, any proposal is taken.)
    const Float a = cc > 0 ? std::min<Float>(1, cp / cc) : 1;
    if (a > 0 && cp > 0) splat(proposed, a / cp);
    if (a < 1 && cc > 0) splat(current, (1 - a) / cc);
    if (rng.next_float() < a) {
        std::swap(current, proposed);
        sampler.accept();
        return true;
    }
    sampler.reject();
    return false;
}

}  // namespace sr
