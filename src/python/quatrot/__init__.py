"""quatrot: rotational dynamics of rigid rotors in quaternion form.

The engine is the Rust extension `quatrot._native`; this package re-exports
every name it defines (`run`, `builtin_scenes`, `SceneError`, `BlowUpError`,
`multipole_evaluate`, the submodule `quaternion`, ...), so `quatrot.run` is
the native function. Pure-Python parts live beside it: `quatrot.sweep`
(grids of runs as Dask tasks; needs the `sweep` extra) is imported on demand.
"""

import sys

from quatrot import _native
from quatrot._native import *  # noqa: F403 (the names in the native module's `__all__`)

__all__ = list(_native.__all__)

# `import quatrot.quaternion` finds the native submodule.
sys.modules[f"{__name__}.quaternion"] = _native.quaternion
