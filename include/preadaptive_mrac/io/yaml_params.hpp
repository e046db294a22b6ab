#pragma once
/// \file yaml_params.hpp
/// \brief YAML files and `--set` values into the core's ParamValue tree (yaml-cpp).

#include <cstddef>
#include <stdexcept>
#include <string>

#include "preadaptive_mrac/core/schema/params.hpp"

namespace preadaptive_mrac {

/// \brief Thrown for unreadable or malformed files; the message names the file (and line).
class FileError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

/// \brief The most a configuration may ask of the reader, checked before the tree is built
/// (docs/reference/limits.md): bytes of a file or document, values (scalars, lists and maps,
/// each YAML alias counted again where it is used) and levels of nesting.
constexpr std::size_t kMaxYamlBytes = std::size_t{1} << 20;
constexpr std::size_t kMaxYamlNodes = 200000;
constexpr int kMaxYamlDepth = 64;

/// \brief Load a YAML file into a tree. Scalars become bool, int, double (including .nan/.inf,
/// which the readers then reject by name) or string; quoted scalars stay strings. Refused
/// (FileError naming the key): a file or tree beyond the limits above, a key repeated in a map.
ParamValue loadYamlFile(const std::string& path);
/// \brief Parse YAML text (a document) into a tree; `origin` names it in errors.
ParamValue parseYaml(const std::string& text, const std::string& origin);
/// \brief Apply "a.b.c=value" (value in YAML syntax: 0.01, true, [1, 2, 3], pa_learn).
/// Throws FileError when it is not of the form key=value.
void applyOverride(ParamValue* tree, const std::string& assignment);

}  // namespace preadaptive_mrac
