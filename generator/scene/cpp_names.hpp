// The names a scene gives the generated C++: the solver's namespace and the driver instances'
// names become identifiers of the generated code, so each is checked here, once for the scene
// file and the command line alike (`--solver`).
#pragma once

#include <cstddef>
#include <string>

namespace sweepgen::scene {

// The longest solver namespace, "::" included: the generated files are named after it
// (emit::file_stem, as long as the namespace), and a file name may hold 255 bytes with
// ".cmake". Also bounds the nesting (at most 67 parts).
constexpr std::size_t kMaxSolverNamespaceBytes = 200;

// Why `name` cannot be an identifier of the generated code, or "" (the reason reads after "it"):
// not an identifier, a C++ keyword, reserved in C++ (`__`, or `_` and an upper-case letter
// first), or a macro of the C library's headers or of the compiler (the preprocessor would
// replace it: NAN, M_PI, linux).
std::string identifier_problem(const std::string& name);

// Whether `name` can be an identifier of the generated code (identifier_problem).
bool is_identifier(const std::string& name);

// Why `qualified`, one identifier or several joined by "::", cannot name the generated solver's
// namespace, or "": a part is not an identifier, a part is `std`, or it is longer than
// kMaxSolverNamespaceBytes. The reason is a whole sentence that quotes `qualified`.
std::string solver_namespace_problem(const std::string& qualified);

// Why `name` cannot name a driver instance, a member of the generated Drivers, or "": not an
// identifier, or a name the generated code declares where the Drivers' members are
// (reserved_driver_names). A whole sentence that quotes `name`.
std::string driver_name_problem(const std::string& name);

// The names no driver instance may take, listed for messages and docs/scene.md.
const std::string& reserved_driver_names();

}  // namespace sweepgen::scene
