#include "steradian/core/error.h"

#include <cstdio>
#include <cstdlib>
#include <mutex>
#include <set>
#include <utility>
#include <vector>

#include "steradian/core/error_list.h"

namespace sr {
namespace {
std::mutex g_warn_mutex;
bool g_quiet = false;
std::set<std::string> g_seen;
std::vector<ErrorEntry>* g_capture = nullptr;  ///< the live WarningCapture's list, if any
}  // namespace

std::string printable(std::string_view text, size_t max_chars) {
    std::string out;
    size_t n = 0;
    for (char ch : text) {
        if (++n > max_chars) {
            out += "...";
            break;
        }
        auto c = static_cast<unsigned char>(ch);
        if (c >= 0x20 && c < 0x7f)
            out += ch;
        else
            out += fmt::format("\\x{:02X}", c);
    }
    return out;
}

std::string terminal_safe(std::string_view text) {
    std::string out;
    out.reserve(text.size());
    const auto* b = reinterpret_cast<const unsigned char*>(text.data());
    const size_t n = text.size();
    for (size_t i = 0; i < n;) {
        unsigned char c = b[i];
        if (c == '\n' || (c >= 0x20 && c < 0x7f)) {
            out += char(c);
            ++i;
            continue;
        }
        // A well-formed UTF-8 sequence of 2 to 4 bytes (no overlong lead bytes C0, C1).
        size_t len = c >= 0xC2 && c <= 0xDF ? 2 : c >= 0xE0 && c <= 0xEF ? 3
                   : c >= 0xF0 && c <= 0xF4 ? 4 : 0;
        bool ok = len > 0 && i + len <= n;
        for (size_t k = 1; ok && k < len; ++k) ok = (b[i + k] & 0xC0) == 0x80;
        if (ok) {
            out.append(text.substr(i, len));
            i += len;
        } else {
            out += fmt::format("\\x{:02X}", c);
            ++i;
        }
    }
    return out;
}

void warning(const SourceLoc& loc, const std::string& msg) {
    std::lock_guard lock(g_warn_mutex);
    if (g_capture) {
        g_capture->push_back({loc, msg, false});
        return;
    }
    std::string line = loc.file.empty() ? msg : loc.to_string() + ": " + msg;
    if (g_quiet || !g_seen.insert(line).second) return;
    std::fprintf(stderr, "warning: %s\n", terminal_safe(line).c_str());
}

WarningCapture::WarningCapture() {
    std::lock_guard lock(g_warn_mutex);
    SR_CHECK(g_capture == nullptr);
    g_capture = &m_warnings;
}

WarningCapture::~WarningCapture() {
    std::lock_guard lock(g_warn_mutex);
    g_capture = nullptr;
}

std::vector<ErrorEntry> WarningCapture::take() {
    std::lock_guard lock(g_warn_mutex);
    return std::exchange(m_warnings, {});
}

void set_warnings_quiet(bool quiet) {
    std::lock_guard lock(g_warn_mutex);
    g_quiet = quiet;
}

void check_failed(const char* file, int line, const char* expr) {
    std::fprintf(stderr, "internal error: CHECK(%s) failed at %s:%d\n", expr, file, line);
    std::abort();
}

}  // namespace sr
