#include "steradian/lights/photometric/text_util.h"

#include <charconv>
#include <cmath>
#include <cstdlib>
#include <fstream>
#include <sstream>

#include "steradian/core/error.h"
#include "steradian/core/input_file.h"

namespace sr::photometric_detail {

std::vector<std::string_view> split_lines(std::string_view text) {
    if (text.size() >= 3 && text.substr(0, 3) == "\xEF\xBB\xBF") text.remove_prefix(3);
    std::vector<std::string_view> lines;
    size_t start = 0;
    for (size_t i = 0; i < text.size(); ++i) {
        char c = text[i];
        if (c != '\n' && c != '\r') continue;
        lines.push_back(text.substr(start, i - start));
        if (c == '\r' && i + 1 < text.size() && text[i + 1] == '\n') ++i;
        start = i + 1;
    }
    if (start < text.size()) lines.push_back(text.substr(start));
    return lines;
}

static bool is_space(char c) {
    return c == ' ' || c == '\t' || c == '\f' || c == '\v' || c == '\r' || c == '\n';
}

std::string_view trim(std::string_view s) {
    while (!s.empty() && is_space(s.front())) s.remove_prefix(1);
    while (!s.empty() && is_space(s.back())) s.remove_suffix(1);
    return s;
}

std::string to_upper(std::string_view s) {
    std::string out(s);
    for (char& c : out) {
        if (c >= 'a' && c <= 'z') c = static_cast<char>(c - 'a' + 'A');
    }
    return out;
}

NumberStatus parse_number(std::string_view token, double& out) {
    std::string_view t = token;
    if (!t.empty() && t.front() == '+') t.remove_prefix(1);
    if (t.empty() || t.front() == '+') return NumberStatus::NotANumber;
    double value = 0;
    auto [ptr, ec] = std::from_chars(t.data(), t.data() + t.size(), value);
    if (ptr != t.data() + t.size()) return NumberStatus::NotANumber;
    if (ec == std::errc::result_out_of_range) {
        // Overflow is not finite; underflow rounds to a tiny or zero value.
        value = std::strtod(std::string(t).c_str(), nullptr);
    } else if (ec != std::errc()) {
        return NumberStatus::NotANumber;
    }
    if (!std::isfinite(value)) return NumberStatus::NotFinite;
    out = value;
    return NumberStatus::Ok;
}

std::string quoted(std::string_view token) { return "'" + printable(token) + "'"; }

std::string read_file_text(const std::string& path, const char* what) {
    if (std::string why = regular_file_problem(path, kMaxSmallFileBytes); !why.empty())
        throw Error(fmt::format("{}: cannot open {}: {}", path, what, why));
    return read_regular_file(path, kMaxSmallFileBytes, what);
}

}  // namespace sr::photometric_detail
