#pragma once
/// The unified glare rating of CIE 117:1995 for an observer (`Meter "ugr"`):
///
///     UGR = 8 log10( 0.25 / L_b * sum_i L_i^2 omega_i / p_i^2 )
///
///   L_b      background luminance, cd/m^2: E_ind / pi, E_ind the indirect illuminance on the
///            plane of the eye facing the view direction (the meter's measured value);
///   L_i      luminance of luminaire i's luminous parts towards the eye, I_i / A_i, with I_i
///            its intensity towards the eye (cd) and A_i the projected area of its LM-63
///            luminous opening seen from the eye;
///   omega_i  the opening's solid angle at the eye, A_i / r_i^2;
///   p_i      Guth's position index of the luminaire's direction, in Levin's closed form
///            (J. IES 1975), the one Radiance's glarendx uses:
///              ln p = (35.2 - 0.31889 tau - 1.22 e^(-2 tau / 9)) 1e-3 sigma
///                     + (21 + 0.26667 tau - 0.002963 tau^2) 1e-5 sigma^2
///            sigma the angle (degrees) between the line of sight and the direction to the
///            luminaire, tau the angle (degrees) between "up" and the plane through both.
/// So L_i^2 omega_i = I_i^2 / (A_i r_i^2): a luminaire counts with its file's intensity and
/// its opening's size, whether the scene emits it from a point or from its opening.
///
/// Which luminaires count: those from photometric files (IES, EULUMDAT) with a luminous
/// opening (a file with no opening, W = L = H = 0, has no luminance and is listed as not
/// counted), in front of the eye (sigma < 90 degrees), whose centre the eye sees (one shadow
/// ray, stopped short of the opening itself). Other lights (area, point, sky) are not
/// luminaires in CIE 117's sense and enter only through L_b.
///
/// Validity (stated per luminaire and for the result): CIE 117's formula holds for
/// luminaires of solid angle 0.0003 sr to 0.1 sr, and for UGR between 10 and 30; the position
/// index is Guth's for luminaires above the line of sight, applied to those below as Radiance
/// does (mirrored), which CIE 117 does not cover.
#include <string>
#include <vector>

#include "steradian/core/math.h"

namespace sr {

class Scene;
struct PhotometricData;
struct GoniometricProfile;
struct MeasureResult;

/// A luminaire of the scene from a photometric file (IES, EULUMDAT): a goniometric point
/// light, or a luminous opening or body (its triangles, spheres and disks share one
/// GoniometricEmission and count once).
struct PhotometricLuminaire {
    const GoniometricProfile* profile = nullptr;
    /// Candela in the scene per candela of the file ("scale", "power", tilt): the light's
    /// scale times its spectrum's photometric value (which the builder divides out).
    double multiplier = 1;
    bool opening = false;  ///< emitted from its opening (else from its photometric centre)
    Point3 centre() const;  ///< the photometric centre, world space
    Vec3 nadir() const;     ///< the world direction of gamma = 0
};
/// The scene's photometric luminaires, in the order of their lights.
std::vector<PhotometricLuminaire> photometric_luminaires(const Scene& scene);

struct GlareSource {
    std::string file;             ///< the luminaire's photometric file
    Point3 position{0, 0, 0};     ///< its photometric centre
    double distance = 0;          ///< r, m
    double intensity = 0;         ///< I towards the eye, cd
    double projected_area = 0;    ///< A, m^2
    double solid_angle = 0;       ///< omega = A / r^2, sr
    double luminance = 0;         ///< L = I / A, cd/m^2
    double position_index = 0;    ///< p
    double term = 0;              ///< L^2 omega / p^2
    bool counted = false;         ///< in the sum
    std::string note;             ///< why not counted, or a validity remark
};

struct GlareReading {
    double ugr = 0, ugr_stderr = 0;
    double indirect_illuminance = 0, indirect_stderr = 0;  ///< E_ind, lx
    double background_luminance = 0;                       ///< L_b = E_ind / pi
    bool defined = false;  ///< a luminaire counted and L_b > 0; else ugr is 0 and `note` says why
    bool in_range = false;  ///< 10 <= UGR <= 30 and every counted luminaire within 3e-4..0.1 sr
    std::string note;
    std::vector<GlareSource> sources;
};

/// Guth's position index (Levin's form above) of the unit direction `to_source` for an eye
/// looking along unit `view` with `up` (any vector not parallel to view). Returns 1 on the
/// line of sight and -1 behind the eye (sigma >= 90 degrees).
double guth_position_index(Vec3 to_source, Vec3 view, Vec3 up);

/// Projected area (m^2) of the LM-63 luminous opening of `d` seen along the unit direction
/// `l` of the luminaire frame (photometric.h: x along C0, y along C90, z up; width along y,
/// length along x, height along z), for every LM-63-2019 shape: rectangles and boxes with
/// luminous sides, disks and ellipses (horizontal or vertical), vertical and horizontal
/// (elliptical) cylinders, spheres and ellipsoids. 0 for a point (no opening).
double luminous_projected_area(const PhotometricData& d, Vec3 l);

/// The rating at one eye given the measured indirect illuminance E_ind (lx) and its
/// standard error; the rating's standard error is the first-order propagation
/// 8 / ln 10 * se(E_ind) / E_ind.
GlareReading unified_glare_rating(const Scene& scene, Point3 eye, Vec3 view, Vec3 up,
                                  double e_ind, double e_ind_stderr);

/// For every glare meter of a result: replaces its values (E_ind) by the ratings and their
/// standard errors, and keeps the details in MeterReading::glare. Called by measure().
void apply_glare(const Scene& scene, MeasureResult& result);

}  // namespace sr
