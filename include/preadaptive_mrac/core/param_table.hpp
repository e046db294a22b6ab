#pragma once
/// \file param_table.hpp
/// \brief The generic reader of a generated parameter struct (params/*.yaml through
/// params_codegen.py): every scalar the table declares, read with its presence and checked
/// against its range, each problem naming its key. What no table row can say (a value checked
/// against another, a matrix's shape) stays in the component's own validate().

#include <string>

#include "preadaptive_mrac/core/param_spec.hpp"
#include "preadaptive_mrac/core/params.hpp"

namespace preadaptive_mrac {

/// \brief Read one scalar: required keys must be there; optional ones keep `*v` (the
/// declared default) and are noted.
void readScalar(ParamReader& r, const std::string& key, const ParamSpec& s, double* v);
void readScalar(ParamReader& r, const std::string& key, const ParamSpec& s, int* v);
void readScalar(ParamReader& r, const std::string& key, const ParamSpec& s, bool* v);
/// \brief A problem naming `key` when the value given there lies outside the row's check.
void checkScalar(ParamReader& r, const std::string& key, const ParamCheck& c, double v);

/// \brief Every scalar row of P's table below `prefix`; a row inside an optional section only
/// when the section is there. Sections left out are noted with their absent_note.
template <class P>
void readScalars(ParamReader& r, const std::string& prefix, P* p) {
  P::forEachSection([&](const char* key, const char* note) {
    if (!r.has(prefix + "." + key)) r.noteDefault(prefix + "." + key, note);
  });
  P::forEachScalar(*p, [&](const ParamSpec& s, auto& v) {
    if (s.presence == ParamPresence::kInSection && !r.has(prefix + "." + s.section)) return;
    readScalar(r, prefix + "." + s.key, s, &v);
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
    if (s.check.any()) checkScalar(r, prefix + "." + s.key, s.check, static_cast<double>(v));
  });
}

}  // namespace preadaptive_mrac
