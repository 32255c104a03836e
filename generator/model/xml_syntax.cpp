#include "model/xml_syntax.hpp"

#include <tinyxml.h>

#include "model/error.hpp"

namespace sweepgen::model {
namespace {

std::string row_and_column(const TiXmlBase& node) {
  return ":" + std::to_string(node.Row()) + ":" + std::to_string(node.Column());
}

// urdfdom reads a joint's first <mimic> and drops any further one without a word.
void refuse_second_mimic(const TiXmlDocument& document, const std::string& file) {
  const TiXmlElement* robot = document.FirstChildElement("robot");
  if (!robot) return;  // urdfdom says so
  for (const TiXmlElement* joint = robot->FirstChildElement("joint"); joint; joint = joint->NextSiblingElement("joint")) {
    const TiXmlElement* first = joint->FirstChildElement("mimic");
    if (const TiXmlElement* second = first ? first->NextSiblingElement("mimic") : nullptr) {
      const char* name = joint->Attribute("name");
      throw InputError(file + row_and_column(*second), "joint " + quote_name(name ? name : ""),
                       "a second <mimic> (the first at line " + std::to_string(first->Row()) +
                           "); a joint follows one other joint");
    }
  }
}

// An element's tag as a message's element: `<link>`, or the name quoted (quote_name) where it
// holds a ':' (a namespace prefix, which XML allows) or anything inert_text would escape, so the
// element still ends at the first ": " (model/error.hpp).
std::string tag_element(std::string_view name) {
  const std::string shown = inert_text(name);
  return "<" + (shown.find(':') == std::string::npos ? shown : quote_name(name)) + ">";
}

}  // namespace

void check_xml_syntax(const std::string& text, const std::string& file, const XmlOutline& outline) {
  TiXmlDocument document;
  document.SetTabSize(1);  // columns count characters, a tab as one, as the scene's positions do
  document.Parse(text.c_str());
  if (!document.Error()) {
    refuse_second_mimic(document, file);
    return;
  }
  // A missing end tag is TinyXML's error only where another end tag, or the text's end, comes:
  // the element left open is said where it opened.
  if (document.ErrorId() == TiXmlBase::TIXML_ERROR_READING_END_TAG && outline.unclosed_line != 0) {
    const std::string instead = outline.closed_instead_line == 0
                                    ? "the text ends first"
                                    : "</" + inert_text(outline.closed_instead) + "> at " +
                                          std::to_string(outline.closed_instead_line) + ":" +
                                          std::to_string(outline.closed_instead_column) + " comes first";
    throw InputError(file + ":" + std::to_string(outline.unclosed_line) + ":" + std::to_string(outline.unclosed_column),
                     tag_element(outline.unclosed), "not well-formed: this element has no end tag (" + instead + ")");
  }
  const std::string place = document.ErrorRow() > 0 ? ":" + std::to_string(document.ErrorRow()) + ":" +
                                                          std::to_string(document.ErrorCol())
                                                    : "";
  throw InputError(file + place, "XML", std::string("not well-formed: ") + document.ErrorDesc());
}

}  // namespace sweepgen::model
