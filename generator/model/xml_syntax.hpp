// A URDF's XML syntax, checked before urdfdom reads it: urdfdom reports a syntax error without
// its place ("Error reading end tag."), which in a 1000-line file leaves the user searching.
// TinyXML, urdfdom's own XML reader, knows the line and column; so it is asked, too, where an
// element is that urdfdom would drop without a word.
#pragma once

#include <string>

#include "model/xml_nesting.hpp"

namespace sweepgen::model {

// Throws InputError("<file>:<line>:<column>", "XML", reason) when `text` is not well-formed XML
// (an element left open: "<name>" where it opened, from `outline`, the text's xml_outline, which
// the caller has already scanned), and InputError("<file>:<line>:<column>", "joint 'name'",
// reason) at a joint's second <mimic>, which urdfdom drops without a word.
void check_xml_syntax(const std::string& text, const std::string& file, const XmlOutline& outline);

}  // namespace sweepgen::model
