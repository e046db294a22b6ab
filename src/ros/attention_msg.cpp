#include "preadaptive_mrac/ros/attention_msg.hpp"

#include <vector>

namespace preadaptive_mrac {
namespace ros1 {
namespace {

// The message's codes (msg/AttentionEvent.msg: 0, 1, 2, ... in the enums' order) are the
// core enums' ordinals.
static_assert(AttentionEvent::ONSET == static_cast<int>(Event::Type::kOnset) &&
                  AttentionEvent::IGNORED_RECOVERY ==
                      static_cast<int>(Event::Type::kIgnoredRecovery) &&
                  AttentionEvent::DECISION == static_cast<int>(Event::Type::kDecision) &&
                  AttentionEvent::DECISION_NONE == static_cast<int>(Event::Decision::kNone) &&
                  AttentionEvent::DECISION_MEMORY == static_cast<int>(Event::Decision::kMemory) &&
                  AttentionEvent::DECISION_NETWORK == static_cast<int>(Event::Decision::kNetwork),
              "AttentionEvent's codes follow Event::Type and Event::Decision");

void copyVec(const Vec& v, std::vector<double>* out) {
  out->resize(static_cast<size_t>(v.size()));
  for (int i = 0; i < v.size(); ++i) (*out)[static_cast<size_t>(i)] = v[i];
}

}  // namespace

void toMsg(const Event& ev, std::uint64_t step, AttentionEvent* msg) {
  msg->type = static_cast<std::uint8_t>(ev.type);
  msg->type_name = eventTypeName(ev.type);
  msg->step = step;
  msg->t = ev.t;
  msg->e = ev.e;
  msg->e_dot_est = ev.e_dot;
  copyVec(ev.theta_hat_before, &msg->theta_hat_before);
  copyVec(ev.theta_hat_after, &msg->theta_hat_after);
  msg->reset = ev.reset;
  msg->cost = ev.cost;
  copyVec(ev.grad, &msg->grad);
  msg->learned = ev.learned;
  msg->episodes = ev.episodes;
  // pa_robust's verification; the defaults ("", NONE, -1, 0, 0, 0) for every other event.
  const bool decided = ev.decision != Event::Decision::kNone;
  msg->decision = decided ? decisionName(ev.decision) : "";
  msg->decision_code = static_cast<std::uint8_t>(ev.decision);
  msg->chosen = decided ? ev.chosen : -1;
  msg->candidates = decided ? ev.candidates : 0;
  msg->score = decided ? ev.score : 0.0;
  msg->score_keep = decided ? ev.score_keep : 0.0;
}

}  // namespace ros1
}  // namespace preadaptive_mrac
