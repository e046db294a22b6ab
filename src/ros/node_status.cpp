#include "preadaptive_mrac/ros/node_status.hpp"

namespace preadaptive_mrac {
namespace ros1 {
NodeStatus& NodeStatus::problem(bool holds, unsigned char level, const std::string& message) {
  if (holds && !have_problem_) {
    have_problem_ = true;
    level_ = level;
    message_ = message;
  }
  return *this;
}

NodeStatus& NodeStatus::summarize(const std::string& ok_message) {
  if (have_problem_)
    stat_.summary(level_, message_);
  else
    stat_.summary(diagnostic_msgs::DiagnosticStatus::OK, ok_message);
  return *this;
}

NodeStatus& NodeStatus::rows(std::initializer_list<Row> rows) {
  for (const Row& r : rows) stat_.add(r.first, r.second.text);
  return *this;
}

NodeStatus& NodeStatus::guard(const PublisherGuard& g) {
  return rows({{"accept from", g.acceptedText()},
               {"foreign publisher drops", g.dropped()},
               {"foreign publishers", g.droppedText()}});
}

}  // namespace ros1
}  // namespace preadaptive_mrac
