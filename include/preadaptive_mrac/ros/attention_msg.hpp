#pragma once
/// \file attention_msg.hpp
/// \brief The controller's attention events as ROS messages (controller/attention).

#include <cstdint>

#include "preadaptive_mrac/AttentionEvent.h"
#include "preadaptive_mrac/core/controller/controller.hpp"

namespace preadaptive_mrac {
namespace ros1 {

/// \brief Fill an AttentionEvent from a core event (step: the sample it happened at).
void toMsg(const Event& ev, std::uint64_t step, AttentionEvent* msg);

}  // namespace ros1
}  // namespace preadaptive_mrac
