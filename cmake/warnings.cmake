add_library(steradian_warnings INTERFACE)
target_compile_options(steradian_warnings INTERFACE -Wall -Wextra -Wpedantic -Wshadow)
# GCC 12 at -O3 reports false -Wrestrict errors inside std::string concatenation
# (GCC bug 105329, fixed in GCC 13); the diagnostic is off for that compiler only.
if(CMAKE_CXX_COMPILER_ID STREQUAL "GNU" AND CMAKE_CXX_COMPILER_VERSION VERSION_LESS 13)
  target_compile_options(steradian_warnings INTERFACE -Wno-restrict)
endif()
if(CMAKE_CXX_COMPILER_ID STREQUAL "Clang")
  # GCC-only tuning attributes ([[gnu::optimize]] in zsobol_sampler.cpp) mean nothing to clang
  # (used by the fuzz preset), which would otherwise warn about each.
  target_compile_options(steradian_warnings INTERFACE -Wno-unknown-attributes)
endif()
if(STERADIAN_WERROR)
  target_compile_options(steradian_warnings INTERFACE -Werror)
endif()
if(STERADIAN_FUZZ AND NOT CMAKE_CXX_COMPILER_ID STREQUAL "Clang")
  message(FATAL_ERROR "STERADIAN_FUZZ needs clang (libFuzzer): cmake --preset fuzz")
endif()
if(STERADIAN_SANITIZE OR STERADIAN_FUZZ)
  target_compile_options(steradian_warnings INTERFACE -fsanitize=address,undefined
                         -fno-sanitize-recover=undefined -fno-omit-frame-pointer)
  target_link_options(steradian_warnings INTERFACE -fsanitize=address,undefined)
  if(CMAKE_CXX_COMPILER_ID STREQUAL "GNU")
    # The sanitizers' instrumentation makes GCC's -Wmaybe-uninitialized report false
    # positives (here: moving a std::variant temporary); GCC documents the warning as
    # unreliable with them. The warning stays on in the normal -Werror build.
    target_compile_options(steradian_warnings INTERFACE -Wno-maybe-uninitialized)
  endif()
endif()
if(STERADIAN_FUZZ)
  # libFuzzer's coverage instrumentation for every source, the library included; the
  # harnesses link libFuzzer itself (-fsanitize=fuzzer, fuzz/CMakeLists.txt).
  target_compile_options(steradian_warnings INTERFACE -fsanitize=fuzzer-no-link)
endif()
