#pragma once
/// A format-neutral luminous intensity distribution read from an IES LM-63 or EULUMDAT file.
///
/// Luminaire frame (used by every accessor below): z points up, the luminaire's nadir
/// (photometric zero) is -z, the photometric horizontal (C = 0, gamma = 90 deg) is +x and
/// the C = 90 deg plane contains +y. In the Type C system a direction is
///     d(gamma, C) = (sin gamma cos C, sin gamma sin C, -cos gamma),
/// gamma measured from nadir, C counterclockwise seen from above (LM-63-2002 sec. 3).
///
/// Types B and A are stored in their own angles (as in the file) and mapped from the Type C
/// angles of a query direction (LM-63-2002 sec. 3: photometric zero and photometric
/// horizontal are the same directions in all three types; A and B horizontal angles turn
/// clockwise, i.e. a positive horizontal angle H points towards -y):
///   Type B (polar axis horizontal, along y): the file's vertical angle V turns the
///     measuring plane about the y axis (V = 0 nadir, V = +90 photometric horizontal +x),
///     the horizontal angle H is the lateral angle within that plane:
///       d(H, V) = (cos H sin V, -sin H, -cos H cos V).
///   Type A (polar axis vertical): V is the elevation (V = -90 nadir, V = 0 horizontal),
///     H the azimuth:  d(H, V) = (cos V cos H, -cos V sin H, sin V).
/// A direction outside a Type A/B file's measured range (e.g. behind a floodlight) has
/// intensity 0.
#include <map>
#include <string>
#include <vector>

namespace sr {

enum class PhotometricFormat { Ies, Eulumdat };

/// LM-63 photometric type code (1 = C, 2 = B, 3 = A). EULUMDAT data are always Type C.
enum class PhotometricType { C = 1, B = 2, A = 3 };

/// Luminous opening shape, classified by the signs of width, length and height as in
/// LM-63-2002 (Table 1). "Along" means the axis lies along the photometric horizontal
/// (the 0-180 deg line, the length direction); "perpendicular" along the 90-270 line.
enum class LuminousShape {
    Point,                                      // W = L = H = 0
    Rectangular,                                // W > 0, L > 0, H = 0
    RectangularWithLuminousSides,               // W > 0, L > 0, H > 0
    Circular,                                   // W = L < 0, H = 0 (diameter |W|)
    Elliptical,                                 // W, L < 0, W != L, H = 0
    VerticalCylinder,                           // W = L < 0, H > 0
    VerticalEllipticalCylinder,                 // W, L < 0, W != L, H > 0
    Sphere,                                     // W = L = H < 0
    Ellipsoid,                                  // W, L, H < 0, not all equal
    HorizontalCylinderAlong,                    // W = H < 0, L > 0
    HorizontalEllipticalCylinderAlong,          // W, H < 0, W != H, L > 0
    HorizontalCylinderPerpendicular,            // L = H < 0, W > 0
    HorizontalEllipticalCylinderPerpendicular,  // L, H < 0, L != H, W > 0
    VerticalCircleFacingHorizontal,             // W = H < 0, L = 0
    VerticalEllipseFacingHorizontal,            // W, H < 0, W != H, L = 0
    VerticalCirclePerpendicular,                // L = H < 0, W = 0
    VerticalEllipsePerpendicular,               // L, H < 0, L != H, W = 0
    Unknown,                                    // any other sign pattern
};

const char* to_string(PhotometricType t);
const char* to_string(LuminousShape s);

/// LM-63 shape classification from the signed dimensions (any consistent unit).
LuminousShape classify_luminous_shape(double width, double length, double height);

/// LM-63 lamp tilt data: multiplying factors as a function of the lamp's tilt angle
/// (degrees) in the luminaire. Not applied to the candela table: the factor depends on how
/// the luminaire is mounted, which the scene knows.
struct TiltData {
    /// "NONE", "INCLUDE" or the tilt file name as written after TILT=.
    std::string mode = "NONE";
    /// 1 = vertical base-up/down lamp, 2 = horizontal lamp whose axis stays horizontal when
    /// the luminaire tilts, 3 = horizontal lamp that tilts with the luminaire; 0 = no tilt.
    int lamp_to_luminaire_geometry = 0;
    std::vector<double> angles;   // degrees, increasing
    std::vector<double> factors;  // dimensionless, same size as angles
    /// Multiplying factor at `angle_deg`, linear between entries and clamped at the ends;
    /// 1 when there is no tilt data.
    double factor(double angle_deg) const;
};

/// One EULUMDAT lamp set (IES files fill one set from the lamp line).
struct LampSet {
    int count = 0;  // number of lamps; negative in EULUMDAT = absolute photometry
    std::string type;
    double total_flux_lm = 0;  // all lamps of the set together
    std::string colour;        // colour temperature / appearance as written
    std::string cri;           // colour rendering group / index as written
    double watts = 0;          // including ballast
};

struct PhotometricData {
    std::string source;  // file name the data came from
    PhotometricFormat format = PhotometricFormat::Ies;
    /// "LM-63-1986", "LM-63-1991", "LM-63-1995", "LM-63-2002", "LM-63-2019" or "EULUMDAT".
    std::string version;
    /// IES keyword lines ("TEST" -> "ABC123"; repeated keywords and [MORE] lines are joined
    /// by '\n'); EULUMDAT text lines under "COMPANY", "REPORT", "LUMINAIRE", ... .
    std::map<std::string, std::string> keywords;
    /// Header lines that are neither a version line nor a keyword (LM-63-1986 labels).
    std::vector<std::string> header_lines;

    PhotometricType type = PhotometricType::C;
    /// Degrees, strictly increasing, as given in the file: Type C gamma from nadir; Type
    /// A/B the vertical angle V (see the frame note at the top of this header).
    std::vector<double> vertical_angles;
    /// Degrees, strictly increasing, as given (Type C: C planes; A/B: H). The symmetry is
    /// implied by the first and last entries (LM-63-2002 sec. 5.15): Type C {0} rotational,
    /// 0..90 quadrant, 0..180 bilateral about the 0-180 plane, 90..270 bilateral about the
    /// 90-270 plane, 0..(180, 360] none (the gap up to 360 wraps to the 0 plane); Types A/B
    /// a range starting at 0 mirrors the angle (-x -> x), for H and V alike.
    std::vector<double> horizontal_angles;
    /// Luminous intensity in candela, candela[h][v] for horizontal_angles[h] and
    /// vertical_angles[v], with every multiplier below already applied.
    std::vector<std::vector<double>> candela;

    /// Lumens per lamp for relative photometry, -1 for absolute photometry.
    double lamp_lumens = -1;
    int num_lamps = 1;
    /// Factors as read (already folded into `candela`): candela multiplier (EULUMDAT:
    /// conversion factor x flux / 1000), ballast factor, ballast-lamp photometric factor
    /// (LM-63-1986/1991 only; 1 otherwise).
    double candela_multiplier = 1;
    double ballast_factor = 1;
    double ballast_lamp_factor = 1;
    /// The 12th number of the IES lamp line as written: the ballast-lamp factor in
    /// 1986/1991, "future use" in 1995/2002, the file generation type in 2019 (1.00001
    /// undefined, 1.00010 simulation, 1.abcde flags otherwise). NaN for EULUMDAT.
    double future_use = 1;
    int units_type = 2;  // LM-63: 1 feet, 2 metres (EULUMDAT: millimetres, stored as 2)
    /// Luminous opening in metres (absolute values; the sign pattern is in `shape`): width
    /// measured along the 90-270 deg direction (y), length along the 0-180 deg direction
    /// (x, the photometric horizontal), height along z. Diameters for round shapes.
    double width = 0, length = 0, height = 0;
    LuminousShape shape = LuminousShape::Point;
    double input_watts = 0;
    TiltData tilt;

    /// EULUMDAT extras (unset for IES): light output ratio and downward flux fraction as
    /// fractions (-1 unknown), measurement tilt (deg), direct ratios for k = 0.6 ... 5.
    double light_output_ratio = -1;
    double downward_flux_fraction = -1;
    double measurement_tilt_deg = 0;
    std::vector<double> direct_ratios;
    std::vector<LampSet> lamp_sets;

    /// Luminous intensity (cd) towards Type C angles (degrees) of the luminaire frame:
    /// bilinear in the file's own angles, the file's symmetry expanded to the full sphere,
    /// 0 outside the measured range. Any gamma/C is accepted (wrapped to the sphere).
    double intensity(double gamma_deg, double c_deg) const;
    /// The same for a direction (x, y, z) of the luminaire frame (need not be normalised;
    /// the zero vector gives 0).
    double intensity_direction(double x, double y, double z) const;
    /// Total luminous flux (lm) of the interpolated distribution: the exact integral over
    /// the sphere of the piecewise bilinear interpolant used by intensity() (trapezoid in
    /// the azimuthal angle, closed-form sin/cos weights in the polar angle, on the data
    /// grid expanded by symmetry).
    double total_flux() const;
    /// lamp_lumens * num_lamps for relative photometry, -1 for absolute photometry.
    double nominal_flux() const;
    /// Largest tabulated intensity (cd).
    double max_intensity() const;

    /// Intensity at the file's own angles (h = horizontal angle, v = vertical angle, in
    /// degrees, in the file's photometric type), symmetry applied, 0 outside the range.
    double table_intensity(double h_deg, double v_deg) const;
};

}  // namespace sr
