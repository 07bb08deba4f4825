#pragma once
/// Integrator "mlt": primary-sample-space Metropolis light transport over the bidirectional
/// path sampler (Kelemen et al. 2002; Veach 1997, ch. 11), as pbrt-v4's MLTIntegrator.
///
/// A state of a chain is a vector of uniform numbers in three streams (camera subpath,
/// light subpath, connection; mlt_sampler.h) and a path length (depth). It maps to one
/// bidirectional strategy (s, t) of that length, chosen by the state's first camera number,
/// whose MIS-weighted contribution times the number of strategies is the state's radiance L
/// (bdpt_strategy() of integrators/bdpt/); the chains sample the states in proportion to
/// L's luminance c. The render:
///  1. Bootstrap: `bootstrapsamples` x (maxdepth + 1) independent states (each depth
///     alike); their mean c times (maxdepth + 1) is the normalisation b (the integral of c
///     over primary sample space, summed over depths).
///  2. `chains` Markov chains, each started from a bootstrap state drawn in proportion to
///     its c (which fixes the chain's depth), share the mutations: `mutationsperpixel` x the
///     area of the film's sample bounds. Each mutation is a large step (probability
///     `largestepprobability`) or a small one (normal, deviation `sigma`), and splats the
///     current and the proposed state with expected values (metropolis_step()).
///  3. The image is the splat sums times b / (mutations per pixel x filter integral).
///
/// Determinism: every random number is a function of the seed and of a bootstrap sample's
/// or a chain's index; the chains' mutations are done in rounds of one mutation per pixel,
/// and each round's splats are added chain by chain in chain order (each chain's in its
/// mutation order), so the image is the same bit for bit on any number of threads (and of
/// processes: the chains move between them with their states), and a
/// render stopped by its time budget after m rounds is the render of m mutations per pixel.
#include "steradian/integrators/integrator.h"

namespace sr {

class Scene;
class Film;

/// Renders `scene` (Integrator "mlt") into `film`'s splat sums. opt.spp > 0 replaces
/// "mutationsperpixel" (as pbrt-v4's --spp). Throws sr::Error for what it cannot do: a
/// scene the bidirectional kernels cannot trace (check_bidir_scene), checkpoints, films
/// other than "rgb", and a scene whose bootstrap found no light. With opt.distribute, the
/// bootstrap's blocks and the chains (their states travelling with them) are shared with
/// the other processes (mlt_job_handler of distributed.h) and the splats added in the same
/// chain order: the same image (docs/distributed.md).
RenderStats render_mlt(const Scene& scene, Film& film, const RenderOptions& opt);

}  // namespace sr
