"""Cross-code checks. Each module here defines ``run(ctx: Context) ->
list[Check]`` (``validation.shared.check``); the report and the quick pytest
subset discover them with :func:`modules`. Checks import ``validation.shared``
and ``validation.longrun``, never ``validation.bench`` or ``validation.fixtures``."""

import importlib
import pkgutil


def modules():
    """The check modules, in name order."""
    names = sorted(m.name for m in pkgutil.iter_modules(__path__))
    return [importlib.import_module(f"{__name__}.{n}") for n in names]
