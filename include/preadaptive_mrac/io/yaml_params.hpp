#pragma once
/// \file yaml_params.hpp
/// \brief YAML files and `--set` values into the core's ParamValue tree (yaml-cpp).

#include <stdexcept>
#include <string>

#include "preadaptive_mrac/core/schema/params.hpp"

namespace preadaptive_mrac {

/// \brief Thrown for unreadable or malformed files; the message names the file (and line).
class FileError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

/// \brief Load a YAML file into a tree. Scalars become bool, int, double (including .nan/.inf,
/// which the readers then reject by name) or string; quoted scalars stay strings.
ParamValue loadYamlFile(const std::string& path);
/// \brief Parse YAML text (a document) into a tree; `origin` names it in errors.
ParamValue parseYaml(const std::string& text, const std::string& origin);
/// \brief Apply "a.b.c=value" (value in YAML syntax: 0.01, true, [1, 2, 3], pa_learn).
/// Throws FileError when it is not of the form key=value.
void applyOverride(ParamValue* tree, const std::string& assignment);

}  // namespace preadaptive_mrac
