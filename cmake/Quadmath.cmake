# sweepgen_quadmath: GCC's libquadmath (__float128 arithmetic and math functions) for the
# high-precision referee (generator/solver/quad_scalar.hpp). g++ finds quadmath.h by itself;
# clang does not search GCC's private include directory, so it is added with -idirafter, behind
# clang's own headers (the library itself is on clang's default link path next to libstdc++).
include(CheckIncludeFileCXX)
add_library(sweepgen_quadmath INTERFACE)
target_link_libraries(sweepgen_quadmath INTERFACE quadmath)
check_include_file_cxx(quadmath.h SWEEPGEN_HAS_QUADMATH_H)
if(NOT SWEEPGEN_HAS_QUADMATH_H)
  find_program(SWEEPGEN_GCC NAMES gcc)
  if(SWEEPGEN_GCC)
    execute_process(COMMAND ${SWEEPGEN_GCC} -print-file-name=include OUTPUT_VARIABLE gcc_include
                    OUTPUT_STRIP_TRAILING_WHITESPACE)
  endif()
  if(NOT SWEEPGEN_GCC OR NOT EXISTS "${gcc_include}/quadmath.h")
    message(FATAL_ERROR "quadmath.h (GCC's libquadmath, the __float128 referee) not found; install g++ "
                        "(cmake/install-dependencies.sh does)")
  endif()
  target_compile_options(sweepgen_quadmath INTERFACE -idirafter ${gcc_include})
endif()
