#!/usr/bin/env python3
"""Closed-loop MPC of the spinner written in Python: the controller re-plans at 200 Hz (one
solver iteration from the warm start) and the plant is stepped at 1 ms from this loop.

    PYTHONPATH=build/python python3 examples/python/mpc_spinner.py [--duration 5] [--plant builtin]
        [--latency SECONDS]

Each new plan drives the robot after the wall-clock time its re-plan took (as idto-run --mpc
does by default), so the result is what this machine achieves in real time; --latency fixes the
delay instead, which makes the run reproducible. Task: the spinner
keeps turning, at least 0.6 rad/s on average (3 rad in 5 s).
"""

import argparse
import sys
import time

import numpy as np

import idto


def run(example="spinner", duration=None, plant=None, latency=None, verbose=True):
    """Runs the closed loop; returns a dict of results.

    latency: None to apply each plan after the wall-clock time its re-plan took, or a fixed delay
    in seconds (the run is then the same on every machine and at any load).
    """
    if latency is not None and not (np.isfinite(latency) and latency >= 0):
        raise ValueError(f"latency: expected a finite delay >= 0 s or None, got {latency!r}")
    ex = idto.load_example(example)
    model, mpc = ex.model, ex.mpc
    if plant is not None:
        mpc.plant = plant
    duration = mpc.closed_loop.duration if duration is None else duration
    sim = ex.make_plant()  # reset to the controller problem's initial state
    controller = idto.Controller(
        ex.mpc_model, ex.mpc_problem, ex.mpc_solver_options, mpc.controller)
    first = controller.initialize(ex.controller_initial_guess(), mpc.initial_iterations)
    if verbose:
        print(f"{ex.name}: plant {sim.name}, {mpc.controller.control_rate:g} Hz, "
              f"{mpc.controller.iterations_per_step} iteration(s) per re-plan, {duration} s")
        print(f"initial plan: {first.brief_report()}")

    # PD+ tracking of the plan in force; its damping term is integrated implicitly by the plant.
    actuated = controller.options.actuated
    gains = controller.options.gains
    pd = idto.PdController(model, actuated, gains)
    kd = np.zeros(model.nv())
    kd[actuated] = gains.Kd[actuated]
    sim.set_extra_damping(kd)

    dt = mpc.closed_loop.plant_time_step
    period = 1.0 / mpc.controller.control_rate
    steps = int(round(duration / dt))
    steps_per_replan = max(1, int(round(period / dt)))
    active, pending, pending_at = controller.plan, None, -1.0
    solve_times, rejected, late = [], 0, 0
    q0 = sim.q
    for step in range(steps):
        t = step * dt
        # A plan due now takes over before a re-plan at this step replaces the pending one (as in
        # idto.run_closed_loop: a delay of exactly one period activates at the next re-plan).
        if pending is not None and t + 1e-12 >= pending_at:
            active, pending = pending, None
        if step > 0 and step % steps_per_replan == 0:
            start = time.perf_counter()
            summary = controller.replan(t, sim.q, sim.v)
            solve = time.perf_counter() - start
            solve_times.append(solve)
            delay = solve if latency is None else latency
            if summary.termination == idto.TerminationType.kFailure:
                rejected += 1  # the plan in force stays
            elif delay > period + 1e-12:
                late += 1  # too late to be used: the plan in force stays
            else:
                pending, pending_at = controller.plan, t + max(delay, dt)
        q_d, v_d, u_ff = active.sample(model, t)
        q, v = sim.q, sim.v
        u = pd.compute(q, v, q_d, v_d, u_ff)
        sim.advance(dt, u + kd * v)

    spinner = ex.mpc_problem.get_unactuated_dofs(model)[0]
    gained = sim.q[spinner] - q0[spinner]
    solve_times = np.array(solve_times)
    result = {
        "angle_gained_rad": gained,
        "mean_rate_rad_s": gained / duration,
        "task_success": gained >= 0.6 * duration,
        "replans": len(solve_times),
        "rejected": rejected,
        "late": late,
        "mean_solve_ms": 1e3 * solve_times.mean(),
        "p95_solve_ms": 1e3 * np.percentile(solve_times, 95),
        "fraction_on_time": float(np.mean(solve_times <= period)),
        "q_final": sim.q,
    }
    if verbose:
        print(f"re-plans: {result['replans']}, rejected: {rejected}, late: {late}, solve time mean "
              f"{result['mean_solve_ms']:.3f} ms, p95 {result['p95_solve_ms']:.3f} ms, on time "
              f"{100 * result['fraction_on_time']:.1f} % (period {1e3 * period:.1f} ms)")
        print(f"spinner angle gained: {gained:.3f} rad ({result['mean_rate_rad_s']:.3f} rad/s); "
              f"task_success: {result['task_success']} (>= 0.6 rad/s)")
    return result


def main(argv=None):
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--duration", type=float)
    parser.add_argument("--plant", choices=["builtin", "mujoco"])
    parser.add_argument("--latency", type=float,
                        help="fixed plan delay in s (default: the measured re-plan time)")
    args = parser.parse_args(argv)
    result = run(duration=args.duration, plant=args.plant, latency=args.latency)
    return 0 if result["task_success"] else 1


if __name__ == "__main__":
    sys.exit(main())
