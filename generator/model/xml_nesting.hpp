// A URDF's element structure, read without parsing (and without recursion) before urdfdom parses it:
// TinyXML, the reader under urdfdom, recurses once per level of nesting, so a file nested a
// hundred thousand deep overflows the stack, and a file of millions of <link>s fills the memory
// before any check of ours could run (model/input_limits.hpp).
#pragma once

#include <cstddef>
#include <string_view>

namespace sweepgen::model {

struct XmlOutline {
  std::size_t depth = 0;       // the deepest nesting of elements (the root element is 1)
  std::size_t deepest_line = 0;  // the line (from 1) where that depth is first reached
  std::size_t links = 0;       // <link> elements directly inside the root element
  std::size_t joints = 0;      // <joint> elements directly inside the root element
  // The first document type declaration (<!DOCTYPE ...>, or any <!...> but a comment or CDATA):
  // its line and column (from 1; line 0: none).
  std::size_t declaration_line = 0, declaration_column = 0;
  // Elements at any depth, counted to one past kMaxXmlElements, where the scan stops: the element
  // that passes the limit (the name as written) and its line, where one does.
  std::size_t elements = 0;
  std::string_view element_past_limit;
  std::size_t element_past_limit_line = 0;
  // The first element left open: the innermost one open where an end tag names another, or where
  // the text ends (a missing end tag, which the parser reports only there): its name, line and
  // column (line 0: none), and the end tag that came first (its line 0: the text's end).
  std::string_view unclosed;
  std::size_t unclosed_line = 0, unclosed_column = 0;
  std::string_view closed_instead;
  std::size_t closed_instead_line = 0, closed_instead_column = 0;
};

// Scans elements as TinyXML does: comments, CDATA, declarations and <!...> skipped, quoted
// attribute values stepped over, `<name ... />` empty; the text ends at its first NUL (where
// the parser stops). Never below what the parser nests: a malformed file may count deeper.
// The text's characters up to the element past kMaxXmlElements, none after.
XmlOutline xml_outline(std::string_view text);

}  // namespace sweepgen::model
