// Models (URDF parsing, queries, name look-ups), Data and the dynamics kernels.

#include "convert.hpp"

namespace idto::python {
namespace {

py::array_t<double> ToArray4(const Eigen::Isometry3d& X) {
  return ToArray(Eigen::MatrixXd(X.matrix()));
}

Eigen::VectorXd Q(const Model& m, py::handle q, const char* where, const char* name = "q") {
  return ToVector(q, where, name, m.nq(), "nq");
}
Eigen::VectorXd V(const Model& m, py::handle v, const char* where, const char* name = "v") {
  return ToVector(v, where, name, m.nv(), "nv");
}

/// Data made for another model would be indexed out of bounds: refuse it.
void CheckData(const char* where, const Model& model, const Data& data) {
  if (static_cast<int>(data.X_WB_.size()) != model.num_bodies() || data.tau.size() != model.nv()) {
    ThrowInvalidArgument(where, "data",
                         "a Data of another model (" + std::to_string(data.X_WB_.size()) +
                             " bodies, nv " + std::to_string(data.tau.size()) + ")",
                         "Data(model)");
  }
}

/// The URDF's warnings (what it holds that idto ignores by design) as Python UserWarnings, so
/// that the warnings module shows them (or turns them into errors) instead of their being lost.
void EmitUrdfWarnings(const std::vector<UrdfWarning>& warnings) {
  for (const UrdfWarning& w : warnings) {
    if (PyErr_WarnEx(PyExc_UserWarning, w.ToString().c_str(), 1) != 0) {
      throw py::error_already_set();
    }
  }
}

void BindUrdf(py::module_& m) {
  py::enum_<BaseType>(m, "BaseType", "How the root of a model is attached to the world.")
      .value("kFixed", BaseType::kFixed)
      .value("kFloating", BaseType::kFloating)
      .value("kPlanar", BaseType::kPlanar);
  py::enum_<JointType>(m, "JointType")
      .value("kFixed", JointType::kFixed)
      .value("kRevolute", JointType::kRevolute)
      .value("kContinuous", JointType::kContinuous)
      .value("kPrismatic", JointType::kPrismatic)
      .value("kPlanar", JointType::kPlanar)
      .value("kFloating", JointType::kFloating);
  py::class_<InscribedSpheresOptions>(m, "InscribedSpheresOptions")
      .def(py::init<>())
      .def_readwrite("num_per_axis", &InscribedSpheresOptions::num_per_axis)
      .def_readwrite("radius_fraction", &InscribedSpheresOptions::radius_fraction);
  py::class_<UrdfOptions>(m, "UrdfOptions", "How a URDF model is attached to the world.")
      .def(py::init<>())
      .def_readwrite("base", &UrdfOptions::base)
      .def_property(
          "X_WB", [](const UrdfOptions& o) { return ToArray4(o.X_WB); },
          [](UrdfOptions& o, py::handle X) { o.X_WB = ToIsometry(X, "UrdfOptions", "X_WB"); },
          "Pose of the root's joint frame in the world (4 x 4)")
      .def_property(
          "planar_normal",
          [](const UrdfOptions& o) { return ToArray(Eigen::VectorXd(o.planar_normal)); },
          [](UrdfOptions& o, py::handle n) {
            o.planar_normal = ToVector(n, "UrdfOptions", "planar_normal", 3);
          })
      .def_readwrite("prefix", &UrdfOptions::prefix)
      .def_readwrite("model_name", &UrdfOptions::model_name)
      .def_readwrite("box_inscribed_spheres", &UrdfOptions::box_inscribed_spheres);
  m.def(
      "parse_urdf",
      [](const std::string& path, const UrdfOptions& options) {
        std::vector<UrdfWarning> warnings;
        Model model = ParseUrdfFile(path, options, &warnings);
        EmitUrdfWarnings(warnings);
        return model;
      },
      py::arg("path"), py::arg("options") = UrdfOptions(),
      "A Model from a URDF file (raises FileError naming the file and element; what the file "
      "holds that idto ignores by design is reported as a UserWarning).");
  m.def(
      "parse_urdf_string",
      [](const std::string& urdf_xml, const UrdfOptions& options, const std::string& source) {
        std::vector<UrdfWarning> warnings;
        Model model = ParseUrdfString(urdf_xml, options, source, &warnings);
        EmitUrdfWarnings(warnings);
        return model;
      },
      py::arg("urdf_xml"), py::arg("options") = UrdfOptions(),
      py::arg("source_name") = "<urdf string>");
}

std::vector<std::string> Names(int n, const std::function<const std::string&(int)>& name) {
  std::vector<std::string> out;
  for (int i = 0; i < n; ++i) out.push_back(name(i));
  return out;
}

void BindModelQueries(py::class_<Model>& c) {
  c.def(py::init<>())
      .def("nq", &Model::nq)
      .def("nv", &Model::nv)
      .def("num_bodies", &Model::num_bodies)
      .def("num_joints", &Model::num_joints)
      .def("num_frames", &Model::num_frames)
      .def("num_moving_bodies", &Model::num_moving_bodies)
      .def("num_geometries", [](const Model& m) { return static_cast<int>(m.geometries().size()); })
      .def("name", &Model::name)
      .def("get_body_index", &Model::GetBodyIndex, py::arg("name"))
      .def("has_body", &Model::HasBody, py::arg("name"))
      .def("get_joint_index", &Model::GetJointIndex, py::arg("name"))
      .def("has_joint", &Model::HasJoint, py::arg("name"))
      .def("get_position_start", &Model::GetPositionStart, py::arg("joint_name"))
      .def("get_velocity_start", &Model::GetVelocityStart, py::arg("joint_name"))
      .def("get_frame_index", &Model::GetFrameIndex, py::arg("name"))
      .def("has_frame", &Model::HasFrame, py::arg("name"))
      .def("get_geometry_index", &Model::GetGeometryIndex, py::arg("name"))
      .def("body_names",
           [](const Model& m) {
             return Names(m.num_bodies(),
                          [&m](int b) -> const std::string& { return m.body_name(b); });
           })
      .def("joint_names",
           [](const Model& m) {
             // Joint b moves body b (b >= 1); entry 0 is the world's (empty) name.
             return Names(m.num_bodies(),
                          [&m](int j) -> const std::string& { return m.joint_name(j); });
           })
      .def("frame_names",
           [](const Model& m) {
             return Names(m.num_frames(),
                          [&m](int f) -> const std::string& { return m.frame_name(f); });
           })
      .def("geometry_names",
           [](const Model& m) {
             std::vector<std::string> out;
             for (const GeometryInstance& g : m.geometries()) out.push_back(g.name);
             return out;
           })
      .def("total_mass", &Model::total_mass)
      .def("has_quaternions", &Model::has_quaternions)
      .def("floating_joints", &Model::floating_joints)
      .def("is_base_velocity", &Model::is_base_velocity)
      .def("gravity", [](const Model& m) { return ToArray(Eigen::VectorXd(m.gravity())); })
      .def("damping", [](const Model& m) { return ToArray(m.damping()); })
      .def("effort_limits", [](const Model& m) { return ToArray(m.effort_limits()); })
      .def("lower_position_limits",
           [](const Model& m) { return ToArray(m.lower_position_limits()); })
      .def("upper_position_limits",
           [](const Model& m) { return ToArray(m.upper_position_limits()); })
      .def("neutral_configuration",
           [](const Model& m) { return ToArray(m.NeutralConfiguration()); })
      .def("__repr__", [](const Model& m) {
        return "<idto.Model '" + m.name() + "': nq " + std::to_string(m.nq()) + ", nv " +
               std::to_string(m.nv()) + ", " + std::to_string(m.num_bodies()) + " bodies>";
      });
}

void BindModelIndexed(py::class_<Model>& c) {
  const auto body = [](const char* where, const Model& m, int b) {
    CheckIndex(where, "body", b, m.num_bodies());
  };
  const auto joint = [](const char* where, const Model& m, int j) {
    CheckIndex(where, "joint", j, m.num_bodies());
  };
  c.def("body_name",
        [body](const Model& m, int b) {
          body("body_name", m, b);
          return m.body_name(b);
        })
      .def("parent",
           [body](const Model& m, int b) {
             body("parent", m, b);
             return m.parent(b);
           })
      .def("mobilized_body",
           [body](const Model& m, int b) {
             body("mobilized_body", m, b);
             return m.mobilized_body(b);
           })
      .def("body_mass",
           [body](const Model& m, int b) {
             body("body_mass", m, b);
             return m.body_mass(b);
           })
      .def("joint_name",
           [joint](const Model& m, int j) {
             joint("joint_name", m, j);
             return m.joint_name(j);
           })
      .def("joint_type",
           [joint](const Model& m, int j) {
             joint("joint_type", m, j);
             return m.joint_type(j);
           })
      .def("position_start",
           [joint](const Model& m, int j) {
             joint("position_start", m, j);
             return m.position_start(j);
           })
      .def("velocity_start",
           [joint](const Model& m, int j) {
             joint("velocity_start", m, j);
             return m.velocity_start(j);
           })
      .def("joint_nq",
           [joint](const Model& m, int j) {
             joint("joint_nq", m, j);
             return m.joint_nq(j);
           })
      .def("joint_nv",
           [joint](const Model& m, int j) {
             joint("joint_nv", m, j);
             return m.joint_nv(j);
           })
      .def("position_name",
           [](const Model& m, int i) {
             CheckIndex("position_name", "i", i, m.nq());
             return m.position_name(i);
           })
      .def("velocity_name",
           [](const Model& m, int i) {
             CheckIndex("velocity_name", "i", i, m.nv());
             return m.velocity_name(i);
           })
      .def("frame_name",
           [](const Model& m, int f) {
             CheckIndex("frame_name", "frame", f, m.num_frames());
             return m.frame_name(f);
           })
      .def("frame_body", [](const Model& m, int f) {
        CheckIndex("frame_body", "frame", f, m.num_frames());
        return m.frame_body(f);
      });
}

void BindData(py::module_& m) {
  const auto body = [](const char* where, const Data& d, int b) {
    CheckIndex(where, "body", b, static_cast<long>(d.X_WB_.size()));
  };
  py::class_<Data>(m, "Data", "Per-thread workspace of the dynamics algorithms for one model.")
      .def(py::init<const Model&>(), py::arg("model"))
      .def("X_WB",
           [body](const Data& d, int b) {
             body("X_WB", d, b);
             return ToArray4(d.X_WB(b));
           })
      .def("R_WB",
           [body](const Data& d, int b) {
             body("R_WB", d, b);
             return ToArray(Eigen::MatrixXd(d.R_WB(b)));
           })
      .def("p_WB",
           [body](const Data& d, int b) {
             body("p_WB", d, b);
             return ToArray(Eigen::VectorXd(d.p_WB(b)));
           })
      .def("V_WB",
           [body](const Data& d, int b) {
             body("V_WB", d, b);
             return ToArray(Eigen::VectorXd(d.V_WB(b)));
           })
      .def("w_WB",
           [body](const Data& d, int b) {
             body("w_WB", d, b);
             return ToArray(Eigen::VectorXd(d.w_WB(b)));
           })
      .def("v_WBo",
           [body](const Data& d, int b) {
             body("v_WBo", d, b);
             return ToArray(Eigen::VectorXd(d.v_WBo(b)));
           })
      .def(
          "X_WF",
          [](const Data& d, const Model& model, int f) {
            CheckIndex("X_WF", "frame", f, model.num_frames());
            CheckData("X_WF", model, d);
            return ToArray4(d.X_WF(model, f));
          },
          py::arg("model"), py::arg("frame"))
      .def_property_readonly("tau", [](const Data& d) { return ToArray(d.tau); })
      .def_property_readonly("M", [](const Data& d) { return ToArray(d.M); })
      .def_property_readonly("a", [](const Data& d) { return ToArray(d.a); });
}

void BindKinematics(py::module_& m) {
  m.def(
      "forward_kinematics",
      [](const Model& model, py::handle q, Data& data) {
        CheckData("forward_kinematics", model, data);
        ForwardKinematics(model, Q(model, q, "forward_kinematics"), &data);
      },
      py::arg("model"), py::arg("q"), py::arg("data"), "Body poses for q (nq) into data.");
  m.def(
      "forward_kinematics",
      [](const Model& model, py::handle q, py::handle v, Data& data) {
        CheckData("forward_kinematics", model, data);
        ForwardKinematics(model, Q(model, q, "forward_kinematics"),
                          V(model, v, "forward_kinematics"), &data);
      },
      py::arg("model"), py::arg("q"), py::arg("v"), py::arg("data"),
      "Body poses and velocities for q (nq) and v (nv) into data.");
  m.def(
      "calc_point_jacobian",
      [](const Model& model, const Data& data, int body, py::handle p_BC) {
        CheckData("calc_point_jacobian", model, data);
        CheckIndex("calc_point_jacobian", "body", body, model.num_bodies());
        Eigen::Matrix3Xd J;
        CalcPointJacobian(model, data, body, ToVector(p_BC, "calc_point_jacobian", "p_BC", 3), &J);
        return ToArray(Eigen::MatrixXd(J));
      },
      py::arg("model"), py::arg("data"), py::arg("body"), py::arg("p_BC"),
      "3 x nv world-aligned Jacobian of point C fixed in body (after forward_kinematics).");
  m.def(
      "calc_frame_jacobian",
      [](const Model& model, const Data& data, int body, py::handle X_BF) {
        CheckData("calc_frame_jacobian", model, data);
        CheckIndex("calc_frame_jacobian", "body", body, model.num_bodies());
        Eigen::Matrix<double, 6, Eigen::Dynamic> J;
        CalcFrameJacobian(model, data, body, ToIsometry(X_BF, "calc_frame_jacobian", "X_BF"), &J);
        return ToArray(Eigen::MatrixXd(J));
      },
      py::arg("model"), py::arg("data"), py::arg("body"), py::arg("X_BF"));
  m.def(
      "integrate",
      [](const Model& model, py::handle q, py::handle v, double dt) {
        Eigen::VectorXd out;
        Integrate(model, Q(model, q, "integrate"), V(model, v, "integrate"), dt, &out);
        return ToArray(out);
      },
      py::arg("model"), py::arg("q"), py::arg("v"), py::arg("dt"));
  m.def(
      "difference",
      [](const Model& model, py::handle q1, py::handle q0) {
        Eigen::VectorXd out;
        Difference(model, Q(model, q1, "difference", "q1"), Q(model, q0, "difference", "q0"), &out);
        return ToArray(out);
      },
      py::arg("model"), py::arg("q1"), py::arg("q0"));
  m.def(
      "normalize_quaternions",
      [](const Model& model, py::handle q) {
        Eigen::VectorXd out = Q(model, q, "normalize_quaternions");
        NormalizeQuaternions(model, &out);
        return ToArray(out);
      },
      py::arg("model"), py::arg("q"), "A copy of q with every quaternion normalized.");
  m.def(
      "calc_n_matrix",
      [](const Model& model, py::handle q) {
        Eigen::MatrixXd N;
        CalcNMatrix(model, Q(model, q, "calc_n_matrix"), &N);
        return ToArray(N);
      },
      py::arg("model"), py::arg("q"));
  m.def(
      "calc_nplus_matrix",
      [](const Model& model, py::handle q) {
        Eigen::MatrixXd N;
        CalcNplusMatrix(model, Q(model, q, "calc_nplus_matrix"), &N);
        return ToArray(N);
      },
      py::arg("model"), py::arg("q"));
}

void BindDynamics(py::module_& m) {
  m.def(
      "inverse_dynamics",
      [](const Model& model, py::handle q, py::handle v, py::handle a, Data& data) {
        static constexpr const char* kWhere = "inverse_dynamics";
        CheckData(kWhere, model, data);
        return ToArray(InverseDynamics(model, Q(model, q, kWhere), V(model, v, kWhere),
                                       V(model, a, kWhere, "a"), &data));
      },
      py::arg("model"), py::arg("q"), py::arg("v"), py::arg("a"), py::arg("data"),
      "tau = M(q) a + C(q, v) v - tau_g(q) + joint damping (nv; no contact).");
  m.def(
      "mass_matrix",
      [](const Model& model, py::handle q, Data& data) {
        CheckData("mass_matrix", model, data);
        return ToArray(MassMatrix(model, Q(model, q, "mass_matrix"), &data));
      },
      py::arg("model"), py::arg("q"), py::arg("data"), "M(q) (nv x nv) by CRBA.");
  m.def(
      "bias_term",
      [](const Model& model, py::handle q, py::handle v, Data& data) {
        CheckData("bias_term", model, data);
        return ToArray(BiasTerm(model, Q(model, q, "bias_term"), V(model, v, "bias_term"), &data));
      },
      py::arg("model"), py::arg("q"), py::arg("v"), py::arg("data"));
  m.def(
      "forward_dynamics",
      [](const Model& model, py::handle q, py::handle v, py::handle tau, Data& data) {
        static constexpr const char* kWhere = "forward_dynamics";
        CheckData(kWhere, model, data);
        return ToArray(ForwardDynamics(model, Q(model, q, kWhere), V(model, v, kWhere),
                                       V(model, tau, kWhere, "tau"), &data));
      },
      py::arg("model"), py::arg("q"), py::arg("v"), py::arg("tau"), py::arg("data"));
}

}  // namespace

void BindModel(py::module_& m) {
  BindUrdf(m);
  py::class_<Model> model(m, "Model", "A tree of rigid bodies (immutable).");
  BindModelQueries(model);
  BindModelIndexed(model);
  BindData(m);
  BindKinematics(m);
  BindDynamics(m);
}

}  // namespace idto::python
