"""load_example, ProblemDefinition, SolverOptions, TrajectoryOptimizer and SolverSummary."""

import copy
import json
import os
import subprocess

import numpy as np
import pytest

import idto
from conftest import ROOT, short_options


def test_load_example(spinner):
    ex = spinner
    assert ex.name == "spinner" and ex.source_file.endswith("spinner.yaml")
    assert ex.description and ex.task_success and "spinner" in repr(ex)
    assert ex.model.nq() == 3 and ex.problem.num_steps == 40
    assert ex.solver_options.constraint_method == idto.ConstraintMethod.kLagrangeMultipliers
    assert ex.initial_guess_type == idto.InitialGuessType.kConstant
    guess = ex.initial_guess()
    assert guess.shape == (41, 3) and guess.dtype == np.float64
    assert ex.controller_initial_guess().shape == (41, 3)
    assert ex.mpc.controller.control_rate == 200 and ex.mpc.initial_iterations == 100
    assert ex.mpc.closed_loop.duration == 5.0
    assert ex.mpc.plant in ("mujoco", "builtin")
    assert ex.mpc_problem.num_steps == 40 and ex.mpc_solver_options.max_iterations == 300
    # No mpc.model_mass_scale: the controller plans with the scene's model.
    assert ex.mpc_model.nq() == ex.model.nq() and ex.mpc_model.body_names() == ex.model.body_names()
    assert "spinner" in idto.list_examples(idto.default_share_dirs())
    path = idto.find_example_config("spinner", idto.default_share_dirs())
    assert idto.load_example(path).name == "spinner"
    np.testing.assert_allclose(
        idto.interpolate_configuration(ex.model, guess[0], guess[0] + 1, 0.5), guess[0] + 0.5)


def test_load_example_errors(tmp_path):
    with pytest.raises(OSError, match="no_such_example"):
        idto.load_example("no_such_example")
    bad = tmp_path / "bad.yaml"
    bad.write_text("scene: {models: []}\nproblem: {time_step: -0.05, horizon: 1}\n")
    with pytest.raises(idto.FileError, match="bad.yaml"):
        idto.load_example(str(bad))


def test_problem_and_options_attributes(spinner):
    p = copy.copy(spinner.problem)
    p.time_step = 0.1
    assert spinner.problem.time_step == 0.05 and p.time_step == 0.1
    assert p.q_init.shape == (3,) and p.v_init.shape == (3,)
    assert isinstance(p.q_nom, list) and len(p.q_nom) == 41 and p.q_nom[0].shape == (3,)
    p.q_nom = np.zeros((41, 3))
    assert all(x.tolist() == [0, 0, 0] for x in p.q_nom)
    p.v_nom = [np.zeros(3)] * 41
    for name in ("Qq", "Qv", "R", "Qfq", "Qfv"):
        setattr(p, name, np.arange(3.0))
        np.testing.assert_array_equal(getattr(p, name), [0, 1, 2])
    p.unactuated_dofs = [2]
    assert p.unactuated_dofs == [2] and p.get_unactuated_dofs(spinner.model) == [2]
    p.unactuated_dofs = None
    assert p.get_unactuated_dofs(spinner.model) == []
    p.enable_contact = False
    p.contact.parameters.stiffness = 123.0
    assert p.contact.parameters.stiffness == 123.0
    p.contact.force_tolerance = 0.0
    p.contact.excluded_pairs = [("a", "b")]
    p.contact.collision_groups = [["a", "b"]]
    p.contact.included_pairs = []
    o = idto.ContactParameterOverride()
    o.a, o.b, o.stiffness = "a", "*", 10.0
    p.contact.overrides = [o]
    assert p.contact.overrides[0].stiffness == 10.0 and o.smoothing is None
    p.validate(spinner.model)
    p.time_step = -1.0
    with pytest.raises(ValueError, match="time_step"):
        p.validate(spinner.model)
    with pytest.raises(ValueError, match="q_init is an array of shape"):
        p.q_init = np.zeros((3, 2))
    with pytest.raises(ValueError, match="contact.parameters|stiffness"):
        c = idto.ContactParameters()
        c.stiffness = -1
        c.validate()
    d = idto.ProblemDefinition.make_default(spinner.model, 0.1, 10)
    d.set_constant_nominal(np.ones(3), np.zeros(3))
    assert len(d.q_nom) == 11 and d.q_nom[5].tolist() == [1, 1, 1]
    d.validate(spinner.model)

    s = idto.SolverOptions()
    assert s.max_iterations == 100 and s.is_valid() and s.invalid_reason() == ""
    assert s.trial_derivatives and s.constraint_correction == 0.5
    for name, value in [("num_threads", 2), ("penalty_weight", 1.0), ("fixed_iterations", True),
                        ("trial_derivatives", False), ("constraint_correction", 2.0),
                        ("finite_difference_step", 1e-6), ("initial_trust_radius", 0.2),
                        ("max_trust_radius", 10.0), ("acceptance_ratio", 0.1),
                        ("cost_tolerance", 0.0), ("gradient_tolerance", 0.0),
                        ("step_tolerance", 0.0), ("verbosity", 0),
                        ("constraint_method", idto.ConstraintMethod.kNone),
                        ("derivative_method", idto.DerivativeMethod.kCentralDifferences),
                        ("scaling", idto.ScalingMethod.kSqrt)]:
        setattr(s, name, value)
        assert getattr(s, name) == value
    s.max_iterations = -1
    assert not s.is_valid() and "max_iterations" in s.invalid_reason()
    assert idto.constraint_method_name(idto.ConstraintMethod.kPenalty) == "penalty"


def test_solve_shapes_summary_and_trajectory(spinner):
    ex = spinner
    opts = short_options(ex, 5)
    opt = idto.TrajectoryOptimizer(ex.model, ex.problem, opts)
    summary, traj = opt.solve(ex.initial_guess())
    assert isinstance(summary, idto.SolverSummary) and isinstance(traj, idto.Trajectory)
    assert traj.q.shape == (41, 3) and traj.v.shape == (41, 3) and traj.tau.shape == (41, 3)
    assert len(traj) == 41
    assert summary.iterations == 5 and len(summary.log) == 5
    assert summary.termination == idto.TerminationType.kMaxIterations
    assert idto.termination_type_name(summary.termination) == "max_iterations"
    assert summary.final_cost < summary.initial_cost and summary.solve_time > 0
    assert summary.costs.shape == (5,) and summary.costs[0] == summary.log[0].cost
    it = summary.log[-1]
    assert isinstance(it, idto.IterationSummary) and it.iteration == 4
    for name in ("merit", "gradient_norm", "step_norm", "scaled_step_norm", "correction_norm",
                 "trust_radius",
                 "ratio", "constraint_violation", "trial_cost", "regularization",
                 "time_derivatives", "time_cost", "time_hessian", "time_factorization",
                 "time_multipliers", "time_total", "time_contact"):
        assert isinstance(getattr(it, name), float)
    assert isinstance(it.accepted, bool) and isinstance(it.step_type, idto.DoglegStep)
    assert all(isinstance(i.growth_guard, bool) for i in summary.log)
    # The last iteration's trial point has no next iteration to bring derivatives to.
    assert it.trial_with_derivatives is False and summary.log[0].trial_with_derivatives is True
    assert summary.mean_iteration_time() > 0
    assert "max_iterations" in summary.brief_report() or summary.brief_report()
    assert len(summary.full_report()) > len(summary.brief_report())
    assert summary.to_csv().count("\n") == 6
    assert summary.constraint_violation >= 0 and summary.message is not None
    assert repr(summary).startswith("<idto.SolverSummary")
    # q_0 is replaced by q_init; the guess as a list of rows works too.
    np.testing.assert_array_equal(traj.q[0], ex.problem.q_init)
    summary2, traj2 = idto.TrajectoryOptimizer(ex.model, ex.problem, opts).solve(
        list(ex.initial_guess()))
    np.testing.assert_array_equal(traj.q, traj2.q)
    t = idto.Trajectory()
    t.q, t.v, t.tau = traj.q, traj.v, traj.tau
    np.testing.assert_array_equal(t.q, traj.q)


def test_optimizer_methods(spinner):
    ex = spinner
    opts = short_options(ex, 3)
    opt = idto.TrajectoryOptimizer(ex.model, ex.problem, opts)
    assert opt.model.nq() == 3 and opt.problem.num_steps == 40
    assert opt.options.max_iterations == 3
    opt.options.max_iterations = 2
    assert opt.options.max_iterations == 2
    bad = idto.SolverOptions()
    bad.max_iterations = -3
    with pytest.raises(ValueError):
        opt.options = bad
    q = ex.initial_guess()
    cost = opt.eval_cost(q)
    assert isinstance(cost, float) and cost > 0
    g = opt.eval_gradient(q)
    assert g.shape == (40 * 3,)
    H = opt.eval_dense_hessian(q)
    assert H.shape == (120, 120)
    h = opt.eval_constraints(q)
    assert h.shape == (40,)
    tr = opt.eval_trajectory(q)
    assert tr.q.shape == (41, 3) and tr.tau.shape[1] == 3
    opt.set_iterate(q)
    s1, t1 = opt.solve_warm_start()
    assert s1.iterations == 2 and t1.q.shape == (41, 3)
    assert opt.trust_radius() > 0
    opt.reset_initial_conditions(q[0] + 0.01, np.zeros(3))
    opt.update_nominal_trajectory(np.array(ex.problem.q_nom), np.array(ex.problem.v_nom))
    s2, t2 = opt.solve_warm_start()
    np.testing.assert_allclose(t2.q[0], q[0] + 0.01)


def test_shape_errors_name_argument_and_shape(spinner):
    ex = spinner
    opt = idto.TrajectoryOptimizer(ex.model, ex.problem, short_options(ex, 1))
    with pytest.raises(ValueError, match=r"q_guess is an array of shape \(40, 3\); expected "
                                         r"shape \(41, 3\) \(N \+ 1, nq\)"):
        opt.solve(np.zeros((40, 3)))
    with pytest.raises(ValueError, match=r"q_guess is an array of shape \(123,\)"):
        opt.solve(np.zeros(123))
    with pytest.raises(ValueError, match="q_guess.*dtype"):
        opt.solve(np.zeros((41, 3), dtype=complex))
    with pytest.raises(ValueError, match="q_guess"):
        opt.solve([[0.0, 0.0, 0.0]] * 40 + [[0.0]])
    with pytest.raises(ValueError, match="v_init"):
        opt.reset_initial_conditions(np.zeros(3), np.zeros(4))
    with pytest.raises(ValueError, match="v_nom"):
        opt.update_nominal_trajectory(np.zeros((41, 3)), np.zeros((41, 2)))
    for fn in (opt.set_iterate, opt.eval_cost, opt.eval_gradient, opt.eval_constraints,
               opt.eval_trajectory, opt.eval_dense_hessian):
        with pytest.raises(ValueError, match=r"\(N \+ 1, nq\)"):
            fn(np.zeros((41, 2)))
    with pytest.raises(ValueError, match="q_guess"):
        opt.solve(np.full((41, 3), np.nan))
    p = copy.copy(ex.problem)
    p.num_steps = 0
    with pytest.raises(ValueError, match="num_steps"):
        idto.TrajectoryOptimizer(ex.model, p, idto.SolverOptions())


def test_callbacks(spinner):
    ex = spinner
    opt = idto.TrajectoryOptimizer(ex.model, ex.problem, short_options(ex, 10))
    seen = []
    opt.add_callback(lambda it: seen.append(it.iteration))
    opt.add_callback(lambda it: False if it.iteration == 3 else None)
    summary, _ = opt.solve(ex.initial_guess())
    assert seen == [0, 1, 2, 3] and summary.iterations == 4
    assert summary.termination == idto.TerminationType.kUserTermination

    opt = idto.TrajectoryOptimizer(ex.model, ex.problem, short_options(ex, 10))
    opt.add_callback(lambda it: idto.CallbackReturn.kAbort if it.iteration == 1
                     else idto.CallbackReturn.kContinue)
    summary, _ = opt.solve(ex.initial_guess())
    assert summary.iterations == 2 and "abort" in summary.message
    assert summary.termination == idto.TerminationType.kUserAbort

    opt = idto.TrajectoryOptimizer(ex.model, ex.problem, short_options(ex, 10))
    calls = []

    def failing(it):
        calls.append(it.iteration)
        if it.iteration == 2:
            raise ZeroDivisionError("from the callback")
    opt.add_callback(failing)
    with pytest.raises(ZeroDivisionError, match="from the callback"):
        opt.solve(ex.initial_guess())
    assert calls == [0, 1, 2]
    opt2 = idto.TrajectoryOptimizer(ex.model, ex.problem, short_options(ex, 3))
    opt2.add_callback(lambda it: 42)
    with pytest.raises(TypeError, match="callback"):
        opt2.solve(ex.initial_guess())
    with pytest.raises(TypeError):
        opt2.add_callback(3)
    # The optimizer is usable after an exception: the next solve runs normally.
    ok = idto.TrajectoryOptimizer(ex.model, ex.problem, short_options(ex, 2))
    assert ok.solve(ex.initial_guess())[0].iterations == 2


def test_bit_equal_to_cpp_helper(spinner):
    ex = spinner
    opts = short_options(ex, 8)
    summary, traj = idto.TrajectoryOptimizer(ex.model, ex.problem, opts).solve(ex.initial_guess())
    cpp_summary, cpp_traj = idto._testing.solve_in_cpp(ex.model, ex.problem, opts,
                                                       ex.initial_guess())
    assert np.array_equal(traj.q, cpp_traj.q) and np.array_equal(traj.tau, cpp_traj.tau)
    assert [it.cost for it in summary.log] == [it.cost for it in cpp_summary.log]
    assert summary.final_cost == cpp_summary.final_cost


@pytest.mark.skipif(not os.environ.get("IDTO_RUN"), reason="idto-run not built (IDTO_RUN)")
@pytest.mark.parametrize("example,iterations", [("spinner", 12), ("quadruped", 3)])
def test_bit_equal_to_idto_run(tmp_path, example, iterations):
    out = tmp_path / "summary.json"
    subprocess.run([os.environ["IDTO_RUN"], example, "--quiet", "--max-iterations",
                    str(iterations), "--summary-json", str(out)], check=True,
                   cwd=ROOT, stdout=subprocess.DEVNULL)
    ref = json.loads(out.read_text())
    ex = idto.load_example(example)
    opts = ex.solver_options
    opts.max_iterations = iterations
    summary, traj = idto.TrajectoryOptimizer(ex.model, ex.problem, opts).solve(ex.initial_guess())
    assert ref["iterations"] == summary.iterations
    assert traj.q[-1].tolist() == ref["q_final"]
    assert traj.v[-1].tolist() == ref["v_final"]
    assert summary.final_cost == ref["final_cost"]
    assert [it.cost for it in summary.log] == [it["cost"] for it in ref["log"]]


def test_readme_example_runs(capsys):
    with open(os.path.join(ROOT, "README.md")) as f:
        readme = f.read()
    code = readme.split("```python\n", 1)[1].split("```", 1)[0]
    assert len(code.strip().splitlines()) <= 10
    exec(compile(code, "README.md", "exec"), {})
    assert "idto:" in capsys.readouterr().out


def test_overhead_benchmark_runs(capsys):
    import importlib.util
    path = os.path.join(ROOT, "benchmarks", "python", "overhead.py")
    spec = importlib.util.spec_from_file_location("overhead", path)
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    assert module.main(["--example", "pendulum", "--rounds", "3", "--json"]) == 0
    result = json.loads(capsys.readouterr().out)
    assert result["calls_each"] == 3 and result["cpu"]["cpp_median_ms"] > 0
    ex = idto.load_example("pendulum")
    opt = idto.TrajectoryOptimizer(ex.model, ex.problem, short_options(ex, 2))
    opt.solve(ex.initial_guess())
    times = idto._testing.time_warm_start(opt, 2)
    assert len(times) == 2 and all(wall >= 0 and cpu >= 0 for wall, cpu in times)


def test_limit_penalties_from_yaml_and_python():
    config = idto.load_example("quadruped_limits")
    limits = config.problem.limits
    assert limits.any()
    assert limits.position_weight == 1e4
    assert len(limits.tau_max) == config.model.nv()
    fresh = idto.LimitPenalties()
    assert not fresh.any() and len(fresh.tau_max) == 0
    fresh.effort_weight = 10.0
    fresh.tau_max = np.full(config.model.nv(), 3.0)
    problem = copy.copy(config.problem)
    problem.limits = fresh
    problem.validate(config.model)
    fresh.tau_max = np.ones(2)
    problem.limits = fresh
    with pytest.raises(ValueError, match="limits.tau_max"):
        problem.validate(config.model)


def test_contact_options_that_would_change_nothing_are_errors(spinner):
    # The checks of the YAML loader hold for options set from Python too: an override of a
    # geometry against itself matches no pair, so it would change nothing.
    g = spinner.model.geometry_names()[0]
    p = copy.copy(spinner.problem)
    o = idto.ContactParameterOverride()
    o.a, o.b, o.stiffness = g, g, 10.0
    p.contact.overrides = [o]
    with pytest.raises(ValueError, match=r"options\.overrides\[0\] is \[.*\]; expected a pair "
                                         r"whose parameters it would change"):
        idto.TrajectoryOptimizer(spinner.model, p, short_options(spinner, 1))
    p.contact.overrides = []
    p.contact.collision_groups = [[g]]
    with pytest.raises(ValueError, match=r"options\.collision_groups\[0\] is a list of one name"):
        idto.TrajectoryOptimizer(spinner.model, p, short_options(spinner, 1))
