#pragma once
/// Load-time errors with a source location, and render-time CHECKs.
#include <fmt/format.h>

#include <stdexcept>
#include <string>
#include <string_view>

namespace sr {

/// A position in an input file: 1-based line and column. An empty file means "no location".
struct SourceLoc {
    std::string file;
    int line = 0;
    int column = 0;
    std::string to_string() const {
        if (file.empty()) return "<unknown>";
        return fmt::format("{}:{}:{}", file, line, column);
    }
};

/// A user-facing error (bad input file, bad parameter, unsupported feature). what() is the
/// whole message, prefixed by the location when there is one.
class Error : public std::runtime_error {
public:
    explicit Error(const std::string& msg) : std::runtime_error(msg), m_message(msg) {}
    Error(const SourceLoc& loc, const std::string& msg)
        : std::runtime_error(loc.file.empty() ? msg : loc.to_string() + ": " + msg),
          m_loc(loc),
          m_message(msg) {}
    const SourceLoc& loc() const { return m_loc; }
    /// The message without the location prefix.
    const std::string& message() const { return m_message; }

private:
    SourceLoc m_loc;
    std::string m_message;
};

/// An Error saying that the input asks for something steradian does not support or does not
/// know (an entity type, a feature, a parameter name no entity reads). Continuing past it is
/// safe: the scene builder records it, goes on, and reports all of them at once.
class UnsupportedError : public Error {
  public:
    using Error::Error;
};

template <typename... Args>
[[noreturn]] void throw_unsupported(const SourceLoc& loc, fmt::format_string<Args...> f,
                                    Args&&... args) {
    throw UnsupportedError(loc, fmt::format(f, std::forward<Args>(args)...));
}

template <typename... Args>
[[noreturn]] void throw_error(const SourceLoc& loc, fmt::format_string<Args...> f, Args&&... args) {
    throw Error(loc, fmt::format(f, std::forward<Args>(args)...));
}

/// Input text for an error message: at most `max_chars` characters (then "..."), and every
/// byte outside printable ASCII as \xNN, so that a binary file's bytes never reach a
/// terminal raw.
std::string printable(std::string_view text, size_t max_chars = 40);

/// A message made safe for a terminal: valid UTF-8 is kept (file names, units), while control
/// bytes (but newlines) and bytes that are not valid UTF-8 become \xNN. Every error and
/// warning passes through it before it is printed.
std::string terminal_safe(std::string_view text);

/// Warning sink: printed to stderr once each unless silenced (tests may redirect it).
void warning(const SourceLoc& loc, const std::string& msg);
void set_warnings_quiet(bool quiet);

[[noreturn]] void check_failed(const char* file, int line, const char* expr);

}  // namespace sr

#define SR_CHECK(x) ((x) ? (void)0 : ::sr::check_failed(__FILE__, __LINE__, #x))
#ifndef NDEBUG
#define SR_DCHECK(x) SR_CHECK(x)
#else
#define SR_DCHECK(x) ((void)0)
#endif
