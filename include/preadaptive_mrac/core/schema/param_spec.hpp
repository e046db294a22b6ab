#pragma once
/// \file param_spec.hpp
/// \brief What a parameter table row says to the C++ (params/*.yaml): the generated
/// headers (preadaptive_mrac/params/*_params.hpp) describe each scalar with a ParamSpec, and
/// param_table.hpp reads and checks any generated struct with them.

namespace preadaptive_mrac {

/// \brief A row's `presence`: required, optional (absent keeps the default, noted), required
/// inside an optional section (read only when the section is there), or optional without the
/// note (a key added later: a run without it reports exactly what it reported before it).
enum class ParamPresence { kRequired, kOptional, kInSection, kOptionalUnnoted };

/// \brief A row's `check`: the range the validation accepts (bounds open or closed).
struct ParamCheck {
  bool has_lo = false;
  double lo = 0.0;
  bool lo_open = false;
  bool has_hi = false;
  double hi = 0.0;
  bool hi_open = false;

  bool any() const { return has_lo || has_hi; }
  bool holds(double v) const {
    return (!has_lo || (lo_open ? v > lo : v >= lo)) && (!has_hi || (hi_open ? v < hi : v <= hi));
  }
};

/// \brief One scalar row: its key below the table's prefix, presence, check, and for a row
/// inside an optional section that section's key ("" otherwise).
struct ParamSpec {
  const char* key;
  ParamPresence presence;
  ParamCheck check;
  const char* section;
};

}  // namespace preadaptive_mrac
