// The core's plant-engine registry without any engine library linked: a run that names an
// engine this program lacks is refused with the reason, and an engine registered in one line
// (here a test-only one) is what ScenarioPlant steps.

#include <gtest/gtest.h>

#include <memory>
#include <string>

#include "preadaptive_mrac/core/sim/plant_engine.hpp"
#include "preadaptive_mrac/core/sim/scenario_plant.hpp"
#include "test_helpers.hpp"

namespace preadaptive_mrac {
namespace {

/// The linear model integrated with forward Euler: an engine that needs no process.
class EulerEngine : public PlantEngine {
 public:
  explicit EulerEngine(const PlantConfig& cfg) : cfg_(cfg) { reset(); }
  void reset() override { x_ = cfg_.x0; }
  const Vec& state() const override { return x_; }
  void step(double dt, const Vec& theta, double effect, double r, double) override {
    const Vec dx = cfg_.A * x_ + cfg_.B * (effect + theta.dot(x_)) + cfg_.B1r * r;
    x_ += dt * dx;
    flight_.pitch = x_[1];
    ++steps;
  }
  void setFaults(const PhysicalFaults&) override {}
  const FlightOutputs& flight() const override { return flight_; }
  double trimAirspeed() const override { return cfg_.airspeed; }
  void close() override {}
  static int steps;

 private:
  PlantConfig cfg_;
  Vec x_;
  FlightOutputs flight_;
};
int EulerEngine::steps = 0;

RunConfig shortRun() {
  RunConfig cfg = test::packageConfig("1");
  cfg.scenario.theta.resize(1);
  cfg.scenario.theta[0].until = 0.5;
  cfg.scenario.reference.resize(1);
  cfg.scenario.reference[0].until = 0.5;
  cfg.scenario.reference[0].r = 0.01;
  return cfg;
}

// Declared first: gtest runs a file's tests in order, and the next test registers an engine.
TEST(PlantEngine, AnEngineThisProgramLacksIsRefusedWithTheReason) {
  EXPECT_TRUE(hasPlantEngine(PlantEngineKind::kLinear));
  EXPECT_FALSE(hasPlantEngine(PlantEngineKind::kJsbsim));
  RunConfig cfg = shortRun();
  cfg.plant.engine = PlantEngineKind::kJsbsim;
  try {
    ScenarioPlant plant(cfg.plant, cfg.scenario, 0.001);
    FAIL() << "a plant without its engine was made";
  } catch (const PlantEngineError& e) {
    EXPECT_NE(std::string(e.what()).find("plant.engine jsbsim"), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find("built without"), std::string::npos) << e.what();
  }
}

TEST(PlantEngine, ARegisteredEngineIsWhatTheScenarioPlantSteps) {
  // The recipe's registration line (docs/design.md "Adding a plant engine").
  registerPlantEngine(PlantEngineKind::kJsbsim, [](const PlantConfig& cfg, double) {
    return std::make_unique<EulerEngine>(cfg);
  });
  ASSERT_TRUE(hasPlantEngine(PlantEngineKind::kJsbsim));
  RunConfig cfg = shortRun();
  ScenarioPlant linear(cfg.plant, cfg.scenario, 0.001);
  cfg.plant.engine = PlantEngineKind::kJsbsim;
  ScenarioPlant euler(cfg.plant, cfg.scenario, 0.001);
  ASSERT_NE(euler.engine(), nullptr);
  EXPECT_TRUE(euler.conditionRows().engine);
  EXPECT_FALSE(linear.conditionRows().engine);
  EulerEngine::steps = 0;
  for (int k = 0; k < 500; ++k) {
    linear.advance(0.001);
    euler.advance(0.001);
  }
  EXPECT_EQ(EulerEngine::steps, 500);
  // Euler against RK4 on the same model: close, not equal.
  EXPECT_NE(euler.state(), linear.state());
  EXPECT_LT((euler.state() - linear.state()).norm(), 1e-2 * linear.state().norm());
  EXPECT_EQ(euler.flight()->pitch, euler.state()[1]);
}

}  // namespace
}  // namespace preadaptive_mrac
