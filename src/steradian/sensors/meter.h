#pragma once
/// Photometric and radiometric meters (the `Meter` directive, a steradian extension;
/// docs/photometry.md): illuminance and irradiance at points or on a grid of cells, and
/// luminance and radiance seen from a point within a cone.
#include <string>
#include <vector>

#include "steradian/core/error.h"
#include "steradian/core/math.h"

namespace sr {

enum class MeterKind { Point, Grid, Luminance };
/// Photopic V(lambda) (lx, cd/m^2), scotopic V'(lambda) (scotopic lx, cd/m^2), or
/// radiometric (W/m^2, W/(m^2 sr), integrated over 360..830 nm).
enum class MeterWeighting { Photopic, Scotopic, Radiometric };
/// Which light a receiving meter counts: all of it, only light arriving straight from the
/// emitters (one scattering vertex: the meter's own), or only light that was scattered by
/// the scene at least once before arriving (two or more).
enum class MeterComponent { All, Direct, Indirect };

struct Meter {
    std::string name;
    std::string type;  ///< as written: "illuminance", "illuminancegrid", ...
    SourceLoc loc;
    MeterKind kind = MeterKind::Point;
    MeterWeighting weighting = MeterWeighting::Photopic;
    MeterComponent component = MeterComponent::All;
    /// World-space measuring points, in output order (grids: cell centres row by row along
    /// u, rows along v).
    std::vector<Point3> points;
    /// Point/Grid: the receiving surface's unit normal per point. Luminance: the unit
    /// viewing direction per point (the meter looks along it).
    std::vector<Vec3> directions;
    /// Luminance: half-angle of the acceptance cone (radians); 0 = a single ray.
    Float cone_half_angle = 0;
    /// Grid: resolution and cell edge vectors (world space); cell_average spreads each
    /// cell's samples uniformly over the cell, so its value is the cell's mean illuminance
    /// (and E_avg the exact area mean) instead of the value at its centre.
    int nu = 0, nv = 0;
    Vec3 cell_u{0, 0, 0}, cell_v{0, 0, 0};
    bool cell_average = false;
    /// Largest number of scattering vertices of a counted path; < 0: no limit (Russian
    /// roulette alone ends paths, so the reading has no depth cut-off bias).
    int max_depth = -1;
    /// The medium the measuring points are in (Scene::media index, -1: none): the outside
    /// medium of the MediumInterface in effect at the Meter directive.
    int medium = -1;
    /// A glare meter (`Meter "ugr"`): each point is an observer's eye looking along its
    /// `directions` entry with `glare_up` up. The measurement estimates the indirect
    /// illuminance on the eye's plane facing the view (a Point meter, component Indirect);
    /// measure() then turns it into the unified glare rating (integrators/glare.h).
    bool glare = false;
    Vec3 glare_up{0, 0, 1};

    /// "lx", "W/m2", "cd/m2", "W/(m2 sr)" (scotopic values carry the same unit names);
    /// "UGR" for a glare meter (dimensionless).
    std::string unit() const;
    /// Spectral weight w(lambda) turning scene-unit spectral values into the meter's unit
    /// (docs/units.md: photopic = ybar, scotopic = (K'_m / K_m) V', radiometric = 1 / K_m).
    Float spectral_weight(Float lambda) const;
};

}  // namespace sr
