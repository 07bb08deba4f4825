/// Number parsing and token descriptions for the pbrt reader's messages.
#include "steradian/scene/pbrt/stream.h"

#include <charconv>
#include <cmath>
#include <limits>
#include <string>

namespace sr::pbrt_detail {

std::string describe(const Token& t) {
    // printable(): a binary file's bytes are escaped, not echoed to the terminal.
    if (t.kind == TokenKind::String) return fmt::format("string \"{}\"", printable(t.text));
    return fmt::format("'{}'", printable(t.text));
}

bool parse_double(std::string_view s, double& v) {
    const char* b = s.data();
    const char* e = b + s.size();
    if (b != e && *b == '+') {
        ++b;
        if (b != e && (*b == '+' || *b == '-')) return false;
    }
    auto r = std::from_chars(b, e, v);
    return r.ec == std::errc() && r.ptr == e && std::isfinite(v);
}

IntParse parse_int(std::string_view s, int& v) {
    const char* b = s.data();
    const char* e = b + s.size();
    if (b != e && *b == '+') {
        ++b;
        if (b != e && (*b == '+' || *b == '-')) return IntParse::NotInteger;
    }
    long long x = 0;
    auto r = std::from_chars(b, e, x);
    if (b == e || r.ptr != e) return IntParse::NotInteger;
    if (r.ec == std::errc::result_out_of_range || x < std::numeric_limits<int>::min() ||
        x > std::numeric_limits<int>::max())
        return IntParse::OutOfRange;
    if (r.ec != std::errc()) return IntParse::NotInteger;
    v = int(x);
    return IntParse::Ok;
}

}  // namespace sr::pbrt_detail
