// A minimal XML reader for MJCF: elements, attributes, comments, declarations;
// text content is ignored. Errors are InputError with the line number.
#pragma once
#include <string>
#include <utility>
#include <vector>

namespace pliant::articulated {

struct XmlElement {
  std::string name;
  std::vector<std::pair<std::string, std::string>> attrs;
  std::vector<XmlElement> children;
  int line = 0;
  const std::string* attr(const std::string& key) const;
};

XmlElement parse_xml(const std::string& text, const std::string& file);

}  // namespace pliant::articulated
