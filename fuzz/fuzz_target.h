#pragma once
/// The frame of the harnesses in fuzz/: STERADIAN_FUZZ_TARGET(name) { ... } defines a
/// harness body that receives the input bytes as `std::string_view input`. It is built two
/// ways (fuzz/CMakeLists.txt):
/// - in the fuzz preset (clang, STERADIAN_FUZZ) each harness is its own libFuzzer binary
///   (fuzz_<name>) whose LLVMFuzzerTestOneInput calls the body;
/// - in every other build all harnesses go into one program, steradian_fuzz_replay, which
///   runs the files of fuzz/regressions/<name>/ through the body of that name (ctest
///   fuzz_regressions), so inputs that once crashed keep being checked without clang.
/// A body returns normally when the reader accepted the input or rejected it with an
/// sr::Error naming the input; anything else (another exception, a failed fuzz_check, a
/// sanitizer report, a hang, an unbounded allocation) is a bug in the reader.
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <string>
#include <string_view>

#include "steradian/core/error.h"

namespace sr::fuzz {

using TargetFn = void (*)(std::string_view input);

/// Adds a harness to the replay program's table (unused with libFuzzer).
bool register_target(const char* name, TargetFn fn);

/// Aborts (a crash libFuzzer records) with `what` unless `ok`.
inline void fuzz_check(bool ok, const char* what) {
    if (ok) return;
    std::fprintf(stderr, "fuzz_check failed: %s\n", what);
    std::abort();
}

/// With STERADIAN_FUZZ_VERBOSE=1 in the environment, prints the reader's rejection of an input
/// (to see what seeds and regression inputs are rejected for); otherwise does nothing.
inline void note_rejection(const Error& e) {
    static const bool verbose = std::getenv("STERADIAN_FUZZ_VERBOSE") != nullptr;
    if (verbose) std::fprintf(stderr, "rejected: %s\n", e.what());
}

/// A reader's rejection must say which input it is about: the error's text contains `name`
/// (the file name the harness gave the reader), so a user sees where the problem is.
inline void check_names_input(const Error& e, std::string_view name) {
    note_rejection(e);
    if (std::string_view(e.what()).find(name) != std::string_view::npos) return;
    std::fprintf(stderr, "error without the input's name \"%.*s\": %s\n", int(name.size()),
                 name.data(), e.what());
    std::abort();
}

inline void check_finite(double x, const char* what) { fuzz_check(std::isfinite(x), what); }

}  // namespace sr::fuzz

#ifdef STERADIAN_LIBFUZZER
// Warnings are silenced: printing them would slow the fuzzer, and the set that prints each
// only once would grow with every new message.
#define STERADIAN_FUZZ_TARGET(name)                                                    \
    extern "C" int LLVMFuzzerInitialize(int*, char***) {                               \
        sr::set_warnings_quiet(true);                                                  \
        return 0;                                                                      \
    }                                                                                  \
    static void fuzz_body_##name(std::string_view input);                              \
    extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {          \
        fuzz_body_##name(std::string_view(reinterpret_cast<const char*>(data), size)); \
        return 0;                                                                      \
    }                                                                                  \
    static void fuzz_body_##name(std::string_view input)
#else
#define STERADIAN_FUZZ_TARGET(name)                             \
    static void fuzz_body_##name(std::string_view input);       \
    [[maybe_unused]] static const bool fuzz_registered_##name = \
        ::sr::fuzz::register_target(#name, fuzz_body_##name);   \
    static void fuzz_body_##name(std::string_view input)
#endif
