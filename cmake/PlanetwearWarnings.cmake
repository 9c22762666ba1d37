# Warnings as a usage requirement of an INTERFACE target (cf. HighFive's
# HighFiveWarnings.cmake): link it privately, never set global flags.
add_library(planetwear_warnings INTERFACE)
add_library(pw::warnings ALIAS planetwear_warnings)
target_compile_options(planetwear_warnings INTERFACE
  $<$<CXX_COMPILER_ID:GNU,Clang>:-Wall -Wextra -Wpedantic -Wshadow -Wnon-virtual-dtor -Wconversion -Wno-sign-conversion>)
# GCC 12 reports -Wrestrict false positives inside libstdc++'s
# std::string::append/insert at -O2 (GCC bug 105329, fixed in GCC 13); they
# point into <bits/char_traits.h>, not at our code.
if(CMAKE_CXX_COMPILER_ID STREQUAL "GNU" AND CMAKE_CXX_COMPILER_VERSION VERSION_LESS 13)
  target_compile_options(planetwear_warnings INTERFACE -Wno-restrict)
endif()
