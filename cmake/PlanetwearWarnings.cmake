# Warnings as a usage requirement of an INTERFACE target (cf. HighFive's
# HighFiveWarnings.cmake): link it privately, never set global flags.
add_library(planetwear_warnings INTERFACE)
add_library(pw::warnings ALIAS planetwear_warnings)
target_compile_options(planetwear_warnings INTERFACE
  $<$<CXX_COMPILER_ID:GNU,Clang>:-Wall -Wextra -Wpedantic -Wshadow -Wnon-virtual-dtor -Wconversion -Wno-sign-conversion>)
