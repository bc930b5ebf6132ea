// Small models shared by the articulated tests.
#pragma once
#include <string>

#include "pliant/articulated/io.h"
#include "pliant/articulated/sim.h"
#include "pliant/core/error.h"

namespace pliant::articulated::test {

// "pointer | problem" of the InputError an MJCF text raises, or "no error".
inline std::string mjcf_error(const std::string& xml) {
  try {
    model_from_mjcf(xml, "bad.xml");
  } catch (const InputError& e) {
    return e.pointer() + " | " + e.problem();
  }
  return "no error";
}

// Options for a model that touches nothing: the integrator at dt, contact off.
inline SimOptions contact_free_options(Integrator integrator, double dt) {
  SimOptions o;
  o.integrator = integrator;
  o.dt = dt;
  o.contact.enabled = false;
  return o;
}

// A model exercising every joint type: free root, ball, hinge, slide.
inline Model mixed_model() {
  const std::string xml = R"(<mujoco model="mixed">
  <worldbody>
    <body name="root" pos="0 0 1">
      <freejoint/>
      <geom type="box" size="0.1 0.05 0.03"/>
      <body name="a" pos="0.1 0 0">
        <joint type="ball" pos="0 0 0"/>
        <geom type="capsule" fromto="0 0 0 0.2 0.05 0" size="0.02"/>
        <body name="b" pos="0.2 0.05 0" quat="0.9 0.1 0.3 0.2">
          <joint type="hinge" axis="0.3 1 0.2" pos="0.01 0 0"/>
          <joint type="slide" axis="1 0 0.5"/>
          <geom type="sphere" size="0.04" pos="0.05 0 0"/>
        </body>
      </body>
    </body>
  </worldbody>
</mujoco>)";
  return model_from_mjcf(xml, "mixed.xml");
}

// A hinge pendulum: point-like mass at distance length below the pivot.
inline Model pendulum(double length, double mass = 1.0) {
  const std::string xml = "<mujoco><worldbody><body name=\"bob\"><joint type=\"hinge\" axis=\"0 1 0\"/>"
                          "<inertial pos=\"0 0 " + std::to_string(-length) + "\" mass=\"" +
                          std::to_string(mass) + "\" diaginertia=\"1e-6 1e-6 1e-6\"/>"
                          "</body></worldbody></mujoco>";
  return model_from_mjcf(xml, "pendulum.xml");
}

}  // namespace pliant::articulated::test
