#!/usr/bin/env python3
"""Open-loop trajectory optimization of an example, with a text summary (no plotting).

    PYTHONPATH=build/python python3 examples/python/solve_open_loop.py spinner
    PYTHONPATH=build/python python3 examples/python/solve_open_loop.py quadruped --max-iterations 50
"""

import argparse
import sys

import numpy as np

import idto


def print_iteration(it):
    if it.iteration % 10 == 0:
        print(f"{it.iteration:5d} {it.cost:13.6e} {it.gradient_norm:11.3e} {it.trust_radius:10.3e} "
              f"{it.constraint_violation:11.3e} {'yes' if it.accepted else 'no':>4}")


def print_trajectory(model, traj, time_step, rows=8):
    """A few knots of q, with the coordinate names as headers."""
    names = [model.position_name(i)[:14] for i in range(model.nq())]
    print("      t " + " ".join(f"{n:>14}" for n in names))
    n = traj.q.shape[0]
    for k in sorted(set(np.linspace(0, n - 1, rows + 1).astype(int))):
        print(f"{k * time_step:7.3f} " + " ".join(f"{x:14.5f}" for x in traj.q[k]))


def main(argv=None):
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("example", nargs="?", default="spinner", help="name or YAML file")
    parser.add_argument("--max-iterations", type=int)
    parser.add_argument("--threads", type=int, default=1)
    parser.add_argument("--quiet", action="store_true", help="no iteration table")
    args = parser.parse_args(argv)

    ex = idto.load_example(args.example)
    opts = ex.solver_options
    if args.max_iterations is not None:
        opts.max_iterations = args.max_iterations
    opts.num_threads = args.threads
    problem = ex.problem
    print(f"{ex.name}: nq = {ex.model.nq()}, nv = {ex.model.nv()}, N = {problem.num_steps}, "
          f"dt = {problem.time_step} s, {idto.constraint_method_name(opts.constraint_method)}")
    optimizer = idto.TrajectoryOptimizer(ex.model, problem, opts)
    if not args.quiet:
        print(" iter          cost   |gradient|     radius   violation  acc")
        optimizer.add_callback(print_iteration)
    summary, traj = optimizer.solve(ex.initial_guess())

    print(summary.brief_report())
    print(f"termination: {idto.termination_type_name(summary.termination)} ({summary.message})")
    print(f"cost: {summary.initial_cost:.6e} -> {summary.final_cost:.6e} in "
          f"{summary.iterations} iterations, {1e3 * summary.mean_iteration_time():.3f} ms each")
    print(f"constraint violation: {summary.constraint_violation:.3e}")
    print_trajectory(ex.model, traj, problem.time_step)
    effort = np.abs(traj.tau[:-1]).max(axis=0)
    print("max |tau| per DoF: " + ", ".join(
        f"{ex.model.velocity_name(i)} {effort[i]:.4g}" for i in range(ex.model.nv())))
    print(f"task: {ex.task_success}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
