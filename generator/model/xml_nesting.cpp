#include "model/xml_nesting.hpp"

#include <algorithm>
#include <vector>

#include "model/input_limits.hpp"

namespace sweepgen::model {

XmlOutline xml_outline(std::string_view text) {
  text = text.substr(0, std::min(text.size(), text.find('\0')));
  XmlOutline outline;
  std::size_t depth = 0, line = 1, i = 0;
  // Moves i past the first `end` at or after `from` (or to the end), counting lines.
  const auto skip_past = [&](std::size_t from, std::string_view end) {
    const std::size_t found = text.find(end, from);
    const std::size_t stop = found == std::string_view::npos ? text.size() : found + end.size();
    line += static_cast<std::size_t>(std::count(text.begin() + static_cast<std::ptrdiff_t>(i),
                                                text.begin() + static_cast<std::ptrdiff_t>(stop), '\n'));
    i = stop;
  };
  const auto starts = [&](std::string_view prefix) { return text.compare(i, prefix.size(), prefix) == 0; };
  const auto column_of = [&text](std::size_t at) { return at - (at == 0 ? 0 : text.rfind('\n', at - 1) + 1) + 1; };  // npos + 1 is 0
  // The elements open, innermost last (as far as a URDF may nest: deeper files are refused anyway).
  struct Open {
    std::string_view name;
    std::size_t line, column;
  };
  std::vector<Open> open;
  const auto leave_open = [&outline](const Open& element) {
    outline.unclosed = element.name;
    outline.unclosed_line = element.line;
    outline.unclosed_column = element.column;
  };
  const auto name_start = [](unsigned char c) {
    return (c >= 'a' && c <= 'z') || (c >= 'A' && c <= 'Z') || c == '_' || c == ':' || c >= 0x7f;  // TinyXML: >= 127
  };
  while (i < text.size()) {
    const char c = text[i];
    if (c == '\n') ++line;
    if (c != '<') {
      ++i;
      continue;
    }
    if (starts("<!--")) {
      skip_past(i + 4, "-->");
    } else if (starts("<![CDATA[")) {
      skip_past(i + 9, "]]>");
    } else if (starts("<?")) {
      skip_past(i + 2, "?>");
    } else if (starts("<!")) {
      if (outline.declaration_line == 0) {
        outline.declaration_line = line;
        outline.declaration_column = column_of(i);
      }
      skip_past(i + 2, ">");
    } else if (starts("</")) {
      depth -= depth > 0 ? 1 : 0;
      std::size_t name_end = i + 2;
      while (name_end < text.size() && text[name_end] != '>' && static_cast<unsigned char>(text[name_end]) > ' ') ++name_end;
      const std::string_view name = text.substr(i + 2, name_end - i - 2);
      if (!open.empty() && open.back().name != name && outline.unclosed_line == 0) {
        leave_open(open.back());
        outline.closed_instead = name;
        outline.closed_instead_line = line;
        outline.closed_instead_column = column_of(i);
      }
      if (!open.empty()) open.pop_back();
      skip_past(i + 2, ">");
    } else if (i + 1 < text.size() && name_start(static_cast<unsigned char>(text[i + 1]))) {
      ++depth;
      if (depth > outline.depth) {
        outline.depth = depth;
        outline.deepest_line = line;
      }
      const std::size_t opened_line = line;
      std::size_t end = i + 1;
      while (end < text.size() && text[end] != '>' && text[end] != '/' && static_cast<unsigned char>(text[end]) > ' ') ++end;
      const std::string_view name = text.substr(i + 1, end - i - 1);
      if (++outline.elements > kMaxXmlElements) {
        outline.element_past_limit = name;
        outline.element_past_limit_line = line;
        break;
      }
      if (depth == 2) {
        outline.links += name == "link" ? 1 : 0;
        outline.joints += name == "joint" ? 1 : 0;
      }
      // The attributes, to the tag's end: a '>' or "/>" inside a quoted value does not end it. A
      // value is quoted where its first character, after '=' and white space, is a quote (as the
      // parser reads it): a quote inside a word opens nothing.
      char quote = 0;
      bool value_next = false;
      for (; end < text.size(); ++end) {
        const char d = text[end];
        if (d == '\n') ++line;
        if (quote) {
          if (d == quote) quote = 0;
        } else if (d == '=') {
          value_next = true;
        } else if (value_next && (d == '"' || d == '\'')) {
          quote = d;
          value_next = false;
        } else if (d == '>') {
          break;
        } else if (static_cast<unsigned char>(d) > ' ') {
          value_next = false;
        }
      }
      const bool empty = end < text.size() && end > i && text[end - 1] == '/' && !quote;
      if (empty)
        --depth;
      else if (open.size() <= kMaxXmlDepth)
        open.push_back({name, opened_line, column_of(i)});
      i = end + 1;
    } else {
      ++i;
    }
  }
  if (!open.empty() && outline.unclosed_line == 0) leave_open(open.back());
  return outline;
}

}  // namespace sweepgen::model
