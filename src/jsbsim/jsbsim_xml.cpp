#include "preadaptive_mrac/jsbsim/jsbsim_xml.hpp"

#include <algorithm>
#include <cctype>

namespace preadaptive_mrac {

namespace {

std::string trimmed(const std::string& s) {
  const size_t a = s.find_first_not_of(" \t\r\n");
  if (a == std::string::npos) return {};
  return s.substr(a, s.find_last_not_of(" \t\r\n") - a + 1);
}

bool isNameChar(char c) {
  return std::isalnum(static_cast<unsigned char>(c)) || c == '_' || c == '-' || c == '.' ||
         c == ':';
}

class Parser {
 public:
  explicit Parser(const std::string& t) : t_(t) {}

  std::unique_ptr<XmlElement> document() {
    skipMisc();
    if (pos_ >= t_.size() || t_[pos_] != '<') fail("no root element");
    auto root = element();
    skipMisc();
    if (pos_ < t_.size()) fail("text after the root element");
    return root;
  }

 private:
  [[noreturn]] void fail(const std::string& what) const {
    size_t line = 1 + static_cast<size_t>(
                          std::count(t_.begin(), t_.begin() + std::min(pos_, t_.size()), '\n'));
    throw XmlError("not well-formed XML at line " + std::to_string(line) + ": " + what);
  }

  bool at(const char* s) const {
    return t_.compare(pos_, std::char_traits<char>::length(s), s) == 0;
  }

  void skipTo(const char* end) {
    const size_t e = t_.find(end, pos_);
    if (e == std::string::npos) fail(std::string("no closing '") + end + "'");
    pos_ = e + std::char_traits<char>::length(end);
  }

  /// Whitespace, comments, declarations and processing instructions.
  void skipMisc() {
    for (;;) {
      while (pos_ < t_.size() && std::isspace(static_cast<unsigned char>(t_[pos_]))) ++pos_;
      if (at("<!--")) {
        skipTo("-->");
      } else if (at("<?")) {
        skipTo("?>");
      } else if (at("<!")) {
        skipTo(">");
      } else {
        return;
      }
    }
  }

  std::string name() {
    const size_t b = pos_;
    while (pos_ < t_.size() && isNameChar(t_[pos_])) ++pos_;
    if (pos_ == b) fail("expected a name");
    return t_.substr(b, pos_ - b);
  }

  void spaces() {
    while (pos_ < t_.size() && std::isspace(static_cast<unsigned char>(t_[pos_]))) ++pos_;
  }

  std::unique_ptr<XmlElement> element() {
    auto e = std::make_unique<XmlElement>();
    e->open_begin = pos_;
    ++pos_;  // '<'
    e->name = name();
    for (;;) {
      spaces();
      if (pos_ >= t_.size()) fail("unterminated tag <" + e->name + ">");
      if (at("/>")) {
        pos_ += 2;
        e->open_end = e->close_begin = e->close_end = pos_;
        return e;
      }
      if (t_[pos_] == '>') {
        ++pos_;
        break;
      }
      const std::string key = name();
      spaces();
      if (pos_ >= t_.size() || t_[pos_] != '=') fail("expected '=' after " + key);
      ++pos_;
      spaces();
      if (pos_ >= t_.size() || (t_[pos_] != '"' && t_[pos_] != '\'')) fail("expected a quote");
      const char q = t_[pos_++];
      const size_t end = t_.find(q, pos_);
      if (end == std::string::npos) fail("unterminated attribute " + key);
      e->attributes[key] = t_.substr(pos_, end - pos_);
      pos_ = end + 1;
    }
    e->open_end = pos_;
    std::string text;
    for (;;) {
      if (pos_ >= t_.size()) fail("no closing tag for <" + e->name + ">");
      if (at("</")) {
        e->close_begin = pos_;
        pos_ += 2;
        if (name() != e->name) fail("closing tag does not match <" + e->name + ">");
        spaces();
        if (pos_ >= t_.size() || t_[pos_] != '>') fail("unterminated closing tag");
        e->close_end = ++pos_;
        e->text = trimmed(text);
        return e;
      }
      if (at("<!--")) {
        skipTo("-->");
      } else if (at("<![CDATA[")) {
        const size_t b = pos_ + 9;
        skipTo("]]>");
        text += t_.substr(b, pos_ - 3 - b);
      } else if (at("<?")) {
        skipTo("?>");
      } else if (t_[pos_] == '<') {
        e->children.push_back(element());
      } else {
        const size_t next = t_.find('<', pos_);
        const size_t end = next == std::string::npos ? t_.size() : next;
        text += t_.substr(pos_, end - pos_);
        pos_ = end;
      }
    }
  }

  const std::string& t_;
  size_t pos_ = 0;
};

}  // namespace

const XmlElement* XmlElement::child(const std::string& n) const {
  for (const auto& c : children)
    if (c->name == n) return c.get();
  return nullptr;
}

std::vector<const XmlElement*> XmlElement::childrenNamed(const std::string& n) const {
  std::vector<const XmlElement*> out;
  for (const auto& c : children)
    if (c->name == n) out.push_back(c.get());
  return out;
}

std::string XmlElement::attribute(const std::string& key, const std::string& fallback) const {
  const auto it = attributes.find(key);
  return it == attributes.end() ? fallback : it->second;
}

std::unique_ptr<XmlElement> parseXml(const std::string& text) { return Parser(text).document(); }

void TextEdits::replace(size_t offset, size_t length, std::string what) {
  edits_.push_back({offset, length, edits_.size(), std::move(what)});
}

std::string TextEdits::apply(const std::string& original) const {
  std::vector<const Edit*> order;
  for (const auto& e : edits_) order.push_back(&e);
  // From the end backwards, so earlier offsets stay valid; at one offset the later edit first,
  // so the earlier one ends up in front of it.
  std::sort(order.begin(), order.end(), [](const Edit* a, const Edit* b) {
    return a->offset != b->offset ? a->offset > b->offset : a->order > b->order;
  });
  std::string out = original;
  for (const Edit* e : order) out.replace(e->offset, e->length, e->what);
  return out;
}

}  // namespace preadaptive_mrac
