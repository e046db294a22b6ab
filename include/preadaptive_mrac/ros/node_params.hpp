#pragma once
/// \file node_params.hpp
/// \brief Parameters of the ROS nodes, read from a ParamValue tree (the node's private
/// namespace) with every problem collected at once. ROS-free, so it is tested without a master.

#include <cstdint>
#include <string>
#include <vector>

#include "preadaptive_mrac/core/control/input_guard.hpp"
#include "preadaptive_mrac/core/schema/params.hpp"
#include "preadaptive_mrac/io/setup.hpp"
#include "preadaptive_mrac/params/nodes_params.hpp"

namespace preadaptive_mrac {
namespace ros1 {

/// How the plant node advances time, and which clock the controller measures staleness in
/// (`~clock`): the enum generated from params/nodes.yaml (kLockstep: one step per answered
/// command, simulation time in the stamps; kRealtime: wall-clock timer, zero-order hold).
using preadaptive_mrac::ClockMode;
const char* clockModeName(ClockMode m);

/// \brief Everything plant_sim_node reads from `~`: the scalars, strings and choices of
/// params/nodes.yaml's rows naming it (PlantSimNodeParams, generated: defaults, docs, ranges),
/// ~accept_from, and the plant and scenario sections.
struct PlantNodeParams : PlantSimNodeParams {
  RunConfig run;  ///< plant and scenario sections (controller unused)
  /// Every optional key left out and filled with its default ("<key> = <value>", resolved
  /// names): the node's own (~dt, ~clock, ...) and those of the plant and scenario sections.
  std::vector<std::string> defaults_used;
};

/// \brief Everything mrac_controller_node reads from `~`: its rows of params/nodes.yaml
/// (MracControllerNodeParams, generated), ~accept_from, and the plant and controller sections.
struct ControllerNodeParams : MracControllerNodeParams {
  RunConfig run;  ///< plant (A, B, B1r) and controller sections
  /// Every optional key left out and filled with its default (the node's own, then the plant
  /// and controller sections').
  std::vector<std::string> defaults_used;
};

/// \brief Everything bag_recorder_node reads from `~`: its rows of params/nodes.yaml
/// (BagRecorderNodeParams, generated: ~output, ~progress_every, the split sizes, ...) and the
/// lists ~topics and ~types, read by hand (and ~accept_from, read as the plant's and the
/// controller's own: the nodes whose messages are written, [] = any publisher).
struct BagRecorderParams : BagRecorderNodeParams {
  /// Every optional key left out and filled with its default.
  std::vector<std::string> defaults_used;
};

/// \brief Everything run_monitor_node reads from `~`: ~state_topics (RunMonitorNodeParams,
/// generated; the list read by hand).
struct RunMonitorParams : RunMonitorNodeParams {
  std::vector<std::string> defaults_used;  ///< (none: its one key is required)
};

/// \brief One start-up line naming every optional key filled with its default:
/// "optional keys filled with defaults: k1 = v1, k2 = v2" (or "...: none").
std::string defaultsLine(const std::vector<std::string>& defaults_used);

/// \brief Read and validate plant_sim_node's private parameters. Throws ConfigError listing
/// every problem, each naming its key in `style` (e.g. "/plant_sim/dt").
PlantNodeParams readPlantNodeParams(const ParamValue& tree, const KeyStyle& style);

/// \brief Read and validate mrac_controller_node's private parameters, including the design
/// check of readRunConfig (A, B not stabilisable etc.) and a readable ~weights_in of the
/// right size. Throws ConfigError listing every problem.
ControllerNodeParams readControllerNodeParams(const ParamValue& tree, const KeyStyle& style);

/// \brief Read and validate bag_recorder_node's private parameters: the table's scalars,
/// ~topics (required, non-empty), ~types (optional: one per topic, each one of
/// `message_types`, the types the recorder can subscribe with) and ~output or ~output_prefix.
/// Throws ConfigError listing every problem.
BagRecorderParams readBagRecorderParams(const ParamValue& tree, const KeyStyle& style,
                                        const std::vector<std::string>& message_types);

/// \brief Read and validate run_monitor_node's private parameters (~state_topics, required,
/// non-empty). Throws ConfigError listing every problem.
RunMonitorParams readRunMonitorParams(const ParamValue& tree, const KeyStyle& style);

}  // namespace ros1
}  // namespace preadaptive_mrac
