#pragma once
/// \file node_status.hpp
/// \brief One node's diagnostics status, written the same way by every node: the first problem
/// that holds names the summary (else OK), then named rows, then the ~accept_from rows.

#include <diagnostic_updater/diagnostic_updater.h>

#include <cstdint>
#include <initializer_list>
#include <sstream>
#include <string>
#include <type_traits>
#include <utility>

#include "preadaptive_mrac/ros/publisher_guard.hpp"

namespace preadaptive_mrac {
namespace ros1 {

/// \brief A row's value, as diagnostic_updater writes it (numbers by operator<<, "True" /
/// "False").
struct StatusValue {
  template <class T, std::enable_if_t<std::is_arithmetic<T>::value, int> = 0>
  StatusValue(T v) {  // NOLINT(google-explicit-constructor): a row's literal
    if constexpr (std::is_same<T, bool>::value) {
      text = v ? "True" : "False";
    } else {
      std::ostringstream s;
      s << v;
      text = s.str();
    }
  }
  StatusValue(std::string v) : text(std::move(v)) {}  // NOLINT(google-explicit-constructor)
  StatusValue(const char* v) : text(v) {}             // NOLINT(google-explicit-constructor)
  std::string text;
};

/// \brief Writes one DiagnosticStatus: problem() in order of precedence, then summarize(),
/// rows() and guard().
class NodeStatus {
 public:
  using Row = std::pair<const char*, StatusValue>;
  explicit NodeStatus(diagnostic_updater::DiagnosticStatusWrapper& stat) : stat_(stat) {}
  /// \brief When `holds` and no earlier problem held: the summary is `message` at `level`
  /// (diagnostic_msgs::DiagnosticStatus::WARN or ERROR).
  NodeStatus& problem(bool holds, unsigned char level, const std::string& message);
  /// \brief The summary: the first problem that held, else OK with `ok_message`.
  NodeStatus& summarize(const std::string& ok_message);
  NodeStatus& rows(std::initializer_list<Row> rows);
  /// \brief The ~accept_from rows: accepted names, drops, the dropped publishers.
  NodeStatus& guard(const PublisherGuard& g);

 private:
  diagnostic_updater::DiagnosticStatusWrapper& stat_;
  bool have_problem_ = false;
  unsigned char level_ = 0;
  std::string message_;
};

}  // namespace ros1
}  // namespace preadaptive_mrac
