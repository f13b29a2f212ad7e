#include "host/scenario/timeline_events.h"

#include <algorithm>
#include <cmath>
#include <initializer_list>
#include <string_view>

#include "rig/number_text.h"

namespace hilrig::host {
namespace {

// The label's parts appended one by one: GCC 12 warns falsely (-Wrestrict) on some chains of
// operator+ that start with a literal.
std::string Label(std::initializer_list<std::string_view> parts) {
  std::string label;
  for (std::string_view part : parts) label.append(part);
  return label;
}

std::string Vector(const Eigen::Vector3d& value) {
  return Label({"(", rig::NumberText(value.x()), ", ", rig::NumberText(value.y()), ", ",
                rig::NumberText(value.z()), ")"});
}

std::string Rounded(double value, double step) {
  return rig::NumberText(std::round(value / step) * step);
}

void AddGripperEvents(const GripperConfig& gripper, std::vector<TimelineEvent>& events) {
  for (const GraspCommandEvent& grasp : gripper.grasps) {
    events.push_back({grasp.at_s, grasp.regulate
                                      ? Label({"grasp ", rig::NumberText(grasp.force_n), " N"})
                                      : std::string("open")});
  }
  for (const PourEvent& pour : gripper.pours) {
    events.push_back({pour.at_s, Label({"pour ", Rounded(pour.mass_kg * 1e3, 0.1), " g over ",
                                        rig::NumberText(pour.duration_s), " s"})});
  }
  for (double at_s : gripper.support_removals_s) events.push_back({at_s, "stand removed"});
  for (std::size_t i = 1; i < gripper.objects.size(); ++i) {
    events.push_back({gripper.objects[i].at_s, Label({"present ", gripper.objects[i].fixture})});
  }
}

}  // namespace

std::vector<TimelineEvent> TimelineEvents(const ScenarioConfig& config) {
  std::vector<TimelineEvent> events;
  for (const SetpointCommand& setpoint : config.setpoints) {
    events.push_back({setpoint.at_s, Label({"setpoint ", Vector(setpoint.position_m), " m"})});
  }
  for (const DisturbanceCommand& gust : config.disturbances) {
    events.push_back({gust.at_s, Label({"gust ", Rounded(gust.force_world_n.norm(), 0.01),
                                        " N for ", rig::NumberText(gust.duration_s), " s"})});
  }
  if (config.gripper.enabled) AddGripperEvents(config.gripper, events);
  for (const StrayFieldEvent& stray : config.hall_sensors.stray_fields) {
    events.push_back({stray.at_s, Label({"stray field at node ", std::to_string(stray.node_id)})});
  }
  std::stable_sort(events.begin(), events.end(),
                   [](const TimelineEvent& a, const TimelineEvent& b) { return a.at_s < b.at_s; });
  return events;
}

}  // namespace hilrig::host
