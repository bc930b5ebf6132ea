// Recursive-descent XML subset reader (no entities beyond the five predefined ones,
// no DTDs): enough for MJCF files.
#include "xml.h"

#include <cctype>

#include "pliant/core/error.h"

namespace pliant::articulated {

const std::string* XmlElement::attr(const std::string& key) const {
  for (const auto& [k, v] : attrs)
    if (k == key) return &v;
  return nullptr;
}

namespace {

struct Parser {
  const std::string& s;
  const std::string& file;
  size_t i = 0;
  int line = 1;

  [[noreturn]] void fail(const std::string& what) const {
    throw InputError(file, "", "XML line " + std::to_string(line) + ": " + what);
  }
  bool at_end() const { return i >= s.size(); }
  char peek() const { return at_end() ? '\0' : s[i]; }
  void advance() {
    if (s[i] == '\n') ++line;
    ++i;
  }
  bool starts(const char* t) const { return s.compare(i, std::char_traits<char>::length(t), t) == 0; }
  void skip_space() {
    while (!at_end() && std::isspace(static_cast<unsigned char>(s[i]))) advance();
  }
  void skip_until(const char* end) {
    while (!at_end() && !starts(end)) advance();
    if (at_end()) fail(std::string("missing \"") + end + "\"");
    for (size_t n = std::char_traits<char>::length(end); n > 0; --n) advance();
  }
  // Skips text, comments and declarations; stops at '<' of an element or end tag.
  void skip_misc() {
    for (;;) {
      while (!at_end() && s[i] != '<') advance();
      if (at_end()) return;
      if (starts("<!--")) skip_until("-->");
      else if (starts("<?")) skip_until("?>");
      else if (starts("<!")) skip_until(">");
      else return;
    }
  }
  std::string name() {
    const size_t b = i;
    while (!at_end() && (std::isalnum(static_cast<unsigned char>(s[i])) || s[i] == '_' || s[i] == '-' ||
                         s[i] == ':' || s[i] == '.'))
      advance();
    if (i == b) fail("expected a name");
    return s.substr(b, i - b);
  }
  std::string unescape(const std::string& v) {
    std::string out;
    for (size_t k = 0; k < v.size(); ++k) {
      if (v[k] != '&') {
        out += v[k];
        continue;
      }
      static const std::pair<const char*, char> ents[] = {
          {"&lt;", '<'}, {"&gt;", '>'}, {"&amp;", '&'}, {"&quot;", '"'}, {"&apos;", '\''}};
      bool ok = false;
      for (const auto& [e, c] : ents)
        if (v.compare(k, std::char_traits<char>::length(e), e) == 0) {
          out += c;
          k += std::char_traits<char>::length(e) - 1;
          ok = true;
          break;
        }
      if (!ok) fail("unsupported entity in attribute value");
    }
    return out;
  }
  XmlElement element() {
    XmlElement e;
    e.line = line;
    advance();  // '<'
    e.name = name();
    for (;;) {
      skip_space();
      if (at_end()) fail("unterminated element <" + e.name + ">");
      if (starts("/>")) {
        advance();
        advance();
        return e;
      }
      if (peek() == '>') {
        advance();
        break;
      }
      const std::string key = name();
      skip_space();
      if (peek() != '=') fail("attribute \"" + key + "\" of <" + e.name + "> has no value");
      advance();
      skip_space();
      const char q = peek();
      if (q != '"' && q != '\'') fail("attribute \"" + key + "\" of <" + e.name + "> is not quoted");
      advance();
      const size_t b = i;
      while (!at_end() && s[i] != q) advance();
      if (at_end()) fail("unterminated attribute \"" + key + "\"");
      std::string v = unescape(s.substr(b, i - b));
      advance();
      if (e.attr(key)) fail("attribute \"" + key + "\" repeated in <" + e.name + ">");
      e.attrs.emplace_back(key, std::move(v));
    }
    for (;;) {
      skip_misc();
      if (at_end()) fail("element <" + e.name + "> is not closed");
      if (starts("</")) {
        advance();
        advance();
        const std::string n = name();
        if (n != e.name) fail("closing </" + n + "> does not match <" + e.name + ">");
        skip_space();
        if (peek() != '>') fail("expected '>'");
        advance();
        return e;
      }
      e.children.push_back(element());
    }
  }
};

}  // namespace

XmlElement parse_xml(const std::string& text, const std::string& file) {
  Parser p{text, file};
  p.skip_misc();
  if (p.at_end()) p.fail("no root element");
  XmlElement root = p.element();
  p.skip_misc();
  if (!p.at_end()) p.fail("content after the root element");
  return root;
}

}  // namespace pliant::articulated
