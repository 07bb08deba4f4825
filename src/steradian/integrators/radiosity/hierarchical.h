#pragma once
/// Hierarchical radiosity (Hanrahan, Salzman and Aupperle 1991, "A rapid hierarchical
/// radiosity algorithm") over the patch trees of the radiosity mesh (docs/radiosity.md):
/// pairs of nodes exchange light through links placed as high in the trees as the estimated
/// power they carry allows ("BF refinement"), and the system is solved by gathering over the
/// links and pushing/pulling through the trees until the residual is small.
#include <cstdint>
#include <vector>

#include <tbb/task_arena.h>

#include "steradian/integrators/radiosity/form_factor.h"

namespace sr::radiosity {

/// A node of a patch tree: one side of a (sub-)triangle of the mesh.
struct HierNode {
    PatchGeom g;
    int child = -1;    ///< first of four consecutive children, or -1 (leaf)
    int unknown = -1;  ///< a leaf's unknown (row of rho and E)
};

struct HierParams {
    /// A link is placed between two nodes when its estimated error (hierarchical.cpp: the
    /// power it moves times the spread of the exitance within the nodes, plus the power it
    /// moves times the nodes' size over their distance) is at most this fraction of the
    /// scene's reflected power; else the larger node is split.
    double link_error = 2e-3;
    /// The solve stops when ||B' - B|| <= residual ||B'|| (B' = rho (E + F B): the change of
    /// a sweep is the residual of the equation at B), over all leaves and bands, by area.
    double residual = 1e-6;
    double eps = 0;  ///< offset of ray origins along the normals
    int max_sweeps = 2000;
};

struct HierStats {
    size_t links = 0;
    int sweeps = 0;
    double residual = 0;
    uint64_t rays = 0;
    double seconds_sweeps = 0;  ///< wall, the solve's sweeps
};

/// Solves B = rho (E + F B) on the leaves. rho and E: per unknown, `bands` values each;
/// ybar: the bands' photopic weights (for the refinement's power estimates). Returns B per
/// unknown (`bands` values each). Deterministic on any number of threads. `visible_batch`
/// (optional) answers what `visible` answers, for the rays between two nodes at once.
std::vector<double> solve_hierarchical(const std::vector<HierNode>& nodes,
                                       const std::vector<int>& roots, const std::vector<double>& rho,
                                       const std::vector<double>& E, const std::vector<double>& ybar,
                                       const Visibility& visible, const HierParams& params,
                                       tbb::task_arena& arena, HierStats& stats,
                                       const VisibilityBatch& visible_batch = nullptr);

}  // namespace sr::radiosity
