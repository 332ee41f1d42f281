#!/usr/bin/env python3
"""Overhead of the Python bindings: one warm-start iteration of an example (default: the
quadruped) called from Python vs the same call made from C++, in the same process.

    PYTHONPATH=build/python python3 benchmarks/python/overhead.py [--example quadruped]

Both paths drive the same TrajectoryOptimizer (fixed_iterations, max_iterations = 1, one
thread), alternating call by call (blocks of --block calls) so that machine load affects both
alike:
  C++:    idto._testing.time_warm_start(opt, block): SolveWarmStart timed in a C++ loop;
  Python: summary, traj = opt.solve_warm_start(); traj.q  (GIL release, signal check,
          conversion of the summary and the trajectory to Python objects), timed with
          time.perf_counter() and time.thread_time().
Prints, for wall-clock time and for the calling thread's CPU time (with one thread the solve
runs on the calling thread; CPU time is what a loaded, shared machine distorts least), the
median and minimum time per call of each path, their ratios, and the median of the per-pair
ratios (a Python call over the C++ call just before it).
"""

import argparse
import json
import statistics
import sys
import time

import idto


def measure(example, rounds, block, warmup_iterations):
    """Lists of (wall, thread CPU) seconds per call: C++ and Python."""
    ex = idto.load_example(example)
    opts = ex.solver_options
    opts.num_threads = 1
    opts.max_iterations = warmup_iterations
    opt = idto.TrajectoryOptimizer(ex.model, ex.problem, opts)
    opt.solve(ex.initial_guess())  # a realistic iterate for the warm starts
    opt.options.max_iterations = 1
    opt.options.fixed_iterations = True
    cpp, python = [], []
    for _ in range(rounds):
        cpp.extend(idto._testing.time_warm_start(opt, block))
        for _ in range(block):
            start, start_cpu = time.perf_counter(), time.thread_time()
            summary, traj = opt.solve_warm_start()
            traj.q
            python.append((time.perf_counter() - start, time.thread_time() - start_cpu))
    assert summary.iterations == 1
    return cpp, python


def summarize(cpp, python):
    med_c, med_p = statistics.median(cpp), statistics.median(python)
    return {
        "cpp_median_ms": 1e3 * med_c,
        "python_median_ms": 1e3 * med_p,
        "cpp_min_ms": 1e3 * min(cpp),
        "python_min_ms": 1e3 * min(python),
        "ratio_median": med_p / med_c,
        "ratio_min": min(python) / min(cpp),
        "ratio_pairs_median": statistics.median(p / c for c, p in zip(cpp, python)),
        "overhead_median_us": 1e6 * (med_p - med_c),
    }


def main(argv=None):
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--example", default="quadruped")
    parser.add_argument("--rounds", type=int, default=300)
    parser.add_argument("--block", type=int, default=1)
    parser.add_argument("--warmup-iterations", type=int, default=20)
    parser.add_argument("--json", action="store_true", help="print the result as JSON")
    args = parser.parse_args(argv)
    cpp, python = measure(args.example, args.rounds, args.block, args.warmup_iterations)
    result = {"example": args.example, "calls_each": len(cpp)}
    for clock, index in (("wall", 0), ("cpu", 1)):
        result[clock] = summarize([x[index] for x in cpp], [x[index] for x in python])
    if args.json:
        print(json.dumps(result))
        return 0
    print(f"{args.example}: one warm-start iteration, {len(cpp)} calls each, alternated")
    for clock, title in (("wall", "wall-clock"), ("cpu", "thread CPU time")):
        r = result[clock]
        print(f"  {title}: C++ median {r['cpp_median_ms']:.4f} ms (min {r['cpp_min_ms']:.4f}), "
              f"Python median {r['python_median_ms']:.4f} ms (min {r['python_min_ms']:.4f})")
        print(f"    Python / C++: medians {r['ratio_median']:.4f} "
              f"({r['overhead_median_us']:+.1f} us per call), minimums {r['ratio_min']:.4f}, "
              f"median of pair ratios {r['ratio_pairs_median']:.4f}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
