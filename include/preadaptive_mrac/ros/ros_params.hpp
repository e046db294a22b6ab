#pragma once
/// \file ros_params.hpp
/// \brief The ROS parameter server into the core's ParamValue tree, so the nodes validate
/// their parameters on the same path as the batch CLI (one reader, every problem at once).

#include <xmlrpcpp/XmlRpcValue.h>

#include <string>
#include <vector>

#include "preadaptive_mrac/core/schema/params.hpp"

namespace preadaptive_mrac {
namespace ros1 {

/// \brief Convert one parameter-server value: int, double, bool, string, array and struct map
/// onto the tree's types; date-time and base64 (never written by rosparam YAML) become null
/// so that the readers report them as the wrong type. A string that YAML 1.2 reads as a number
/// with an exponent ("1e-3", "1.0e300": a string to rosparam's YAML 1.1) becomes that number, as
/// the CLI reads it.
ParamValue fromXmlRpc(const XmlRpc::XmlRpcValue& v);

/// \brief Exit code of a node whose configuration was refused.
constexpr int kExitConfigError = 2;
/// \brief Exit code of a node that stopped on a run-time failure (timeout, lost peer).
constexpr int kExitRuntimeError = 3;

}  // namespace ros1
}  // namespace preadaptive_mrac
