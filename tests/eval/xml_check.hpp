// A small XML well-formedness check for the tests (no XML library is a dependency of contactnn): one
// optional <?xml ...?> declaration, then exactly one root element; elements nest properly, names are XML
// names, attributes are quoted and unique per element, text and attribute values contain no raw '<' and only
// the five predefined entities or character references after '&'; comments are allowed. No DTDs, no CDATA.
#pragma once

#include <cctype>
#include <set>
#include <string>
#include <string_view>
#include <vector>

namespace contactnn::testing {

/// "" when `text` is well-formed in the sense above, otherwise a message with the byte offset.
inline std::string xml_well_formedness_error(std::string_view text) {
  std::size_t i = 0;
  const auto fail = [&](const std::string& why) { return "offset " + std::to_string(i) + ": " + why; };
  const auto is_name_start = [](char c) {
    return std::isalpha(static_cast<unsigned char>(c)) || c == '_' || c == ':';
  };
  const auto is_name_char = [&](char c) {
    return is_name_start(c) || std::isdigit(static_cast<unsigned char>(c)) || c == '-' || c == '.';
  };
  const auto skip_space = [&]() {
    while (i < text.size() && std::isspace(static_cast<unsigned char>(text[i]))) ++i;
  };
  const auto read_name = [&]() -> std::string {
    const std::size_t start = i;
    if (i >= text.size() || !is_name_start(text[i])) return "";
    while (i < text.size() && is_name_char(text[i])) ++i;
    return std::string(text.substr(start, i - start));
  };
  // Checks the entity at text[i] == '&'; advances past ';'.
  const auto read_entity = [&]() -> bool {
    const std::size_t semicolon = text.find(';', i);
    if (semicolon == std::string_view::npos) return false;
    const std::string_view entity = text.substr(i + 1, semicolon - i - 1);
    static const std::set<std::string_view> kNamed = {"amp", "lt", "gt", "quot", "apos"};
    bool ok = kNamed.count(entity) > 0;
    if (!ok && entity.size() >= 2 && entity[0] == '#') {
      ok = true;
      const bool hex = entity[1] == 'x';
      for (std::size_t k = hex ? 2 : 1; k < entity.size(); ++k) {
        ok = ok && (hex ? std::isxdigit(static_cast<unsigned char>(entity[k]))
                        : std::isdigit(static_cast<unsigned char>(entity[k])));
      }
      ok = ok && entity.size() > (hex ? 2u : 1u);
    }
    i = semicolon + 1;
    return ok;
  };

  skip_space();
  if (text.substr(i, 5) == "<?xml") {
    const std::size_t end = text.find("?>", i);
    if (end == std::string_view::npos) return fail("unterminated XML declaration");
    i = end + 2;
  }
  std::vector<std::string> open;
  bool root_seen = false;
  while (i < text.size()) {
    if (text[i] != '<') {
      if (open.empty()) {
        if (!std::isspace(static_cast<unsigned char>(text[i]))) return fail("text outside the root element");
        ++i;
        continue;
      }
      if (text[i] == '&') {
        if (!read_entity()) return fail("bad entity in text");
        continue;
      }
      if (text[i] == '>') return fail("raw '>' is allowed but suspicious here");
      ++i;
      continue;
    }
    if (text.substr(i, 4) == "<!--") {
      const std::size_t end = text.find("-->", i + 4);
      if (end == std::string_view::npos) return fail("unterminated comment");
      i = end + 3;
      continue;
    }
    if (text.substr(i, 2) == "</") {
      i += 2;
      const std::string name = read_name();
      skip_space();
      if (i >= text.size() || text[i] != '>') return fail("bad end tag");
      ++i;
      if (open.empty() || open.back() != name) {
        return fail("end tag </" + name + "> does not match <" +
                    (open.empty() ? std::string() : open.back()) + ">");
      }
      open.pop_back();
      continue;
    }
    ++i;  // '<'
    if (open.empty() && root_seen) return fail("a second root element");
    const std::string name = read_name();
    if (name.empty()) return fail("bad element name");
    std::set<std::string> attributes;
    while (true) {
      const std::size_t before = i;
      skip_space();
      if (i >= text.size()) return fail("unterminated start tag <" + name + ">");
      if (text[i] == '>' || text.substr(i, 2) == "/>") break;
      if (i == before) return fail("attributes must be separated by white space");
      const std::string attribute = read_name();
      if (attribute.empty()) return fail("bad attribute name in <" + name + ">");
      if (!attributes.insert(attribute).second) return fail("duplicate attribute " + attribute);
      skip_space();
      if (i >= text.size() || text[i] != '=') return fail("attribute " + attribute + " has no '='");
      ++i;
      skip_space();
      if (i >= text.size() || (text[i] != '"' && text[i] != '\''))
        return fail("attribute " + attribute + " is not quoted");
      const char quote = text[i++];
      while (i < text.size() && text[i] != quote) {
        if (text[i] == '<') return fail("raw '<' in attribute " + attribute);
        if (text[i] == '&') {
          if (!read_entity()) return fail("bad entity in attribute " + attribute);
          continue;
        }
        ++i;
      }
      if (i >= text.size()) return fail("unterminated attribute " + attribute);
      ++i;
    }
    root_seen = true;
    if (text[i] == '/') {
      i += 2;  // "/>"
    } else {
      ++i;
      open.push_back(name);
    }
  }
  if (!open.empty()) return fail("unclosed element <" + open.back() + ">");
  if (!root_seen) return fail("no root element");
  return "";
}

}  // namespace contactnn::testing
