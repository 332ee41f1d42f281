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
          time.perf_counter().
Prints the median and minimum time per call of each path, their ratios, and the median of the
per-pair ratios (a Python call over the C++ call just before it).
"""

import argparse
import json
import statistics
import sys
import time

import idto


def measure(example, rounds, block, warmup_iterations):
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
            start = time.perf_counter()
            summary, traj = opt.solve_warm_start()
            traj.q
            python.append(time.perf_counter() - start)
    assert summary.iterations == 1
    return cpp, python


def main(argv=None):
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--example", default="quadruped")
    parser.add_argument("--rounds", type=int, default=300)
    parser.add_argument("--block", type=int, default=1)
    parser.add_argument("--warmup-iterations", type=int, default=20)
    parser.add_argument("--json", action="store_true", help="print the result as JSON")
    args = parser.parse_args(argv)
    cpp, python = measure(args.example, args.rounds, args.block, args.warmup_iterations)
    result = {
        "example": args.example,
        "calls_each": len(cpp),
        "cpp_median_ms": 1e3 * statistics.median(cpp),
        "python_median_ms": 1e3 * statistics.median(python),
        "cpp_mean_ms": 1e3 * statistics.fmean(cpp),
        "python_mean_ms": 1e3 * statistics.fmean(python),
    }
    result["cpp_min_ms"] = 1e3 * min(cpp)
    result["python_min_ms"] = 1e3 * min(python)
    result["ratio_median"] = result["python_median_ms"] / result["cpp_median_ms"]
    result["ratio_min"] = result["python_min_ms"] / result["cpp_min_ms"]
    result["ratio_pairs_median"] = statistics.median(p / c for p, c in zip(python, cpp))
    result["overhead_median_us"] = 1e3 * (result["python_median_ms"] - result["cpp_median_ms"])
    if args.json:
        print(json.dumps(result))
    else:
        print(f"{args.example}: one warm-start iteration, {len(cpp)} calls each, alternated")
        print(f"  C++    median {result['cpp_median_ms']:.4f} ms (mean {result['cpp_mean_ms']:.4f})")
        print(f"  Python median {result['python_median_ms']:.4f} ms "
              f"(mean {result['python_mean_ms']:.4f})")
        print(f"  C++    min {result['cpp_min_ms']:.4f} ms, Python min {result['python_min_ms']:.4f} ms")
        print(f"  Python / C++: medians {result['ratio_median']:.4f} "
              f"({result['overhead_median_us']:+.1f} us per call), minimums "
              f"{result['ratio_min']:.4f}, median of pair ratios {result['ratio_pairs_median']:.4f}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
