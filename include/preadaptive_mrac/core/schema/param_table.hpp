#pragma once
/// \file param_table.hpp
/// \brief The generic reader of a generated parameter struct (params/*.yaml through
/// params_codegen.py): every scalar the table declares, read with its presence and checked
/// against its range, each problem naming its key. What no table row can say (a value checked
/// against another, a matrix's shape) stays in the component's own validate().

#include <cstdint>
#include <string>
#include <type_traits>

#include "preadaptive_mrac/core/schema/param_spec.hpp"
#include "preadaptive_mrac/core/schema/params.hpp"

namespace preadaptive_mrac {

/// \brief Read one scalar: required keys must be there; optional ones keep `*v` (the
/// declared default) and are noted.
void readScalar(ParamReader& r, const std::string& key, const ParamSpec& s, double* v);
void readScalar(ParamReader& r, const std::string& key, const ParamSpec& s, int* v);
/// \brief A seed: any int64 >= 0 is taken whole (not cut to 32 bits); a negative one is a
/// problem naming `key`.
void readScalar(ParamReader& r, const std::string& key, const ParamSpec& s, std::uint64_t* v);
void readScalar(ParamReader& r, const std::string& key, const ParamSpec& s, bool* v);
void readScalar(ParamReader& r, const std::string& key, const ParamSpec& s, std::string* v);
/// \brief A row with `choices`: the name read as a string, then parsed by the table's
/// generated parseChoice (found by argument-dependent lookup beside the enum); a name that is
/// none of them is a problem listing them all.
template <class E, std::enable_if_t<std::is_enum<E>::value, int> = 0>
void readScalar(ParamReader& r, const std::string& key, const ParamSpec& s, E* v) {
  const std::string name =
      s.presence == ParamPresence::kOptional ? r.getString(key, choiceName(*v)) : r.getString(key);
  if (r.usable(key) && !parseChoice(name, v))
    r.fail(key, std::string("expected one of ") + choiceNames(*v) + ", got '" + name + "'");
}
/// \brief A problem naming `key` when the value given there lies outside the row's check.
void checkScalar(ParamReader& r, const std::string& key, const ParamCheck& c, double v);

/// \brief `prefix.key`, or `key` alone for a table without a prefix (a node's private keys).
inline std::string joinKey(const std::string& prefix, const char* key) {
  return prefix.empty() ? std::string(key) : prefix + "." + key;
}

/// \brief Every scalar row of P's table below `prefix` ("" for a node's own keys); a row inside an
/// optional section only when the section is there. Sections left out are noted with their
/// absent_note.
template <class P>
void readScalars(ParamReader& r, const std::string& prefix, P* p) {
  P::forEachSection([&](const char* key, const char* note) {
    if (!r.has(joinKey(prefix, key))) r.noteDefault(joinKey(prefix, key), note);
  });
  P::forEachScalar(*p, [&](const ParamSpec& s, auto& v) {
    if (s.presence == ParamPresence::kInSection && !r.has(joinKey(prefix, s.section))) return;
    // (absent: the default, not noted; present: read as a required key)
    if (s.presence == ParamPresence::kOptionalUnnoted && !r.has(joinKey(prefix, s.key))) return;
    readScalar(r, joinKey(prefix, s.key), s, &v);
  });
}

/// \brief A part's optional section (a table with its own absent_note: pa_robust's, the L1
/// law's): left out, every default and one note; given, each key read as readScalars does.
template <class P>
void readSection(ParamReader& r, const std::string& prefix, P* p) {
  if (r.has(prefix))
    readScalars(r, prefix, p);
  else
    r.noteDefault(prefix, P::kAbsentNote);
}

/// \brief The range check of every scalar row given below `prefix` (keys left out keep
/// their defaults, which lie in range; the tables' tests hold that).
template <class P>
void checkRanges(ParamReader& r, const std::string& prefix, const P& p) {
  P::forEachScalar(p, [&](const ParamSpec& s, const auto& v) {
    // (strings and choices have no numeric check: theirs is in the reading)
    if constexpr (std::is_arithmetic<std::decay_t<decltype(v)>>::value) {
      if (s.check.any()) checkScalar(r, joinKey(prefix, s.key), s.check, static_cast<double>(v));
    }
  });
}

/// \brief readScalars, then checkRanges: a part read on its own, in a section its owner
/// handles (the plant's parts: sections without an absent_note of their own).
template <class P>
void readChecked(ParamReader& r, const std::string& prefix, P* p) {
  readScalars(r, prefix, p);
  checkRanges(r, prefix, *p);
}

}  // namespace preadaptive_mrac
