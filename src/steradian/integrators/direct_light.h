#pragma once
/// Deterministic direct light for receiving meters (docs/photometry.md, "Direct light
/// without Monte Carlo"): the illuminance an ideal one-sided receiver at a meter point gets
/// straight from the emitters, as a sum of closed forms and quadratures instead of samples.
///
/// - A delta light (point, spot, goniometric point, distant) contributes I cos(theta) / r^2
///   (E cos(theta) for a distant light) times one shadow ray: exact, error 0.
/// - An area light (a triangle, disk or sphere, a photometric luminaire's luminous opening
///   or body included) is integrated over its area, E = integral L cos(theta_r)
///   cos(theta_e) / r^2 V dA, by global adaptive tensor Gauss-Legendre quadrature over the
///   primitive's parametrisation (full spheres: over the cone of directions they subtend):
///   each cell is integrated by the 2x2 and the 3x3 rule, the 3x3 value is kept and the
///   difference of the two is the cell's error estimate (a bound on the 2x2 rule's error,
///   so a conservative one for the 3x3's); the cell of largest estimate is split in four
///   until the estimates sum to the tolerance. Visibility is one shadow ray per node.
/// - The spectrum is integrated exactly as the scene's photometric normalisation does: a
///   sum over every nm of 360..830 of the light's spectrum times the meter's weight.
///
/// The answer is deterministic (no sampler) and the same on any number of threads.
#include <cstdint>
#include <vector>

#include "steradian/sensors/meter.h"

namespace sr {

class Scene;

/// Whether every light of the scene has a deterministic direct contribution (delta lights
/// and area lights without alpha cut-outs; not infinite lights) and the scene has no media
/// (whose attenuation the quadrature does not trace).
bool direct_light_deterministic(const Scene& scene);

/// Whether any surface of the scene may scatter light: false when every shape has the
/// interface material or a "diffuse" one whose reflectance is a constant spectrum that is
/// zero at every wavelength (a black room), so that a meter's indirect component is
/// exactly zero.
bool scene_may_scatter(const Scene& scene);

/// One meter value's deterministic direct illuminance (in the meter's unit).
struct DirectEstimate {
    double value = 0;
    double error = 0;      ///< the quadrature's error estimate (0 for delta lights alone)
    bool exact = true;     ///< only delta lights contributed: no quadrature error
    bool converged = true; ///< the error estimate met the tolerance within the node budget
    uint64_t nodes = 0;    ///< quadrature nodes (and delta lights) evaluated
    uint64_t rays = 0;     ///< shadow rays traced
};

/// The deterministic direct light of one receiving meter (point or grid, not luminance).
class DirectLightQuadrature {
public:
    DirectLightQuadrature(const Scene& scene, const Meter& meter);
    /// Direct illuminance at point `point` of the meter, to an estimated error of at most
    /// rel_tol times the value or abs_tol, whichever is larger (or until max_nodes
    /// quadrature nodes were spent).
    DirectEstimate irradiance(size_t point, double rel_tol, double abs_tol = 0,
                              uint64_t max_nodes = 1u << 18) const;

private:
    const Scene& m_scene;
    const Meter& m_meter;
    /// Per light: the spectral factor sum_lambda S(lambda) w(lambda) over 1 nm steps, and
    /// the probe wavelength at which a light's sampled value is divided by S to give its
    /// spectrum-free (geometric) factor.
    std::vector<double> m_spectral;
    std::vector<float> m_probe, m_probe_s;
};

}  // namespace sr
