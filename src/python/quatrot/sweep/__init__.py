"""`quatrot.sweep`: a base scene and a grid of overrides by scene field path,
expanded to independent runs, each a task on Dask `distributed` (a local
cluster by default, any cluster when given a client or a scheduler
address), with one results table that a sweep resumes from.

* `plan`: paths, overrides, the grid's expansion, run identifiers.
* `task`: the idempotent task that runs one scene in its own folder.
* `table`: the results table (CSV, written atomically).
* `folder`: the sweep's folder, locked, written only inside.
* `execute`: submitting the runs and recording their outcomes.
* `cli`: `python -m quatrot.sweep` (and `quatrot sweep`).

    >>> import quatrot.sweep
    >>> results = quatrot.sweep.run(
    ...     "dipole_in_field",
    ...     grid={"integrator.kind": ["gear_b", "dlm"], "run.dt": [0.01, 0.005]},
    ...     out="sweeps/dipole",
    ... )  # doctest: +SKIP
"""

from quatrot.sweep.execute import ALLOWED_FAILURES, Results, run
from quatrot.sweep.folder import FolderInUse
from quatrot.sweep.plan import MAX_RUNS, Run, apply, expand, iter_runs, load_base, scene_id
from quatrot.sweep.table import FINISHED

__all__ = [
    "ALLOWED_FAILURES",
    "FINISHED",
    "MAX_RUNS",
    "FolderInUse",
    "Results",
    "Run",
    "apply",
    "expand",
    "iter_runs",
    "load_base",
    "run",
    "scene_id",
]
