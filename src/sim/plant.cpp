// The parts of idto/sim/plant.hpp that exist in every build, with or without MuJoCo.

#include "idto/sim/plant.hpp"

#include <memory>
#include <stdexcept>
#include <string>

#include "idto/core/errors.hpp"
#include "idto/sim/mjcf.hpp"

namespace idto::sim {

std::string MakeMujocoPlantMjcf(const Model& model, const MujocoPlantOptions& options) {
  static constexpr const char* kWhere = "MakeMujocoPlantMjcf";
  CheckPositive(kWhere, "options.time_step", options.time_step);
  CheckNonNegative(kWhere, "options.friction_coefficient", options.friction_coefficient);
  CheckNonNegative(kWhere, "options.torsional_friction", options.torsional_friction);
  CheckNonNegative(kWhere, "options.rolling_friction", options.rolling_friction);
  if (options.friction_cone != "elliptic" && options.friction_cone != "pyramidal") {
    ThrowInvalidArgument(kWhere, "options.friction_cone", "'" + options.friction_cone + "'",
                         "\"elliptic\" or \"pyramidal\"");
  }
  // The pairs the planner's engine would evaluate; its law only matters for the friction
  // coefficient (the plant's, unless a per-pair override sets one).
  ContactOptions pairs = options.pairs;
  pairs.parameters.friction_coefficient = options.friction_coefficient;
  const ContactEngine engine(model, pairs);

  MjcfOptions mjcf;
  mjcf.include_geometry = true;
  mjcf.disable_contact = false;
  mjcf.timestep = options.time_step;
  mjcf.integrator = "Euler";
  mjcf.cone = options.friction_cone;
  mjcf.contype = 0;
  mjcf.conaffinity = 0;
  mjcf.contact_pairs.reserve(engine.pairs().size());
  for (const ContactPair& pair : engine.pairs()) {
    mjcf.contact_pairs.push_back({pair.geometry_a, pair.geometry_b,
                                  pair.parameters.friction_coefficient, options.torsional_friction,
                                  options.rolling_friction});
  }
  return MakeMjcf(model, mjcf);
}

bool HaveMujoco() {
#ifdef IDTO_HAVE_MUJOCO
  return true;
#else
  return false;
#endif
}

#ifndef IDTO_HAVE_MUJOCO
std::unique_ptr<Plant> MakeMujocoPlant(const Model& /*model*/,
                                       const MujocoPlantOptions& /*options*/) {
  throw std::runtime_error(
      "MakeMujocoPlant: idto was built without MuJoCo (HaveMujoco() is false); install MuJoCo "
      "(libmujoco-dev) and reconfigure with -DIDTO_WITH_MUJOCO=AUTO or ON, or use the built-in "
      "plant (MakeBuiltinPlant)");
}
#endif

}  // namespace idto::sim
