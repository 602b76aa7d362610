"""Cross-code checks. Each module here (other than ``base``) defines
``run(ctx: Context) -> list[Check]``; the report and the quick pytest subset
discover them with :func:`modules`."""

import importlib
import pkgutil


def modules():
    """The check modules, in name order."""
    names = sorted(m.name for m in pkgutil.iter_modules(__path__) if m.name != "base")
    return [importlib.import_module(f"{__name__}.{n}") for n in names]
