/// \file test_ros_config.cpp
/// \brief The nodes' side of configuration and tuning, without a master: parameter-server
/// values read as the CLI reads the same YAML, and a controller whose state is no longer finite
/// answering with its baseline instead of NaN.

#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <string>

#include "preadaptive_mrac/core/controller/controller.hpp"
#include "preadaptive_mrac/io/setup.hpp"
#include "preadaptive_mrac/io/yaml_params.hpp"
#include "preadaptive_mrac/ros/controller_reconfigure.hpp"
#include "preadaptive_mrac/ros/ros_params.hpp"

namespace pm = preadaptive_mrac;

namespace {
pm::ParamValue cliValue(const std::string& text) {
  return *pm::parseYaml("v: " + text + "\n", "test").find("v");
}
}  // namespace

TEST(RosParams, NumbersReadAsTheCliReadsThem) {
  // rosparam (YAML 1.1) hands these over as strings; the CLI (YAML 1.2) reads numbers.
  for (const char* text : {"1.0e300", "1e-3", "-2.5E4", ".5e1", "1.0e+300"}) {
    const pm::ParamValue ros = pm::ros1::fromXmlRpc(XmlRpc::XmlRpcValue(std::string(text)));
    const pm::ParamValue cli = cliValue(text);
    ASSERT_EQ(cli.type(), pm::ParamValue::Type::kDouble) << text;
    EXPECT_EQ(ros.type(), pm::ParamValue::Type::kDouble) << text;
    EXPECT_EQ(ros.asDouble(), cli.asDouble()) << text;
  }
  // Strings stay strings.
  for (const char* text : {"pa_learn", "e5", "1e", "1.0e300x", "nan"}) {
    const pm::ParamValue ros = pm::ros1::fromXmlRpc(XmlRpc::XmlRpcValue(std::string(text)));
    EXPECT_EQ(ros.type(), pm::ParamValue::Type::kString) << text;
  }
}

TEST(ControllerRecovery, NonFiniteStateAnswersWithTheBaseline) {
  pm::ParamValue tree = pm::ParamValue::makeMap();
  tree.merge(pm::loadYamlFile(pm::defaultPlantPath()));
  tree.merge(pm::loadYamlFile(pm::defaultControllerPath()));
  tree.merge(pm::loadYamlFile(pm::scenarioPath("1")));
  const pm::RunConfig rc = pm::readRunConfig(tree);
  pm::Controller ctl(designModelOf(rc.plant, rc.controller), rc.controller);
  const int n = rc.plant.n();
  pm::Vec x = pm::Vec::Constant(n, 0.01);
  pm::StepInput in;
  in.t = 0.0;
  in.x = &x;
  in.r = 0.1;
  pm::StepOutput out = ctl.step(in);
  EXPECT_FALSE(pm::ros1::recoverNonFinite(&ctl, x, &out));  // a finite step is left alone

  // A diverged adaptation: theta_hat overflowed, the command is NaN.
  const double inf = std::numeric_limits<double>::infinity();
  out.u = std::numeric_limits<double>::quiet_NaN();
  out.u_unsaturated = out.u;
  out.theta_hat = pm::Vec::Constant(n, inf);
  ASSERT_TRUE(pm::ros1::recoverNonFinite(&ctl, x, &out));
  EXPECT_TRUE(std::isfinite(out.u));
  EXPECT_EQ(out.u_adaptive, 0.0);
  EXPECT_EQ(out.u, out.u_baseline);
  EXPECT_TRUE(out.theta_hat.allFinite());
  EXPECT_EQ((out.theta_hat - rc.controller.theta_hat0).norm(), 0.0);  // reset to its start
  EXPECT_EQ((ctl.thetaHat() - rc.controller.theta_hat0).norm(), 0.0);
  // The controller goes on from there with finite commands.
  in.t = rc.controller.sample_time;
  const pm::StepOutput next = ctl.step(in);
  EXPECT_TRUE(std::isfinite(next.u));
}
