"""Models, Data and the dynamics kernels; error mapping and argument checks."""

import warnings

import numpy as np
import pytest

import idto
from conftest import model_path


def test_parse_urdf_fixed_and_queries():
    model = idto.parse_urdf(model_path("pendulum.urdf"))
    assert (model.nq(), model.nv()) == (1, 1)
    # world, base (welded to the world by "base_root_joint") and arm.
    assert model.num_bodies() == 3 and model.num_joints() == 2
    assert model.body_names() == ["world", "base", "arm"]
    assert model.joint_names() == ["", "base_root_joint", "pivot"]
    b = model.get_body_index("arm")
    assert model.body_name(b) == "arm" and model.has_body("arm") and not model.has_body("x")
    assert model.get_position_start("pivot") == 0 and model.get_velocity_start("pivot") == 0
    j = model.get_joint_index("pivot")
    assert model.joint_name(j) == "pivot" and model.joint_type(j) == idto.JointType.kContinuous
    assert model.joint_nq(j) == 1 and model.joint_nv(j) == 1
    assert model.position_start(j) == 0 and model.velocity_start(j) == 0
    assert model.position_name(0) == "pivot" and model.velocity_name(0) == "pivot"
    assert model.parent(b) == 1 and model.mobilized_body(b) == b
    assert model.body_mass(b) == pytest.approx(1.0) and model.total_mass() == pytest.approx(1.0)
    assert model.damping().tolist() == [0.1]
    np.testing.assert_array_equal(model.gravity(), [0, 0, -9.81])
    assert model.effort_limits().shape == (1,)
    assert model.lower_position_limits().shape == (1,)
    assert model.upper_position_limits().shape == (1,)
    assert model.neutral_configuration().tolist() == [0.0]
    assert not model.has_quaternions() and model.floating_joints() == []
    assert model.is_base_velocity() == [False]
    assert model.num_frames() >= 2 and model.frame_name(model.get_frame_index("arm")) == "arm"
    assert model.frame_body(model.get_frame_index("arm")) == b and model.has_frame("arm")
    assert "arm" in model.frame_names()
    assert model.num_geometries() == 0 and model.geometry_names() == []
    assert model.num_moving_bodies() == 1 and model.name() == "pendulum"
    assert "pendulum" in repr(model)


def test_parse_urdf_floating_options(quadruped_model):
    m = quadruped_model
    assert m.nq() == m.nv() + 1 and m.has_quaternions()
    assert m.is_base_velocity()[:6] == [True] * 6
    opts = idto.UrdfOptions()
    opts.base = idto.BaseType.kFloating
    X = np.eye(4)
    X[:3, 3] = [0.0, 0.0, 0.5]
    opts.X_WB = X
    opts.prefix = "a_"
    opts.model_name = "named"
    opts.planar_normal = [0, 0, 1]
    assert opts.box_inscribed_spheres is None
    spheres = idto.InscribedSpheresOptions()
    spheres.num_per_axis, spheres.radius_fraction = 2, 0.25
    opts.box_inscribed_spheres = spheres
    np.testing.assert_array_equal(opts.X_WB, X)
    np.testing.assert_array_equal(opts.planar_normal, [0, 0, 1])
    m2 = idto.parse_urdf(model_path("quadruped.urdf"), opts)
    assert m2.name() == "named" and all(n.startswith("a_") for n in m2.body_names()[1:])
    with open(model_path("pendulum.urdf")) as f:
        text = f.read()
    assert idto.parse_urdf_string(text).nq() == 1


def test_urdf_errors_map_to_python_exceptions(tmp_path):
    with pytest.raises(OSError) as e:
        idto.parse_urdf(str(tmp_path / "missing.urdf"))
    assert "missing.urdf" in str(e.value)
    assert isinstance(e.value, RuntimeError) and isinstance(e.value, idto.FileError)
    assert e.value.file.endswith("missing.urdf")
    bad = tmp_path / "bad.urdf"
    bad.write_text("<robot name='x'><link name='a'/><joint name='j' type='continuous'>"
                   "<parent link='a'/><child link='b'/><axis xyz='0 0 0'/></joint>"
                   "<link name='b'><inertial><mass value='1'/><inertia ixx='1' ixy='0' "
                   "ixz='0' iyy='1' iyz='0' izz='1'/></inertial></link></robot>")
    with pytest.raises(idto.FileError) as e:
        idto.parse_urdf(str(bad))
    assert "bad.urdf" in str(e.value) and "axis" in str(e.value)
    model = idto.parse_urdf(model_path("pendulum.urdf"))
    with pytest.raises(ValueError, match="no_such_link"):
        model.get_body_index("no_such_link")
    with pytest.raises(ValueError, match="no_such_joint"):
        model.get_position_start("no_such_joint")
    with pytest.raises(IndexError, match="body"):
        model.body_name(7)
    with pytest.raises(IndexError):
        model.joint_type(-1)
    bad_X = np.eye(4)
    bad_X[0, 0] = 2.0
    with pytest.raises(ValueError, match="X_WB"):
        idto.UrdfOptions().X_WB = bad_X


def test_urdf_warnings_are_python_warnings():
    # box.urdf on a fixed base: its mass does not move. Reported, not lost.
    with pytest.warns(UserWarning, match="box.urdf: link 'box': mass 0.55 ignored"):
        model = idto.parse_urdf(model_path("box.urdf"))
    assert model.nq() == 0
    with pytest.warns(UserWarning, match="attribute colour=\"red\" of <link>"):
        idto.parse_urdf_string("<robot name='r'><link name='a' colour='red'/></robot>",
                               idto.UrdfOptions(), "case.urdf")
    # The warnings module decides what becomes of them, errors included.
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        with pytest.raises(UserWarning, match="box.urdf"):
            idto.parse_urdf(model_path("box.urdf"))
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        idto.parse_urdf(model_path("pendulum.urdf"))  # nothing to report
    # A scene's: listed on the Example (both arms of the bimanual scene sit on a massive base).
    assert idto.load_example("pendulum").urdf_warnings == []
    bimanual = idto.load_example("bimanual").urdf_warnings
    # One file loaded twice: each warning names the prefixed link of the scene it is about.
    assert len(bimanual) == 2
    for w, prefix in zip(bimanual, ("left_", "right_")):
        assert f"jaco_arm.urdf: link 'base' (the model's link '{prefix}base'): mass" in w, w


def test_kinematics_dynamics_jacobians(quadruped_model):
    m = quadruped_model
    data = idto.Data(m)
    rng = np.random.default_rng(1)
    q = m.neutral_configuration()
    q[4:7] = [0.1, -0.2, 0.4]
    q[7:] = rng.uniform(-0.5, 0.5, m.nq() - 7)
    v = rng.normal(size=m.nv())
    a = rng.normal(size=m.nv())
    idto.forward_kinematics(m, q, data)
    X = data.X_WB(1)
    assert X.shape == (4, 4)
    np.testing.assert_allclose(X[:3, 3], [0.1, -0.2, 0.4])
    idto.forward_kinematics(m, q, v, data)
    body = m.num_bodies() - 1
    np.testing.assert_allclose(data.V_WB(body), np.concatenate([data.w_WB(body),
                                                                data.v_WBo(body)]))
    np.testing.assert_allclose(data.R_WB(body), data.X_WB(body)[:3, :3])
    np.testing.assert_allclose(data.p_WB(body), data.X_WB(body)[:3, 3])
    assert data.X_WF(m, m.get_frame_index(m.body_name(body))).shape == (4, 4)
    J = idto.calc_point_jacobian(m, data, body, [0.0, 0.0, -0.1])
    assert J.shape == (3, m.nv())
    Jf = idto.calc_frame_jacobian(m, data, body, np.eye(4))
    assert Jf.shape == (6, m.nv())
    np.testing.assert_allclose(Jf[3:] @ v, data.v_WBo(body), atol=1e-12)
    M = idto.mass_matrix(m, q, data)
    assert M.shape == (m.nv(), m.nv())
    np.testing.assert_allclose(M, M.T)
    np.testing.assert_array_equal(data.M, M)
    bias = idto.bias_term(m, q, v, data)
    tau = idto.inverse_dynamics(m, q, v, a, data)
    np.testing.assert_array_equal(data.tau, tau)
    np.testing.assert_allclose(tau, M @ a + bias, rtol=1e-9, atol=1e-9)
    acc = idto.forward_dynamics(m, q, v, tau, data)
    np.testing.assert_allclose(acc, a, atol=1e-8)
    np.testing.assert_array_equal(data.a, acc)
    N = idto.calc_n_matrix(m, q)
    Np = idto.calc_nplus_matrix(m, q)
    assert N.shape == (m.nq(), m.nv()) and Np.shape == (m.nv(), m.nq())
    np.testing.assert_allclose(Np @ N, np.eye(m.nv()), atol=1e-12)
    q1 = idto.integrate(m, q, v, 0.01)
    np.testing.assert_allclose(idto.difference(m, q1, q), 0.01 * v, atol=1e-12)
    qn = q.copy()
    qn[:4] *= 3.0
    np.testing.assert_allclose(np.linalg.norm(idto.normalize_quaternions(m, qn)[:4]), 1.0)


def test_same_results_as_repeated_calls(quadruped_model):
    # The bindings call the C++ kernels on copies of the inputs: bit-equal across dtypes.
    m = quadruped_model
    data = idto.Data(m)
    q = m.neutral_configuration()
    tau1 = idto.inverse_dynamics(m, q, np.zeros(m.nv()), np.ones(m.nv()), data)
    tau2 = idto.inverse_dynamics(m, list(q), [0] * m.nv(), np.ones(m.nv(), dtype=np.int32), data)
    np.testing.assert_array_equal(tau1, tau2)


def test_shape_and_dtype_errors(quadruped_model):
    m = quadruped_model
    data = idto.Data(m)
    nq, nv = m.nq(), m.nv()
    with pytest.raises(ValueError, match=r"q is an array of shape \(3,\); expected shape "
                                         rf"\({nq},\) \(nq\)"):
        idto.forward_kinematics(m, np.zeros(3), data)
    with pytest.raises(ValueError, match=r"v is an array of shape"):
        idto.inverse_dynamics(m, np.zeros(nq), np.zeros((nv, 1)), np.zeros(nv), data)
    with pytest.raises(ValueError, match="dtype complex128"):
        idto.mass_matrix(m, np.zeros(nq, dtype=complex), data)
    with pytest.raises(ValueError, match="real numbers"):
        idto.mass_matrix(m, ["a"] * nq, data)
    with pytest.raises(ValueError, match="p_BC"):
        idto.forward_kinematics(m, m.neutral_configuration(), data)
        idto.calc_point_jacobian(m, data, 1, [0.0, 0.0])
    other = idto.parse_urdf(model_path("pendulum.urdf"))
    with pytest.raises(ValueError, match="Data of another model"):
        idto.mass_matrix(m, m.neutral_configuration(), idto.Data(other))
    with pytest.raises(IndexError):
        data.X_WB(1000)
    with pytest.raises(IndexError):
        idto.calc_point_jacobian(m, data, -1, [0, 0, 0])
