"""Shared fixtures of the pytest suite (run by ctest with PYTHONPATH at the build's module)."""

import os

import pytest

import idto

ROOT = os.path.abspath(os.path.join(os.path.dirname(__file__), "..", ".."))
MODELS = os.path.join(ROOT, "models")


def model_path(name):
    return os.path.join(MODELS, name)


@pytest.fixture(scope="module")
def spinner():
    return idto.load_example("spinner")


@pytest.fixture(scope="module")
def quadruped_model():
    opts = idto.UrdfOptions()
    opts.base = idto.BaseType.kFloating
    return idto.parse_urdf(model_path("quadruped.urdf"), opts)


def short_options(example, iterations=5):
    opts = example.solver_options
    opts.max_iterations = iterations
    opts.num_threads = 1
    return opts
