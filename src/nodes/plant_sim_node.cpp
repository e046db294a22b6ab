/// \file plant_sim_node.cpp
/// \brief main() of plant_sim_node; everything else is in PlantSimNode (src/ros).

#include "preadaptive_mrac/ros/plant_sim_node.hpp"

#include <ros/ros.h>

int main(int argc, char** argv) {
  ros::init(argc, argv, "plant_sim");
  return preadaptive_mrac::ros1::runPlantSimNode();
}
