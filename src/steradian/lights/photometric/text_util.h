#pragma once
/// Small text helpers shared by the photometric readers (internal to this directory).
#include <string>
#include <string_view>
#include <vector>

namespace sr::photometric_detail {

/// The largest luminous intensity (cd) a file may give once its multipliers are applied.
/// The renderer holds intensities and the total flux (at most 4 pi times the largest
/// intensity) in 32-bit floats: 1e36 cd keeps both finite (FLT_MAX is 3.4e38), and is
/// still 27 orders of magnitude above the brightest lamps.
inline constexpr double kMaxCandela = 1e36;

/// Splits text into lines at "\r\n", "\n" or "\r"; drops a leading UTF-8 byte order mark.
/// A final line break does not start an extra empty line. Views point into `text`.
std::vector<std::string_view> split_lines(std::string_view text);

/// Strips spaces, tabs and other ASCII whitespace at both ends.
std::string_view trim(std::string_view s);

std::string to_upper(std::string_view s);

enum class NumberStatus { Ok, NotANumber, NotFinite };

/// Parses the whole token as a decimal floating-point number (an optional leading '+' is
/// accepted). NaN and infinities are reported as NotFinite.
NumberStatus parse_number(std::string_view token, double& out);

/// A token for an error message: quoted, at most 40 characters, non-printable bytes as
/// \xNN.
std::string quoted(std::string_view token);

/// Reads a whole file; throws sr::Error naming the file (and `what`, e.g. "IES file") when it
/// cannot be opened or read.
std::string read_file_text(const std::string& path, const char* what);

}  // namespace sr::photometric_detail
