#pragma once
/// \file jsbsim_xml.hpp
/// \brief A small XML reader for JSBSim's aircraft files (STL only): elements with their
/// attributes, text and byte offsets in the source, so a file can be read and then edited by
/// inserting or replacing text at those offsets, leaving every other byte as it was.

#include <map>
#include <memory>
#include <stdexcept>
#include <string>
#include <vector>

namespace preadaptive_mrac {

/// \brief A text that is not the XML this reader understands (the message says where).
class XmlError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

/// \brief One element of a parsed document.
struct XmlElement {
  std::string name;
  std::map<std::string, std::string> attributes;
  std::string text;  ///< the element's own character data (children's not included), trimmed
  std::vector<std::unique_ptr<XmlElement>> children;
  size_t open_begin = 0;   ///< offset of '<' of the opening tag
  size_t open_end = 0;     ///< offset just after the opening tag's '>'
  size_t close_begin = 0;  ///< offset of "</" of the closing tag (= open_end when self-closed)
  size_t close_end = 0;    ///< offset just after the closing tag

  /// \brief The first child named `name`, or nullptr.
  const XmlElement* child(const std::string& name) const;
  /// \brief Every child named `name`, in document order.
  std::vector<const XmlElement*> childrenNamed(const std::string& name) const;
  /// \brief The attribute's value, or `fallback`.
  std::string attribute(const std::string& key, const std::string& fallback = "") const;
};

/// \brief Parse `text` (comments, the XML declaration and processing instructions skipped;
/// entities kept as written). Throws XmlError naming the offset of what it cannot read.
std::unique_ptr<XmlElement> parseXml(const std::string& text);

/// \brief Edits of a text at offsets of its original, applied all at once (later offsets first).
class TextEdits {
 public:
  /// \brief Insert `what` at `offset`; insertions at one offset keep their order.
  void insert(size_t offset, std::string what) { replace(offset, 0, std::move(what)); }
  /// \brief Replace `length` bytes from `offset` by `what`.
  void replace(size_t offset, size_t length, std::string what);
  /// \brief `original` with every edit applied.
  std::string apply(const std::string& original) const;
  bool empty() const { return edits_.empty(); }

 private:
  struct Edit {
    size_t offset, length, order;
    std::string what;
  };
  std::vector<Edit> edits_;
};

}  // namespace preadaptive_mrac
