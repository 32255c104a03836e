// The file skeletons of templates/, embedded at build time (cmake/embed_files.cmake),
// rendered with kainjow's logic-less mustache.
#pragma once

#include <map>
#include <string>

namespace sweepgen::emit {

// Template file name (e.g. "solver.hpp.mustache") -> text.
const std::map<std::string, std::string>& embedded_templates();

}  // namespace sweepgen::emit
