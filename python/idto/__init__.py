"""idto: Inverse Dynamics Trajectory Optimization for contact-implicit MPC.

Bindings of the C++ library with the C++ names in snake_case. Vectors and trajectories are
numpy arrays: a trajectory is an (N + 1) x nq (or nv) array, one row per knot.

    import idto
    ex = idto.load_example("spinner")
    opts = ex.solver_options
    opts.max_iterations = 30
    opt = idto.TrajectoryOptimizer(ex.model, ex.problem, opts)
    summary, traj = opt.solve(ex.initial_guess())   # traj.q: (N + 1, nq)
    print(summary.brief_report())
"""

import os as _os

from ._idto import *  # noqa: F401,F403
from ._idto import FileError, __version__, _load_example, _testing  # noqa: F401
from . import _paths


def default_share_dirs():
    """Folders searched for examples/<name>/<name>.yaml and models/, in order.

    $IDTO_SHARE_DIR (when set), then the source tree (build tree) or the installed
    share/idto folder.
    """
    dirs = []
    env = _os.environ.get("IDTO_SHARE_DIR")
    if env:
        dirs.append(env)
    dirs.extend(_paths.SHARE_DIRS)
    return dirs


def load_example(name_or_path, share_dirs=None):
    """Loads an example configuration (a name such as "spinner", or a YAML file).

    Returns an Example with .model, .problem, .solver_options, .mpc (MpcConfig),
    .mpc_problem, .mpc_solver_options, .initial_guess() and .make_plant(). Raises FileError
    (an OSError) naming the file and key on any problem.
    """
    dirs = default_share_dirs() if share_dirs is None else list(share_dirs)
    return _load_example(str(name_or_path), dirs)
