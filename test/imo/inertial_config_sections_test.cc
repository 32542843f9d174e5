// The inertial methods' section parsers (drag_model_section.h, gate_corner_section.h,
// pipeline/inertial_config_sections.h): values are read, defaults kept, and unknown keys and
// out-of-range values are InputErrors naming the file. Through hdvio_run:
// test/run/inertial_pipeline_test.cc, test/run/gate_io_pipeline_test.cc.
#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <functional>
#include <string>

#include "hdvio/backend/imo/drag_model_section.h"
#include "hdvio/backend/imo/gate_corner_section.h"
#include "hdvio/core/config.h"
#include "hdvio/core/error.h"
#include "hdvio/pipeline/inertial_config_sections.h"

namespace hdvio {
namespace {
using ::testing::HasSubstr;

// The section `key` of `yaml`, from a file named s.yaml.
ConfigReader sectionOf(const std::string& yaml, const std::string& key) {
  return ConfigReader::fromString(yaml, "s.yaml").optionalSection(key);
}

// The InputError's message; fails the test without one or when it does not name the file.
std::string errorOf(const std::function<void()>& f) {
  try {
    f();
  } catch (const InputError& e) {
    EXPECT_THAT(e.what(), HasSubstr("s.yaml"));
    return e.what();
  }
  ADD_FAILURE() << "no InputError";
  return "";
}

imo::DragModelSection dragModel(const std::string& yaml) {
  imo::DragModelSection s;
  imo::readDragModelSection(sectionOf(yaml, "model"), "s.yaml", &s);
  return s;
}

TEST(DragModelSection, ReadsTheModelAndKeepsDefaults) {
  const imo::DragModelSection s =
      dragModel("model: {thrust_scale: 1.02, linear_drag: [0.3, 0.4, 0.2], window_s: 1.0}\n");
  EXPECT_DOUBLE_EQ(s.model.thrust_scale, 1.02);
  EXPECT_EQ(s.model.drag.linear, Vec3(0.3, 0.4, 0.2));
  EXPECT_DOUBLE_EQ(s.window_s, 1.0);
  EXPECT_DOUBLE_EQ(s.integration_step_s, 0.005);
  EXPECT_TRUE(s.attitude_jacobian);
  EXPECT_FALSE(dragModel("model: {attitude_jacobian: false}\n").attitude_jacobian);
  const imo::DragModelSection defaults = dragModel("");
  EXPECT_DOUBLE_EQ(defaults.window_s, imo::ImoRunOptions().window_s);
  EXPECT_DOUBLE_EQ(defaults.model.thrust_scale, 1.0);
}

TEST(DragModelSection, RejectsUnknownKeysAndBadValues) {
  EXPECT_THAT(errorOf([] { dragModel("model: {linear_drg: [0, 0, 0]}\n"); }), HasSubstr("linear_drg"));
  EXPECT_THAT(errorOf([] { dragModel("model: {linear_drag: [0.3, -0.1, 0.2]}\n"); }),
              HasSubstr("model.linear_drag must be >= 0"));
  errorOf([] { dragModel("model: {linear_drag: [0.3, 0.2]}\n"); });
  errorOf([] { dragModel("model: {thrust_scale: 0}\n"); });
  errorOf([] { dragModel("model: {integration_step_s: 1}\n"); });
  errorOf([] { dragModel("model: {window_s: 0.01}\n"); });
}

imo::GateCornerSection gate(const std::string& yaml) {
  imo::GateCornerSection s;
  imo::readGateCornerSection(sectionOf(yaml, "gate"), &s);
  return s;
}

TEST(GateCornerSection, ReadsTheOptionsAndKeepsDefaults) {
  const imo::GateCornerSection s =
      gate("gate: {pixel_sigma: 2.5, corner_gate_probability: 0.99, use_detections: false}\n");
  EXPECT_DOUBLE_EQ(s.options.pixel_sigma, 2.5);
  EXPECT_DOUBLE_EQ(s.options.corner_gate_probability, 0.99);
  EXPECT_DOUBLE_EQ(s.options.gate_probability, imo::GateCornerOptions().gate_probability);
  EXPECT_FALSE(s.use_detections);
  EXPECT_TRUE(gate("").use_detections);
}

TEST(GateCornerSection, RejectsUnknownKeysAndBadValues) {
  EXPECT_THAT(errorOf([] { gate("gate: {pixle_sigma: 1}\n"); }), HasSubstr("pixle_sigma"));
  errorOf([] { gate("gate: {pixel_sigma: -1}\n"); });
  errorOf([] { gate("gate: {gate_probability: 1}\n"); });
  errorOf([] { gate("gate: {use_detections: maybe}\n"); });
}

InertialRunSpan span(const std::string& yaml) {
  InertialRunSpan s;
  readInertialRunSection(sectionOf(yaml, "run"), &s);
  return s;
}

TEST(InertialRunSection, ReadsTheSpan) {
  const InertialRunSpan s = span("run: {start_offset_s: 12.5, duration_s: 30}\n");
  EXPECT_DOUBLE_EQ(s.start_offset_s, 12.5);
  EXPECT_DOUBLE_EQ(s.duration_s, 30.0);
  EXPECT_DOUBLE_EQ(span("").duration_s, 0.0);
  EXPECT_THAT(errorOf([] { span("run: {duration: 30}\n"); }), HasSubstr("duration"));
  errorOf([] { span("run: {start_offset_s: -1}\n"); });
}

RotorThrust thrust(const std::string& yaml) {
  RotorThrust t;
  readThrustSection(sectionOf(yaml, "thrust"), "s.yaml", &t);
  return t;
}

TEST(ThrustSection, ReadsTheRotorThrustAndChecksTheAxis) {
  const RotorThrust t = thrust("thrust: {coefficient_over_mass: 1.0e-6, axis: [0, 0, -1]}\n");
  EXPECT_DOUBLE_EQ(t.coefficient_over_mass, 1.0e-6);
  EXPECT_EQ(t.axis, Vec3(0, 0, -1));
  EXPECT_EQ(thrust("").axis, Vec3::UnitZ());
  EXPECT_THAT(errorOf([] { thrust("thrust: {axis: [0, 0, 2]}\n"); }),
              HasSubstr("thrust.axis must be a unit vector"));
  EXPECT_THAT(errorOf([] { thrust("thrust: {coefficient: 1.0e-6}\n"); }), HasSubstr("coefficient"));
  errorOf([] { thrust("thrust: {coefficient_over_mass: 2}\n"); });
}

TEST(GateIoDisplacement, IsReadOnceIntoItsEnum) {
  EXPECT_EQ(readGateIoDisplacement(ConfigReader::fromString("a: 1\n", "s.yaml")), DisplacementUse::kNone);
  EXPECT_EQ(readGateIoDisplacement(ConfigReader::fromString("displacement: network\n", "s.yaml")),
            DisplacementUse::kFilterUpdate);
  const ConfigReader bad = ConfigReader::fromString("displacement: sometimes\n", "s.yaml");
  EXPECT_THAT(errorOf([&] { readGateIoDisplacement(bad); }), HasSubstr("sometimes"));
}

}  // namespace
}  // namespace hdvio
