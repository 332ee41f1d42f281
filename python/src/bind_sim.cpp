// Plants for closed-loop simulation: built-in (idto's dynamics, stiff contact) and MuJoCo.

#include "convert.hpp"

namespace idto::python {
namespace {

using sim::Plant;

void BindPlant(py::module_& m) {
  py::class_<Plant>(m, "Plant", "A simulated system (q: nq, v: nv) stepped with forces u (nv).")
      .def(
          "reset",
          [](Plant& p, py::handle q, py::handle v) {
            p.Reset(ToVector(q, "Plant.reset", "q", p.q().size(), "nq"),
                    ToVector(v, "Plant.reset", "v", p.v().size(), "nv"));
          },
          py::arg("q"), py::arg("v"), "Sets the state and the clock to 0.")
      .def(
          "advance",
          [](Plant& p, double duration, py::handle u, int disturbed_body, py::handle f_ext_W) {
            const Eigen::VectorXd u_ = ToVector(u, "Plant.advance", "u", p.v().size(), "nv");
            const Eigen::Vector3d f =
                f_ext_W.is_none()
                    ? Eigen::Vector3d::Zero().eval()
                    : Eigen::Vector3d(ToVector(f_ext_W, "Plant.advance", "f_ext_W", 3));
            py::gil_scoped_release release;
            p.Advance(duration, u_, disturbed_body, f);
          },
          py::arg("duration"), py::arg("u"), py::arg("disturbed_body") = -1,
          py::arg("f_ext_W") = py::none(),
          "Advances by duration (s) in whole plant steps with u held (releases the GIL).")
      .def(
          "set_extra_damping",
          [](Plant& p, py::handle d) {
            p.SetExtraDamping(ToVector(d, "Plant.set_extra_damping", "d", p.v().size(), "nv"));
          },
          py::arg("d"))
      .def_property_readonly("q", [](const Plant& p) { return ToArray(p.q()); })
      .def_property_readonly("v", [](const Plant& p) { return ToArray(p.v()); })
      .def_property_readonly("time", &Plant::time)
      .def_property_readonly("contact_force_per_body",
                             [](const Plant& p) { return ToArray(p.contact_force_per_body()); })
      .def_property_readonly("name", &Plant::name);
}

void BindPlantOptions(py::module_& m) {
  using B = sim::BuiltinPlantOptions;
  py::class_<B>(m, "BuiltinPlantOptions")
      .def(py::init<>())
      .def_readwrite("time_step", &B::time_step)
      .def_readwrite("contact", &B::contact)
      .def_readwrite("pairs", &B::pairs)
      .def_readwrite("implicit_contact", &B::implicit_contact);
  using J = sim::MujocoPlantOptions;
  py::class_<J>(m, "MujocoPlantOptions")
      .def(py::init<>())
      .def_readwrite("time_step", &J::time_step)
      .def_readwrite("friction_coefficient", &J::friction_coefficient)
      .def_readwrite("torsional_friction", &J::torsional_friction)
      .def_readwrite("rolling_friction", &J::rolling_friction)
      .def_readwrite("friction_cone", &J::friction_cone)
      .def_readwrite("pairs", &J::pairs);
}

}  // namespace

void BindSim(py::module_& m) {
  BindPlant(m);
  BindPlantOptions(m);
  m.def("make_builtin_plant", &sim::MakeBuiltinPlant, py::arg("model"),
        py::arg("options") = sim::BuiltinPlantOptions(),
        "Semi-implicit Euler on idto's dynamics with a stiff compliant contact law.");
  m.def("make_mujoco_plant", &sim::MakeMujocoPlant, py::arg("model"),
        py::arg("options") = sim::MujocoPlantOptions(),
        "MuJoCo (rigid contact); raises RuntimeError when idto was built without MuJoCo.");
  m.def("make_mujoco_plant_mjcf", &sim::MakeMujocoPlantMjcf, py::arg("model"),
        py::arg("options") = sim::MujocoPlantOptions());
  m.def("have_mujoco", &sim::HaveMujoco, "True when idto was built with MuJoCo.");
}

}  // namespace idto::python
