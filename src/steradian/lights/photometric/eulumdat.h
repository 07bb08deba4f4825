#pragma once
/// EULUMDAT (.ldt) photometric file reader.
///
/// The format is line based, one field per line (a decimal comma is accepted):
///   1 company / data bank / version      2 Ityp (0-3)       3 Isym (0-4)
///   4 Mc, number of C planes in 0..360   5 Dc (deg)         6 Ng, gamma angles per plane
///   7 Dg (deg)   8 report number   9 luminaire name   10 luminaire number   11 file name
///   12 date/user   13-15 luminaire length/diameter, width (0 = round), height (mm)
///   16-17 luminous area length/diameter, width (0 = round) (mm)
///   18-21 luminous area height at C0, C90, C180, C270 (mm)
///   22 downward flux fraction (%)   23 light output ratio (%)
///   24 conversion factor for intensities   25 tilt during measurement (deg)
///   26 n, number of lamp sets, then n lines each of: number of lamps (negative = absolute
///      photometry), lamp type, total flux (lm), colour temperature, colour rendering,
///      wattage incl. ballast (W)
///   10 direct ratios (k = 0.6 ... 5), Mc C angles, Ng gamma angles, then intensities in
///   cd/klm for planes Mc1..Mc2 (1-based, wrapping past Mc), Ng values each:
///     Isym 0: 1..Mc            1 (about the vertical axis): 1..1
///     2 (C0-C180 plane): 1..Mc/2+1      3 (C90-C270 plane): 3Mc/4+1..3Mc/4+1+Mc/2
///     (i.e. C270 .. C360=C0 .. C90)      4 (both planes): 1..Mc/4+1
///
/// Conversion: candela = value x conversion factor x (total flux of lamp set 1) / 1000; the
/// first lamp set is the one the distribution was measured with (further sets are
/// alternatives). The result is Type C with horizontal_angles = all Mc C angles plus 360
/// (the 0 plane repeated), the symmetry expanded (planes missing from the file are mirrored,
/// or interpolated between stored planes for non-equidistant angles). Dimensions are
/// converted from millimetres to metres.
///
/// Every malformed input is an sr::Error located at the file and line of the offending
/// field saying what was expected.
#include <string>
#include <string_view>

#include "steradian/lights/photometric/photometric.h"

namespace sr {

PhotometricData read_eulumdat(const std::string& path);

/// Parses EULUMDAT text; `name` is used in error messages.
PhotometricData parse_eulumdat(std::string_view text, const std::string& name);

}  // namespace sr
