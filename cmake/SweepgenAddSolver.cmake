# sweepgen_add_solver(<target> SCENE <scene.yaml> [OUTPUT_DIR <dir>] [EXPOSE all|outputs] [ARCH <isa>] [CUDA])
#
# Generates the solver a scene file describes, at build time, and wraps it in a static
# library <target> whose headers are on its include path:
#   #include "<target>.hpp"   // namespace: the scene's `solver:` entry
# Regenerates when the scene, the URDF it names (through a depfile), or the generator (and
# with it its embedded templates) change. ARCH compiles the generated source (only) with
# -march=<isa>, e.g. x86-64-v3 (AVX2, FMA: fewer instructions, FMA contraction changes the last
# bits) or native; the default is the compiler's baseline, which runs on every CPU of the
# architecture, and on x86-64 the batch entry points are compiled once more for each ISA of
# SWEEPGEN_BATCH_ISAS and pick the widest the running CPU has (sweepgen_solver_library). The
# generated code uses plain arrays, so its ABI does not change with ARCH.
# CUDA also builds <target>_cuda from the generated <target>.cu: the kernels and their launchers
# (<solve>_cuda, <solve>_cuda_host) beside every host function, so a program links it instead of
# <target>. It needs the CUDA language enabled first (project(... LANGUAGES CXX CUDA) or
# enable_language(CUDA)); without it configure says so and builds the rest.

# ARCH "" (no ISA) is passed on as an empty value, which CMake 3.31 and later warn about unless
# cmake_parse_arguments keeps it (CMP0174 NEW): the functions below read it as no ARCH either way.
if(POLICY CMP0174)
  cmake_policy(SET CMP0174 NEW)
endif()

function(sweepgen_add_solver target)
  cmake_parse_arguments(PARSE_ARGV 1 arg "CUDA" "SCENE;OUTPUT_DIR;EXPOSE;ARCH" "")
  if(NOT arg_SCENE)
    message(FATAL_ERROR "sweepgen_add_solver(${target}): SCENE is required")
  endif()
  if(arg_UNPARSED_ARGUMENTS)
    message(FATAL_ERROR "sweepgen_add_solver(${target}): unknown arguments ${arg_UNPARSED_ARGUMENTS}")
  endif()
  get_filename_component(scene "${arg_SCENE}" ABSOLUTE BASE_DIR "${CMAKE_CURRENT_SOURCE_DIR}")
  # Said here, at configure time, not by the build tool as a missing input of the generator's rule.
  get_source_file_property(scene_is_generated "${scene}" GENERATED)
  if(NOT EXISTS "${scene}" AND NOT scene_is_generated)
    message(FATAL_ERROR "sweepgen_add_solver(${target}): no scene file ${scene} (SCENE ${arg_SCENE}, relative to "
                        "${CMAKE_CURRENT_SOURCE_DIR})")
  endif()
  set(out "${arg_OUTPUT_DIR}")
  if(NOT out)
    set(out "${CMAKE_CURRENT_BINARY_DIR}/sweepgen/${target}")
  endif()
  set(extra)
  if(arg_EXPOSE)
    list(APPEND extra --expose ${arg_EXPOSE})
  endif()
  add_custom_command(
    OUTPUT "${out}/${target}.hpp" "${out}/${target}.cpp" "${out}/${target}.cu"
    COMMAND sweepgen::sweepgen generate --quiet --scene "${scene}" --out "${out}" --file-stem ${target}
            --depfile "${out}/${target}.d" ${extra}
    DEPENDS "${scene}" sweepgen::sweepgen
    DEPFILE "${out}/${target}.d"
    COMMENT "sweepgen: generating ${target} from ${arg_SCENE}"
    VERBATIM)
  sweepgen_solver_library(${target} ARCH "${arg_ARCH}" SOURCES "${out}/${target}.cpp" "${out}/${target}.hpp"
                          INCLUDE_DIRS "${out}")
  if(arg_CUDA)
    sweepgen_cuda_library(${target}_cuda SOURCE "${out}/${target}.cu" INCLUDE_DIRS "${out}")
  endif()
endfunction()

# sweepgen_committed_solver(<target> GENERATED <dir>/<stem> [ARCH <isa>] [CUDA])
# The library sweepgen_add_solver would make, from files `sweepgen generate` wrote earlier
# (<dir>/<stem>.hpp, .cpp, .cu; the bundled scenes' committed generated/ files), without running the
# generator: <target>.hpp forwards to <stem>.hpp, so that the library looks like
# sweepgen_add_solver's (sweepgen_add_python_module reads it); CUDA: <target>_cuda too.
function(sweepgen_committed_solver target)
  cmake_parse_arguments(PARSE_ARGV 1 arg "CUDA" "GENERATED;ARCH" "")
  get_filename_component(arg_GENERATED "${arg_GENERATED}" ABSOLUTE BASE_DIR "${CMAKE_CURRENT_SOURCE_DIR}")
  get_filename_component(dir "${arg_GENERATED}" DIRECTORY)
  get_filename_component(stem "${arg_GENERATED}" NAME)
  if(NOT EXISTS "${arg_GENERATED}.hpp" OR NOT EXISTS "${arg_GENERATED}.cpp")
    message(FATAL_ERROR "sweepgen_committed_solver(${target}): no ${arg_GENERATED}.hpp and .cpp (sweepgen generate writes them)")
  endif()
  set(forward_dir ${CMAKE_CURRENT_BINARY_DIR}/sweepgen/${target})
  file(CONFIGURE OUTPUT ${forward_dir}/${target}.hpp
       CONTENT "// Forwards to ${arg_GENERATED}.hpp (sweepgen_committed_solver).\n#pragma once\n#include \"${stem}.hpp\"\n")
  sweepgen_solver_library(${target} ARCH "${arg_ARCH}" SOURCES ${arg_GENERATED}.cpp INCLUDE_DIRS ${forward_dir} ${dir})
  # The generated header itself, for sweepgen_add_python_module (which reads the scene from it).
  set_target_properties(${target} PROPERTIES SWEEPGEN_HEADER "${arg_GENERATED}.hpp")
  if(arg_CUDA)
    sweepgen_cuda_library(${target}_cuda SOURCE ${arg_GENERATED}.cu INCLUDE_DIRS ${forward_dir} ${dir})
  endif()
endfunction()

# The CUDA library of a generated solver (its .cu: kernels, launchers and the host functions),
# where the CUDA language is enabled; else a configure message, and nothing.
function(sweepgen_cuda_library target)
  cmake_parse_arguments(PARSE_ARGV 1 arg "" "SOURCE" "INCLUDE_DIRS")
  get_property(languages GLOBAL PROPERTY ENABLED_LANGUAGES)
  if(NOT "CUDA" IN_LIST languages)
    include(CheckLanguage)
    check_language(CUDA)
    if(CMAKE_CUDA_COMPILER)
      message(STATUS "sweepgen: ${target} not built: a CUDA compiler is installed (${CMAKE_CUDA_COMPILER}), but the "
                     "CUDA language is not enabled; call enable_language(CUDA) before sweepgen_add_solver")
    else()
      message(STATUS "sweepgen: ${target} not built: no CUDA compiler found (the host library is built)")
    endif()
    return()
  endif()
  add_library(${target} STATIC ${arg_SOURCE})
  target_include_directories(${target} PUBLIC ${arg_INCLUDE_DIRS})
  target_compile_features(${target} PUBLIC cxx_std_17 cuda_std_17)
endfunction()

# The ISAs whose batch entry points a solver library built without ARCH carries beside the
# baseline's on x86-64 with GCC or clang (docs/generated-code.md, "Batches and GPUs"): each a second compile of the
# generated source with -march=<isa> -ffp-contract=off (no fused multiply-adds: every state's
# values stay the flat call's, bit for bit). Empty: none (the batch entry points then run in the
# baseline's two-double lanes). The batch code's compile time, once per ISA: bench/README.md.
set(SWEEPGEN_BATCH_ISAS "x86-64-v3;x86-64-v4" CACHE STRING
  "ISAs (x86-64-v3, x86-64-v4) the batch entry points of solvers built without ARCH are compiled for, chosen at run time")

# The static library of a generated solver: its sources, public include directories, C++17 and,
# with ARCH, -march=ARCH once the compiler is known to take it; without ARCH, on x86-64, the batch
# entry points once more per ISA of SWEEPGEN_BATCH_ISAS (the generated source included by a file
# that defines SWEEPGEN_BATCH_ISA, compiled with -march=<isa> -ffp-contract=off: the top of the
# generated .cpp says how the two find each other). sweepgen_add_solver's, and the bundled scenes'
# when they are built from the committed generated/ files (cmake/BundledScenes.cmake).
function(sweepgen_solver_library target)
  cmake_parse_arguments(PARSE_ARGV 1 arg "" "ARCH" "SOURCES;INCLUDE_DIRS")
  add_library(${target} STATIC ${arg_SOURCES})
  target_include_directories(${target} PUBLIC ${arg_INCLUDE_DIRS})
  target_compile_features(${target} PUBLIC cxx_std_17)
  if(NOT arg_ARCH AND SWEEPGEN_BATCH_ISAS AND CMAKE_SYSTEM_PROCESSOR MATCHES "^(x86_64|AMD64|amd64)$"
     AND CMAKE_SIZEOF_VOID_P EQUAL 8 AND CMAKE_CXX_COMPILER_ID MATCHES "GNU|Clang")
    list(FILTER arg_SOURCES INCLUDE REGEX "\\.cpp$")
    list(GET arg_SOURCES 0 source)
    get_filename_component(source "${source}" ABSOLUTE)
    include(CheckCXXCompilerFlag)
    foreach(isa ${SWEEPGEN_BATCH_ISAS})
      if(NOT isa MATCHES "^x86-64-v[34]$")
        message(FATAL_ERROR "SWEEPGEN_BATCH_ISAS: ${isa} is not one of x86-64-v3, x86-64-v4")
      endif()
      string(MAKE_C_IDENTIFIER "${isa}" name)  # x86_64_v3: the ISA's namespace in the generated code
      string(TOUPPER "${name}" upper)
      string(MAKE_C_IDENTIFIER "SWEEPGEN_MARCH_${isa}" flag_ok)
      check_cxx_compiler_flag("-march=${isa}" ${flag_ok})
      if(NOT ${flag_ok})
        continue()  # an older compiler: the batch entry points run in the baseline's lanes
      endif()
      set(wrapper "${CMAKE_CURRENT_BINARY_DIR}/sweepgen_batch/${target}_${name}.cpp")
      file(CONFIGURE OUTPUT "${wrapper}" CONTENT
           "// The batch entry points of ${source} for ${isa} (sweepgen_solver_library).\n#define SWEEPGEN_BATCH_ISA ${name}\n#include \"${source}\"\n")
      target_sources(${target} PRIVATE "${wrapper}")
      set_source_files_properties("${wrapper}" PROPERTIES COMPILE_OPTIONS "-march=${isa};-ffp-contract=off")
      target_compile_definitions(${target} PRIVATE SWEEPGEN_BATCH_${upper})
    endforeach()
  endif()
  if(arg_ARCH)
    include(CheckCXXCompilerFlag)
    string(MAKE_C_IDENTIFIER "SWEEPGEN_MARCH_${arg_ARCH}" flag_ok)
    check_cxx_compiler_flag("-march=${arg_ARCH}" ${flag_ok})
    if(NOT ${flag_ok})
      message(FATAL_ERROR "sweepgen solver ${target}: ARCH ${arg_ARCH}: the C++ compiler does not take -march=${arg_ARCH}")
    endif()
    target_compile_options(${target} PRIVATE -march=${arg_ARCH})
  endif()
endfunction()
