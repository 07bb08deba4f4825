#include "steradian/core/error.h"

#include <cstdio>
#include <cstdlib>
#include <mutex>
#include <set>

namespace sr {
namespace {
std::mutex g_warn_mutex;
bool g_quiet = false;
std::set<std::string> g_seen;
}  // namespace

void warning(const SourceLoc& loc, const std::string& msg) {
    std::lock_guard lock(g_warn_mutex);
    std::string line = loc.file.empty() ? msg : loc.to_string() + ": " + msg;
    if (g_quiet || !g_seen.insert(line).second) return;
    std::fprintf(stderr, "warning: %s\n", line.c_str());
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
