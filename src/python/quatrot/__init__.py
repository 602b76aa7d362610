"""quatrot: rotational dynamics of rigid rotors in quaternion form.

The engine is the Rust extension `quatrot._native`; this package re-exports
every public name it defines (`run`, `builtin_scenes`, `SceneError`,
`BlowUpError`, `multipole_evaluate`, the submodule `quaternion`, ...).
Every native function, here and in `quatrot.quaternion`, is guarded: an
internal error of the engine (a Rust panic, which Python would raise as a
`BaseException` that `except Exception` does not catch) is raised as
`InternalError`. Pure-Python parts live beside it: `quatrot.sweep` (grids of
runs as Dask tasks; needs the `sweep` extra) is imported on demand.
"""

import functools
import sys
import types

from quatrot import _native


class InternalError(RuntimeError):
    """An internal error of quatrot (a bug: please report it with the
    message), raised instead of the Rust panic behind it.

    Examples
    --------
    >>> issubclass(quatrot.InternalError, RuntimeError)
    True
    """


_PROCESSING = "while processing '"


def _name_the_argument(error):
    """Puts the argument whose conversion failed in front of `error`'s
    message (`dt: must be real number, not str`), as quatrot's own argument
    errors do: pyo3 names it only in a note (`while processing 'dt'`),
    which `str(error)` does not show."""
    notes = getattr(error, "__notes__", [])
    for note in notes:
        if note.startswith(_PROCESSING) and note.endswith("'") and len(error.args) == 1:
            error.args = (f"{note[len(_PROCESSING):-1]}: {error.args[0]}",)
            notes.remove(note)
            return


def _guarded(function):
    """`function` with a Rust panic (pyo3's `PanicException`) raised as
    `InternalError` naming the function, and an argument that could not be
    converted named in the message."""

    @functools.wraps(function)
    def guarded(*args, **kwargs):
        try:
            return function(*args, **kwargs)
        except Exception as e:
            _name_the_argument(e)
            raise
        except BaseException as e:
            if type(e).__name__ != "PanicException":
                raise
            raise InternalError(f"{function.__name__}: internal error of quatrot (please report it): {e}") from e

    return guarded


# Guarded in place, so that `quatrot.quaternion` stays the native submodule
# and `quatrot.run is quatrot._native.run`.
for _module in (_native, _native.quaternion):
    for _name, _value in list(vars(_module).items()):
        if isinstance(_value, types.BuiltinFunctionType):
            setattr(_module, _name, _guarded(_value))

from quatrot._native import *  # noqa: E402, F403 (the names in the native module's `__all__`)

__all__ = [name for name in _native.__all__ if not name.startswith("_")] + ["InternalError"]

# `import quatrot.quaternion` finds the native submodule.
sys.modules[f"{__name__}.quaternion"] = _native.quaternion
