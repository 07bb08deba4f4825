add_library(steradian_warnings INTERFACE)
target_compile_options(steradian_warnings INTERFACE -Wall -Wextra -Wpedantic -Wshadow)
# GCC 12 at -O3 reports false -Wrestrict errors inside std::string concatenation
# (GCC bug 105329, fixed in GCC 13); the diagnostic is off for that compiler only.
if(CMAKE_CXX_COMPILER_ID STREQUAL "GNU" AND CMAKE_CXX_COMPILER_VERSION VERSION_LESS 13)
  target_compile_options(steradian_warnings INTERFACE -Wno-restrict)
endif()
if(STERADIAN_WERROR)
  target_compile_options(steradian_warnings INTERFACE -Werror)
endif()
if(STERADIAN_SANITIZE)
  # The sanitizers' instrumentation makes GCC's -Wmaybe-uninitialized report false positives
  # (here: moving a std::variant temporary); GCC documents the warning as unreliable with
  # them. The warning stays on in the normal -Werror build.
  target_compile_options(steradian_warnings INTERFACE -fsanitize=address,undefined
                         -fno-sanitize-recover=undefined -fno-omit-frame-pointer
                         -Wno-maybe-uninitialized)
  target_link_options(steradian_warnings INTERFACE -fsanitize=address,undefined)
endif()
