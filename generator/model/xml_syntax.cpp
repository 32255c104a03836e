#include "model/xml_syntax.hpp"

#include <tinyxml.h>

#include "model/error.hpp"

namespace sweepgen::model {

void check_xml_syntax(const std::string& text, const std::string& file) {
  TiXmlDocument document;
  document.SetTabSize(1);  // columns count characters, a tab as one, as the scene's positions do
  document.Parse(text.c_str());
  if (!document.Error()) return;
  const std::string place = document.ErrorRow() > 0 ? ":" + std::to_string(document.ErrorRow()) + ":" +
                                                          std::to_string(document.ErrorCol())
                                                    : "";
  throw InputError(file + place, "XML", std::string("not well-formed: ") + document.ErrorDesc());
}

}  // namespace sweepgen::model
