# The generated solver as a Python module (README, "Python"): pybind11 and NumPy.
#
# sweepgen_find_python()
#   Finds what the modules need: a Python 3 interpreter that imports NumPy, its development files
#   (Development.Module) and pybind11 (CONFIG). Sets SWEEPGEN_PYTHON_FOUND, SWEEPGEN_PYTHON_EXECUTABLE
#   (the interpreter the modules are built for and imported by) and, when something is missing,
#   SWEEPGEN_PYTHON_MISSING (what, and the Debian package, for a message). Without
#   -DPython3_EXECUTABLE it takes the first of `python3` on PATH and /usr/bin/python3 that imports
#   NumPy: a pyenv or virtual-environment interpreter with NumPy is used, one without it (a pyenv
#   shim first on PATH) does not hide the system interpreter. Says which interpreter the modules
#   are for, and which it passed over, or what is missing (message STATUS). Debian 12:
#   pybind11-dev python3-dev python3-numpy. A macro: call it at directory scope, before
#   sweepgen_add_python_module().
#
# sweepgen_add_python_module(<name> SCENE <scene.yaml> [OUTPUT_DIR <dir>] [EXPOSE all|outputs] [CUDA])
# sweepgen_add_python_module(<name> SOLVER <target>)
#   Builds the extension module <name> (`import <name>`) of a scene's generated solver: with SCENE
#   from a new sweepgen_add_solver(<name>_solver ...) library (CUDA: with its CUDA library), with
#   SOLVER from an existing one. Where the solver has its CUDA library (<target>_cuda), the module
#   gets the kernels too (<name>.cuda; its PyTorch layer runs CUDA tensors on them): nvcc compiles
#   python/module_cuda.cu with the generated .cu into lib<name>_cuda.so, which the module links.
#   The library is made position-independent and linked into the module, so the generated source is
#   compiled once for C++ and Python alike. The binding is one library for all modules of a build
#   (python/binding.cpp, target sweepgen_python_binding), each module's own source one for all
#   scenes (python/module.cpp), which describes the scene to it; the scene's namespace, scalars and
#   flat layout are read from the generated header at build time into
#   <binary dir>/sweepgen_python/<name>/sweepgen_module_scene.hpp.
#   The module lands in the target's LIBRARY_OUTPUT_DIRECTORY (set it to collect several).

# The first of `python3` on PATH and /usr/bin/python3 that imports NumPy (or ""), and in
# `passed_over` the ones before it that do not.
function(_sweepgen_python_with_numpy out passed_over)
  find_program(_sweepgen_path_python3 NAMES python3 NO_CACHE)
  set(without)
  foreach(candidate ${_sweepgen_path_python3} /usr/bin/python3)
    if(EXISTS "${candidate}" AND NOT candidate IN_LIST without)
      execute_process(COMMAND "${candidate}" -c "import numpy" RESULT_VARIABLE failed OUTPUT_QUIET ERROR_QUIET)
      if(NOT failed)
        set(${out} "${candidate}" PARENT_SCOPE)
        set(${passed_over} "${without}" PARENT_SCOPE)
        return()
      endif()
      list(APPEND without "${candidate}")
    endif()
  endforeach()
  set(${out} "" PARENT_SCOPE)
  set(${passed_over} "${without}" PARENT_SCOPE)
endfunction()

macro(sweepgen_find_python)
  set(_sweepgen_passed_over)
  if(NOT DEFINED Python3_EXECUTABLE)
    _sweepgen_python_with_numpy(_sweepgen_python _sweepgen_passed_over)
    if(_sweepgen_python)
      set(Python3_EXECUTABLE "${_sweepgen_python}" CACHE FILEPATH "Python interpreter of the sweepgen Python modules")
    endif()
  endif()
  find_package(Python3 QUIET COMPONENTS Interpreter Development.Module NumPy)
  set(SWEEPGEN_PYTHON_SEARCHED TRUE)
  set(SWEEPGEN_PYTHON_FOUND FALSE)
  set(SWEEPGEN_PYTHON_MISSING "")
  if(NOT Python3_Interpreter_FOUND)
    set(SWEEPGEN_PYTHON_MISSING "a Python 3 interpreter (Debian: python3)")
  elseif(NOT Python3_NumPy_FOUND)
    set(SWEEPGEN_PYTHON_MISSING "NumPy for ${Python3_EXECUTABLE} (Debian: python3-numpy)")
  elseif(NOT Python3_Development.Module_FOUND)
    set(SWEEPGEN_PYTHON_MISSING "the Python headers of ${Python3_EXECUTABLE} (Debian: python3-dev)")
  else()
    find_package(pybind11 CONFIG QUIET)
    if(pybind11_FOUND)
      set(SWEEPGEN_PYTHON_FOUND TRUE)
      set(SWEEPGEN_PYTHON_EXECUTABLE "${Python3_EXECUTABLE}")
    else()
      set(SWEEPGEN_PYTHON_MISSING "pybind11 (Debian: pybind11-dev)")
    endif()
  endif()
  if(_sweepgen_passed_over)
    list(JOIN _sweepgen_passed_over ", " _sweepgen_passed_over)
    set(_sweepgen_passed_over "; passed over ${_sweepgen_passed_over}, which cannot import NumPy")
  endif()
  if(SWEEPGEN_PYTHON_FOUND)
    message(STATUS "sweepgen: Python modules are built for ${SWEEPGEN_PYTHON_EXECUTABLE} (Python "
                   "${Python3_VERSION}, NumPy ${Python3_NumPy_VERSION}): import them with that interpreter"
                   "${_sweepgen_passed_over}")
  else()
    message(STATUS "sweepgen: no Python modules: ${SWEEPGEN_PYTHON_MISSING} not found${_sweepgen_passed_over}")
  endif()
endmacro()

function(sweepgen_add_python_module name)
  cmake_parse_arguments(PARSE_ARGV 1 arg "CUDA" "SCENE;SOLVER;OUTPUT_DIR;EXPOSE" "")
  if(arg_UNPARSED_ARGUMENTS)
    message(FATAL_ERROR "sweepgen_add_python_module(${name}): unknown arguments ${arg_UNPARSED_ARGUMENTS}")
  endif()
  if(NOT name MATCHES "^[A-Za-z_][A-Za-z0-9_]*$")
    message(FATAL_ERROR "sweepgen_add_python_module(${name}): the module name must be a Python identifier")
  endif()
  if(NOT SWEEPGEN_PYTHON_SEARCHED)
    message(FATAL_ERROR "sweepgen_add_python_module(${name}): call sweepgen_find_python() first (and check "
                        "SWEEPGEN_PYTHON_FOUND)")
  elseif(NOT SWEEPGEN_PYTHON_FOUND)
    message(FATAL_ERROR "sweepgen_add_python_module(${name}): cannot build a Python module: "
                        "${SWEEPGEN_PYTHON_MISSING} not found (sweepgen_find_python() sets SWEEPGEN_PYTHON_FOUND: "
                        "check it before adding modules)")
  endif()
  if(arg_SCENE AND NOT arg_SOLVER)
    set(solver ${name}_solver)
    set(forwarded SCENE "${arg_SCENE}")
    if(arg_OUTPUT_DIR)
      list(APPEND forwarded OUTPUT_DIR "${arg_OUTPUT_DIR}")
    endif()
    if(arg_EXPOSE)
      list(APPEND forwarded EXPOSE ${arg_EXPOSE})
    endif()
    if(arg_CUDA)
      list(APPEND forwarded CUDA)
    endif()
    sweepgen_add_solver(${solver} ${forwarded})
  elseif(arg_SOLVER AND NOT arg_SCENE AND NOT arg_OUTPUT_DIR AND NOT arg_EXPOSE AND NOT arg_CUDA)
    set(solver ${arg_SOLVER})
  else()
    message(FATAL_ERROR "sweepgen_add_python_module(${name}): give SCENE (with optional OUTPUT_DIR, EXPOSE, CUDA) "
                        "or SOLVER (with its CUDA library where <target>_cuda exists)")
  endif()
  # The generated library goes into a shared object: position-independent code.
  set_property(TARGET ${solver} PROPERTY POSITION_INDEPENDENT_CODE ON)

  # sweepgen_add_solver() puts <target>.hpp in the library's include directory;
  # sweepgen_committed_solver() names the generated header it forwards to.
  get_target_property(header ${solver} SWEEPGEN_HEADER)
  if(NOT header)
    get_target_property(solver_include ${solver} INTERFACE_INCLUDE_DIRECTORIES)
    list(GET solver_include 0 solver_include)
    set(header "${solver_include}/${solver}.hpp")
  endif()
  set(scene_dir "${CMAKE_CURRENT_BINARY_DIR}/sweepgen_python/${name}")
  # The binding and its PyTorch layer: installed next to this file (python/), or in the source tree.
  get_filename_component(here "${CMAKE_CURRENT_FUNCTION_LIST_FILE}" DIRECTORY)
  set(python_dir "${here}/python")
  if(NOT EXISTS "${python_dir}/module.cpp")
    set(python_dir "${here}/../python")
  endif()
  set(source "${python_dir}/module.cpp")
  add_custom_command(
    OUTPUT "${scene_dir}/sweepgen_module_scene.hpp"
    COMMAND ${CMAKE_COMMAND} "-DSWEEPGEN_SCENE_HEADER=${header}"
            "-DSWEEPGEN_MODULE_SCENE=${scene_dir}/sweepgen_module_scene.hpp"
            "-DSWEEPGEN_TORCH_LAYER=${python_dir}/torch_layer.py"
            -P "${CMAKE_CURRENT_FUNCTION_LIST_FILE}"
    DEPENDS "${header}" "${CMAKE_CURRENT_FUNCTION_LIST_FILE}" "${python_dir}/torch_layer.py"
    COMMENT "sweepgen: reading the scene of Python module ${name} from ${solver}.hpp"
    VERBATIM)

  # The binding (python/binding.cpp: pybind11's templates, ~10 s of g++) is compiled once per build
  # and linked into every module; a module's own source only describes its scene.
  if(NOT TARGET sweepgen_python_binding)
    add_library(sweepgen_python_binding STATIC "${python_dir}/binding.cpp" "${python_dir}/module_api.hpp")
    target_include_directories(sweepgen_python_binding PUBLIC "${python_dir}")
    target_link_libraries(sweepgen_python_binding PRIVATE pybind11::module)
    set_target_properties(sweepgen_python_binding PROPERTIES POSITION_INDEPENDENT_CODE ON CXX_VISIBILITY_PRESET hidden
                                                             VISIBILITY_INLINES_HIDDEN ON)
    target_compile_features(sweepgen_python_binding PRIVATE cxx_std_17)
    # -O1 where the build optimises: the binding checks arguments and copies rows, and the solver
    # it calls is the generated library, compiled as that library is (bench/README.md, "Python":
    # the same per-call overhead as at -O2).
    target_compile_options(sweepgen_python_binding PRIVATE $<$<CONFIG:Release,RelWithDebInfo,MinSizeRel>:-O1>)
  endif()
  # NO_EXTRAS: without pybind11's link-time optimisation (the generated library is compiled
  # without it; LTO took as long, 6.9 s against 6.5 s per module here, for no measured gain).
  pybind11_add_module(${name} MODULE NO_EXTRAS "${source}" "${scene_dir}/sweepgen_module_scene.hpp")
  target_include_directories(${name} PRIVATE "${scene_dir}")
  target_compile_definitions(${name} PRIVATE SWEEPGEN_MODULE_NAME=${name})
  target_compile_features(${name} PRIVATE cxx_std_17)
  target_link_libraries(${name} PRIVATE sweepgen_python_binding ${solver})

  # The kernels (python/module_cuda.cu), where the solver has its CUDA library: the generated .cu
  # compiled once more, into a shared library whose symbols are hidden but the table it hands the
  # module, so that its host copy of the solver's functions does not meet the module's (the static
  # solver library's, which has the batch entry points nvcc does not compile).
  if(TARGET ${solver}_cuda)
    get_target_property(cuda_source ${solver}_cuda SOURCES)
    list(FILTER cuda_source INCLUDE REGEX "\\.cu$")
    get_target_property(cuda_include ${solver}_cuda INTERFACE_INCLUDE_DIRECTORIES)
    add_library(${name}_cuda SHARED "${python_dir}/module_cuda.cu" "${scene_dir}/sweepgen_module_scene.hpp")
    target_include_directories(${name}_cuda PRIVATE "${scene_dir}" "${python_dir}" ${cuda_include})
    target_compile_definitions(${name}_cuda PRIVATE SWEEPGEN_MODULE_NAME=${name}
                               "SWEEPGEN_MODULE_CUDA_SOURCE=\"${cuda_source}\"")
    target_compile_features(${name}_cuda PRIVATE cxx_std_17 cuda_std_17)
    target_link_libraries(${name}_cuda PRIVATE Python3::Module)
    # cudart_static's symbols hidden too: the process's other CUDA runtimes (PyTorch's) are not overridden.
    target_link_options(${name}_cuda PRIVATE "LINKER:--exclude-libs,ALL")
    set_target_properties(${name}_cuda PROPERTIES CUDA_VISIBILITY_PRESET hidden CXX_VISIBILITY_PRESET hidden)
    target_compile_definitions(${name} PRIVATE SWEEPGEN_MODULE_HAS_CUDA=1)
    target_link_libraries(${name} PRIVATE ${name}_cuda)
  endif()
endfunction()

# Script mode (the custom command above): reads the generated header SWEEPGEN_SCENE_HEADER and
# writes SWEEPGEN_MODULE_SCENE, which python/module.cpp includes. The header's outer namespace is
# the scene's, `namespace f64 {` / `namespace f32 {` the scalars it has, and the comment above
# flat_in_size states the flat layout ("in = [...]", "out = [...]"). The text of SWEEPGEN_TORCH_LAYER
# (python/torch_layer.py, the module's `torch` attribute) goes in as sweepgen_module_torch_layer.
if(CMAKE_SCRIPT_MODE_FILE AND DEFINED SWEEPGEN_SCENE_HEADER)
  cmake_policy(VERSION 3.25)
  file(STRINGS "${SWEEPGEN_SCENE_HEADER}" namespaces REGEX "^namespace [A-Za-z_][A-Za-z0-9_:]* {$")
  if(NOT namespaces)
    message(FATAL_ERROR "${SWEEPGEN_SCENE_HEADER}: no namespace line; not a sweepgen-generated header?")
  endif()
  list(GET namespaces 0 scene_namespace)
  string(REGEX REPLACE "^namespace (.*) {$" "\\1" scene_namespace "${scene_namespace}")
  set(has_f64 0)
  set(has_f32 0)
  if("namespace f64 {" IN_LIST namespaces)
    set(has_f64 1)
  endif()
  if("namespace f32 {" IN_LIST namespaces)
    set(has_f32 1)
  endif()
  file(READ "${SWEEPGEN_SCENE_HEADER}" text)
  set(has_derivatives 0)
  if(text MATCHES "constexpr int derivative_columns = ")
    set(has_derivatives 1)
  endif()
  foreach(part in out)
    set(flat_${part} "see ${SWEEPGEN_SCENE_HEADER}")
    if(text MATCHES "[ (]${part} = \\[([^]]*)\\]")
      string(REGEX REPLACE "[\n/ ]+" " " flat_${part} "${CMAKE_MATCH_1}")
    endif()
  endforeach()
  file(READ "${SWEEPGEN_TORCH_LAYER}" torch_layer)
  string(FIND "${torch_layer}" ")torch_layer\"" clash)
  if(NOT clash EQUAL -1)
    message(FATAL_ERROR "${SWEEPGEN_TORCH_LAYER} contains the raw-string delimiter )torch_layer\"")
  endif()
  file(CONFIGURE OUTPUT "${SWEEPGEN_MODULE_SCENE}" CONTENT [[
// Written by cmake/SweepgenAddPythonModule.cmake from @SWEEPGEN_SCENE_HEADER@.
#pragma once
#include "@SWEEPGEN_SCENE_HEADER@"
#define SWEEPGEN_MODULE_SCENE @scene_namespace@
#define SWEEPGEN_MODULE_HAS_F64 @has_f64@
#define SWEEPGEN_MODULE_HAS_F32 @has_f32@
#define SWEEPGEN_MODULE_HAS_DERIVATIVES @has_derivatives@
#define SWEEPGEN_MODULE_FLAT_IN "@flat_in@"
#define SWEEPGEN_MODULE_FLAT_OUT "@flat_out@"
inline constexpr const char* sweepgen_module_torch_layer = R"torch_layer(@torch_layer@)torch_layer";
]] @ONLY)
endif()
