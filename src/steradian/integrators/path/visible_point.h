#pragma once
/// The camera pass of stochastic progressive photon mapping (integrators/sppm/): a camera
/// path traced as path_li() traces it (emission with MIS, a light sample at every vertex)
/// that ends where it finds its visible point, pbrt-v4's SPPM camera path.
#include <optional>

#include "steradian/bsdf/bsdf.h"
#include "steradian/integrators/path/path.h"

namespace sr {

/// The first vertex of a camera path whose BSDF has a diffuse lobe, or a glossy one at the
/// last depth (Hachisuka and Jensen 2009; pbrt-v4's SPPMPixel::VisiblePoint): where the
/// photons of a pass are gathered. `beta` is the path throughput up to (not including) the
/// vertex's BSDF.
struct VisiblePoint {
    bool set = false;
    Point3 p;
    Vec3 wo;
    SampledSpectrum beta{0};
    std::optional<Bsdf> bsdf;
    /// Whether the camera path's secondary wavelengths were terminated (dispersion).
    bool secondary_terminated = false;
};

/// The direct part of one SPPM camera sample: the radiance path_li() would add along the
/// camera path until (and including) its visible point's light sample and the emission its
/// BSDF sample finds, after which the path ends; the visible point (if any) in `vp`. The
/// sample dimensions are those of path_li() (kCameraDimensions on).
SampledSpectrum path_li_visible_point(const Scene& scene, const Ray& ray,
                                      SampledWavelengths& lambda, Sampler& sampler,
                                      PathCounters& counters, VisiblePoint& vp);

}  // namespace sr
