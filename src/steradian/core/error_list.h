#pragma once
/// Errors and warnings as data: several located errors thrown at once (ErrorList), and the
/// warnings of a run captured instead of printed (WarningCapture), for `steradian check`.
#include <string>
#include <vector>

#include "steradian/core/error.h"

namespace sr {

/// One located error: where, what (without the location), and whether it is an
/// unsupported feature or unknown parameter (sr::UnsupportedError) or another error.
struct ErrorEntry {
    SourceLoc loc;
    std::string message;
    bool unsupported = false;
};

/// Several errors reported at once: the scene builder's unsupported features and unknown
/// parameters, possibly followed by the error that stopped it. what() lists them all.
class ErrorList : public Error {
  public:
    ErrorList(const std::string& what, std::vector<ErrorEntry> entries, bool truncated)
        : Error(what), m_entries(std::move(entries)), m_truncated(truncated) {}
    const std::vector<ErrorEntry>& entries() const { return m_entries; }
    /// The builder stopped at its limit of unsupported features: there may be more.
    bool truncated() const { return m_truncated; }

  private:
    std::vector<ErrorEntry> m_entries;
    bool m_truncated = false;
};

/// The located errors of an sr::Error: an ErrorList's entries, or the error itself.
inline std::vector<ErrorEntry> error_entries(const Error& e) {
    if (const auto* list = dynamic_cast<const ErrorList*>(&e)) return list->entries();
    return {{e.loc(), e.message(), dynamic_cast<const UnsupportedError*>(&e) != nullptr}};
}

/// While a WarningCapture lives, sr::warning() appends every warning to it, in order and
/// without the once-each filter, instead of printing it. One capture at a time.
class WarningCapture {
  public:
    WarningCapture();   // error.cpp
    ~WarningCapture();  // error.cpp
    WarningCapture(const WarningCapture&) = delete;
    WarningCapture& operator=(const WarningCapture&) = delete;
    /// The warnings so far (each with `unsupported` false).
    std::vector<ErrorEntry> take();

  private:
    std::vector<ErrorEntry> m_warnings;
};

}  // namespace sr
