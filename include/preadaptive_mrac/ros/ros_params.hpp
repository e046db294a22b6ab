#pragma once
/// \file ros_params.hpp
/// \brief The ROS parameter server into the core's ParamValue tree, so the nodes validate
/// their parameters on the same path as the batch CLI (one reader, every problem at once).

#include <xmlrpcpp/XmlRpcValue.h>

#include <string>
#include <vector>

#include "preadaptive_mrac/core/params.hpp"

namespace preadaptive_mrac {
namespace ros1 {

/// \brief Convert one parameter-server value: int, double, bool, string, array and struct map
/// onto the tree's types; date-time and base64 (never written by rosparam YAML) become null
/// so that the readers report them as the wrong type.
ParamValue fromXmlRpc(const XmlRpc::XmlRpcValue& v);

/// \brief The calling node's whole private namespace (`~`) as a map; an empty map when the
/// node has no private parameters. Requires ros::init().
ParamValue readPrivateParams();

/// \brief Key style naming fully resolved private parameters: "/node_name/controller/lqr/R".
KeyStyle privateKeyStyle();

/// \brief ROS_FATAL one line per problem, preceded by a summary line naming the node.
void logConfigProblems(const std::vector<std::string>& problems);

/// \brief Print one line to stdout (flushed) after ros::shutdown(), when rosconsole no longer
/// prints: the final summaries (weights saved, bag closed) must still reach the user.
void printAfterShutdown(const std::string& line, bool error = false);

/// \brief Exit code of a node whose configuration was refused.
constexpr int kExitConfigError = 2;
/// \brief Exit code of a node that stopped on a run-time failure (timeout, lost peer).
constexpr int kExitRuntimeError = 3;

}  // namespace ros1
}  // namespace preadaptive_mrac
