#pragma once
/// pbrt-v4's "sppm": stochastic progressive photon mapping (Hachisuka and Jensen 2009,
/// "Stochastic Progressive Photon Mapping", ACM TOG 28(5); pbrt-v4's SPPMIntegrator).
///
/// Each iteration (one per pixel sample of the Sampler) traces one camera path per pixel
/// until its visible point (path/visible_point.h), adding on the way the light path_li()
/// finds by emission and light samples; it then hashes the visible points into a grid of
/// cells about the largest search radius wide, traces `photonsperiteration` photons from the
/// lights (chosen by power) at wavelengths shared by the whole iteration, and adds every
/// photon that lands, after at least one bounce, within a visible point's radius to that
/// pixel's flux with the visible point's BSDF. Each pixel's radius and flux then shrink as
/// in the paper (alpha = 2/3): with N photons so far and M new, N' = N + alpha M,
/// r' = r sqrt(N' / (N + M)), tau' = (tau + Phi) r'^2 / r^2. The pixel's value is
/// Ld / iterations + tau / (photons traced * pi r^2).
///
/// Determinism: each pixel's camera path is a pure function of (pixel, iteration, seed);
/// photon i of iteration k a pure function of (k, i, seed). The photons are traced in chunks
/// of consecutive photon indices, in parallel; each chunk records its deposits (pixel, sensor
/// values) in photon order, and the chunks' records are added in chunk order, so every
/// pixel's flux is the same sum in photon order on any number of threads (and whatever the
/// chunks' size, which shrinks where photons meet many visible points, to bound the lists).
namespace sr {

class Scene;
class Film;
struct RenderOptions;
struct RenderStats;

/// Renders `scene` (Integrator "sppm") into `film`: throws sr::Error for what sppm does not
/// support (media, films other than "rgb", checkpoints). With options.distribute, each
/// iteration's photon chunks are traced by any process (sppm_job_handler of distributed.h)
/// to their hits, which this process gathers against its visible points and adds in chunk
/// order: the same image (docs/distributed.md).
RenderStats render_sppm(const Scene& scene, Film& film, const RenderOptions& options);

}  // namespace sr
