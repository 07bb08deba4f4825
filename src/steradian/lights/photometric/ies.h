#pragma once
/// IES LM-63 photometric file reader: LM-63-1986 (no version line), LM-63-1991 ("IESNA91"),
/// LM-63-1995 ("IESNA:LM-63-1995"), LM-63-2002 ("IESNA:LM-63-2002") and LM-63-2019
/// ("IES:LM-63-2019").
///
/// Layout: an optional version line; keyword lines "[KEYWORD] text" ([MORE] continues the
/// previous keyword; other lines are kept as free header text); "TILT=NONE",
/// "TILT=INCLUDE" (lamp-to-luminaire geometry, number of tilt angles, angles, multiplying
/// factors follow inline) or "TILT=<file>" (the same block in a file read relative to the
/// IES file's directory); then a free-format numeric block (values separated by spaces,
/// commas or line breaks, lines may break anywhere):
///   lamps, lumens per lamp (-1 = absolute photometry), candela multiplier,
///   number of vertical angles, number of horizontal angles, photometric type (1 C, 2 B,
///   3 A), units (1 feet, 2 metres), width, length, height,
///   ballast factor, future use / ballast-lamp factor / file generation type, input watts,
///   vertical angles, horizontal angles, candela values (one horizontal angle at a time).
///
/// Candela values are multiplied by the candela multiplier and the ballast factor, and, in
/// LM-63-1986/1991 files only, by the ballast-lamp photometric factor (that field is
/// "future use" in 1995/2002 and the file generation type in 2019, and is not applied).
///
/// Every malformed input is an sr::Error located at the file and line of the offending
/// value (or the last line when the file ends early) saying what was expected.
#include <string>
#include <string_view>

#include "steradian/lights/photometric/photometric.h"

namespace sr {

/// Reads and parses the IES file at `path`.
PhotometricData read_ies(const std::string& path);

/// Parses IES text. `name` is used in error messages and as the base for a relative
/// TILT=<file> (its directory).
PhotometricData parse_ies(std::string_view text, const std::string& name);

}  // namespace sr
