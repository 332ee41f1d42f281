"""The GIL is released during solves; Ctrl-C stops a long solve cleanly."""

import os
import signal
import threading
import time

import pytest

import idto
from conftest import short_options


def endless_options(example):
    opts = short_options(example, 1000000)
    opts.fixed_iterations = True  # no convergence test: runs until stopped
    return opts


def test_solve_on_a_thread_while_python_runs(spinner):
    ex = spinner
    opt = idto.TrajectoryOptimizer(ex.model, ex.problem, endless_options(ex))
    iterations = []
    stop = threading.Event()
    opt.add_callback(lambda it: (iterations.append(it.iteration), not stop.is_set())[1])
    result = []
    worker = threading.Thread(target=lambda: result.append(opt.solve(ex.initial_guess())))
    worker.start()
    while not iterations:
        time.sleep(0.001)
    # Pure Python on this thread while the solve runs on the worker.
    done_before = len(iterations)
    count, end = 0, time.perf_counter() + 0.5
    while time.perf_counter() < end:
        count += 1
    done_during = len(iterations) - done_before
    alive = worker.is_alive()
    stop.set()
    worker.join(timeout=60)
    assert alive and not worker.is_alive()
    assert count > 10000, "the Python thread made no progress during the solve"
    assert done_during > 0, "the solve made no progress while Python ran"
    summary, traj = result[0]
    assert summary.termination == idto.TerminationType.kUserTermination
    assert traj.q.shape == (41, 3)


def test_python_thread_runs_during_solve_on_main_thread(spinner):
    ex = spinner
    # 600 iterations (about 0.1 s): long against the scheduler's delays on a loaded machine (with
    # 60, about 10 ms, the thread was once not scheduled at all during the solve under ctest -j2).
    opts = short_options(ex, 600)
    opts.fixed_iterations = True
    opt = idto.TrajectoryOptimizer(ex.model, ex.problem, opts)
    counter = [0]
    stop = threading.Event()
    running = threading.Event()

    def spin():
        running.set()
        while not stop.is_set():
            counter[0] += 1
    thread = threading.Thread(target=spin)
    thread.start()
    try:
        assert running.wait(timeout=60)
        start = counter[0]
        summary, _ = opt.solve(ex.initial_guess())
        progressed = counter[0] - start
    finally:
        stop.set()
        thread.join()
    assert summary.iterations == 600
    assert progressed > 1000, "the Python thread made no progress during the solve"


def test_ctrl_c_stops_a_long_solve(spinner):
    ex = spinner
    opt = idto.TrajectoryOptimizer(ex.model, ex.problem, endless_options(ex))
    previous = signal.signal(signal.SIGINT, signal.default_int_handler)
    timer = threading.Timer(0.3, lambda: os.kill(os.getpid(), signal.SIGINT))
    start = time.perf_counter()
    try:
        timer.start()
        with pytest.raises(KeyboardInterrupt):
            opt.solve(ex.initial_guess())
    finally:
        timer.cancel()
        signal.signal(signal.SIGINT, previous)
    assert time.perf_counter() - start < 20.0
    # The optimizer is still usable.
    opt.options.max_iterations = 1
    summary, traj = opt.solve(ex.initial_guess())
    assert summary.iterations == 1 and traj.q.shape == (41, 3)
