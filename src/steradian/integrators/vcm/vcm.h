#pragma once
/// Integrator "vcm" (a steradian extension; docs/vcm.md): vertex connection and merging
/// (Georgiev, Křivánek, Davidovič and Slusallek 2012, "Light transport simulation with vertex
/// connection and merging", ACM TOG 31(6) (SIGGRAPH Asia); the MIS quantities of Georgiev's
/// technical report "Implementing vertex connection and merging", 2012, as in SmallVCM).
///
/// Each iteration (one per pixel sample of the Sampler) shares one set of wavelengths (as
/// sppm's passes do: merged vertices must carry the same ones):
///  1. Light pass: one light path per pixel of the crop window (N of them); each vertex with
///     a non-specular BSDF is stored, and connected to the camera (t = 1, a splat).
///  2. A hash grid over the stored vertices, cells twice the merge radius r_i wide.
///  3. Camera pass: the camera path of pixel k finds emitters (s = 0), samples a light at
///     each non-specular vertex (s = 1), connects to every vertex of light path k (vertex
///     connection), and merges with every stored vertex within r_i (vertex merging: the
///     photon-mapping estimate f * beta_light / (pi r_i^2 N)).
/// Every contribution is weighted by the power heuristic over all these strategies, through
/// Georgiev's recursive quantities dVCM, dVC, dVM kept along both subpaths, merging counted
/// as a strategy of density pi r_i^2 N times a connection's (eta_VCM). The radius shrinks as
/// r_i = r_1 i^((alpha - 1) / 2) (iteration i from 1; alpha 0.75 by default, SmallVCM's).
/// With merging switched off the estimator is a bidirectional path tracer; with connections
/// off, photon mapping combined with camera paths that hit emitters.
///
/// Media (docs/vcm.md): both subpaths scatter in media by delta tracking (medium vertices,
/// the phase function as their BSDF), connections carry the ratio-tracking transmittance of
/// their segment; medium vertices are connected but not merged (merging is on surfaces),
/// the MIS quantities leaving out the merging terms of medium vertices.
///
/// Determinism: light path k of iteration i and camera path of pixel k are pure functions of
/// (i, k, seed); light vertices go into fixed slots, the grid lists them in index order, each
/// pixel's merges are added in that order, and the light pass's splats are added in path
/// order: the image is the same bit for bit on any number of threads.
namespace sr {

class Scene;
class Film;
struct RenderOptions;
struct RenderStats;

/// Renders `scene` (Integrator "vcm") into `film`. Throws sr::Error for what vcm does not
/// support: what the bidirectional integrators refuse (emissive media, subsurface materials,
/// cameras without importance, environment maps with a portal), films other than "rgb",
/// checkpoints. With opt.distribute (steradian-mpi, several processes) every process traces
/// each iteration's light paths and the camera pass is shared in bands of film rows
/// (vcm_job_handler, distributed.h; docs/distributed.md): the same image.
RenderStats render_vcm(const Scene& scene, Film& film, const RenderOptions& options);

}  // namespace sr
