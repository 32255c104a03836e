// A scene's collections, counted from the YAML reader's events before any node is built: yaml-cpp
// spends some 600 bytes a node, so an 8 MiB file of `gravity: [0,0,0,...]` would take gigabytes
// and half a minute before the reader could say that gravity takes 3 numbers.
#pragma once

#include <string>

namespace sweepgen::scene {

// Throws InputError("file:line:column", element, reason) for a sequence or mapping of more than
// kMaxYamlItems entries, or a document of more than kMaxYamlNodes nodes (model/input_limits.hpp),
// naming the collection where the limit is passed; and for what YAML::Load would refuse on the
// way (syntax, nesting deeper than kMaxYamlDepth), as YAML::Load's own exceptions.
void check_yaml_outline(const std::string& text, const std::string& file);

}  // namespace sweepgen::scene
