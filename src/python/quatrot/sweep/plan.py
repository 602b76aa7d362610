"""A sweep's plan: a base scene and overrides by field path, expanded to runs.

A *path* names a scene field as the scene's TOML does, tables by dotted keys
and arrays by `[index]`: `run.dt`, `integrator.kind`, `initial.seed`,
`rotors.cells`, `rotors.override[0].dipole`. Setting a path creates the
tables it goes through; a value of `None` removes the key (for example
`run.time` when a sweep sets `run.steps`). Setting a table's `kind` to a
different kind starts that table afresh (the old kind's options mean nothing
to the new one: `integrator.kind = "dlm"` on a `gear_b` scene drops `c0`);
paths are applied shallowest first and, among equal depths, `kind` first,
so `integrator.kind` and `integrator.substeps` combine.

Each run is identified by the hash of its fully resolved scene (the scene
dict after its overrides, as canonical JSON): the same scene always gets the
same identifier, whichever grid produced it.
"""

from __future__ import annotations

import copy
import hashlib
import itertools
import json
import math
import os
import re
import tomllib
from collections.abc import Iterable, Iterator, Mapping
from dataclasses import dataclass
from pathlib import Path
from typing import Any

import quatrot

#: Hex digits of the SHA-256 kept in a run identifier (64 bits: a collision
#: is unlikely below about 4e9 runs).
ID_DIGITS = 16

_KEY = r"[A-Za-z0-9_-]+"
_PATH = re.compile(rf"{_KEY}(\[\d+\])*(\.{_KEY}(\[\d+\])*)*")
_SEGMENT = re.compile(rf"({_KEY})|\[(\d+)\]")


@dataclass(frozen=True)
class Run:
    """One run of a sweep: its identifier, the overrides that made it (path ->
    value, in the order given) and its fully resolved scene.

    Examples
    --------
    >>> run = quatrot.sweep.expand("dipole_in_field", {"run.dt": [0.01]})[0]
    >>> run.overrides, run.scene["run"]["dt"], len(run.id)
    ({'run.dt': 0.01}, 0.01, 16)
    """

    id: str
    overrides: dict[str, Any]
    scene: dict[str, Any]


#: The most runs a sweep may have: its table is rewritten after each batch
#: of finished runs (10^4 runs make 2.7 MB) and its plan is held in memory,
#: so a larger study is split into several sweeps.
MAX_RUNS = 100_000


def expand(
    scene: Any,
    grid: Mapping[str, Iterable[Any]] | None = None,
    cases: Iterable[Mapping[str, Any]] | None = None,
) -> list[Run]:
    """The runs of a sweep: every combination of the `grid`'s values (path ->
    values; the last path varies fastest), then each of the `cases` (path ->
    value dicts, for combinations that are not a grid), applied to the base
    `scene` (a built-in name, a path, TOML text or a dict). A run whose scene
    equals an earlier one's is dropped. With neither grid nor cases, the one
    run is the base scene. At most `MAX_RUNS` runs, counted before any is
    made.

    Examples
    --------
    >>> runs = quatrot.sweep.expand(
    ...     "dipole_in_field",
    ...     grid={"integrator.kind": ["gear_b", "dlm"], "run.dt": [0.01, 0.005]},
    ...     cases=[{"integrator.kind": "no_squish", "integrator.substeps": 10}],
    ... )
    >>> [run.overrides for run in runs][:2]
    [{'integrator.kind': 'gear_b', 'run.dt': 0.01}, {'integrator.kind': 'gear_b', 'run.dt': 0.005}]
    >>> len(runs)
    5
    """
    return list(iter_runs(scene, grid, cases))


def iter_runs(
    scene: Any,
    grid: Mapping[str, Iterable[Any]] | None = None,
    cases: Iterable[Mapping[str, Any]] | None = None,
) -> Iterator[Run]:
    """The runs of `expand`, one at a time (a dry run lists them as they
    come); the count is checked against `MAX_RUNS` before the first.

    Examples
    --------
    >>> runs = quatrot.sweep.iter_runs("dipole_in_field", {"run.dt": [0.01, 0.005]})
    >>> next(runs).overrides
    {'run.dt': 0.01}
    """
    base = load_base(scene)
    paths = list(grid or {})
    values = [_bounded(grid[p], f"grid: `{printable(p)}`") for p in paths]  # type: ignore[index]
    for p, v in zip(paths, values):
        if not v:
            raise ValueError(f"grid: `{printable(p)}` has no values")
    case_list = _bounded(cases or [], "cases")
    count = (math.prod(len(v) for v in values) if paths else 0) + len(case_list)
    if count > MAX_RUNS:
        raise ValueError(
            f"grid: {count} runs, more than the {MAX_RUNS} a sweep may have; split it into several sweeps"
        )
    combos: Iterable[dict[str, Any]] = (dict(zip(paths, c)) for c in itertools.product(*values)) if paths else ()
    combos = itertools.chain(combos, (dict(c) for c in case_list))
    if count == 0:
        combos = iter([{}])
    seen: set[str] = set()
    for overrides in combos:
        resolved = apply(base, overrides)
        _require_seed(resolved, overrides)
        run_id = scene_id(resolved)
        if run_id not in seen:
            seen.add(run_id)
            yield Run(run_id, overrides, resolved)


def _bounded(items: Iterable[Any], what: str) -> list[Any]:
    """The items as a list, refused past `MAX_RUNS` of them (an endless
    iterator included) before they are all read."""
    taken = list(itertools.islice(items, MAX_RUNS + 1))
    if len(taken) > MAX_RUNS:
        raise ValueError(f"{what}: more than the {MAX_RUNS} runs a sweep may have; split it into several sweeps")
    return taken


def load_base(scene: Any) -> dict[str, Any]:
    """The base scene as a dict: a dict as given (numpy values made plain),
    TOML text (it has a newline or `=`), or a built-in name or a path, found
    as `quatrot.run` finds them (a name that looks like a path, ending in
    `.toml` or containing a separator, is read from disk; otherwise a built-in
    of that name, and failing that a file).

    Examples
    --------
    >>> quatrot.sweep.load_base("dipole_in_field")["integrator"]
    {'kind': 'gear_b'}
    """
    if isinstance(scene, Mapping):
        return plain(scene, "")
    if isinstance(scene, os.PathLike):
        text = _read(Path(scene))
    elif isinstance(scene, str):
        text = scene if ("\n" in scene or "=" in scene) else _named(scene)
    else:
        raise quatrot.SceneError(
            f"scene: expected TOML text, a built-in name, a path or a dict, got {type(scene).__name__}"
        )
    try:
        return tomllib.loads(text)
    except tomllib.TOMLDecodeError as e:
        raise quatrot.SceneError(f"syntax: {e}") from None


def _named(name: str) -> str:
    looks_like_path = name.endswith(".toml") or "/" in name or "\\" in name
    builtins = quatrot.builtin_scenes()
    if not looks_like_path and name in builtins:
        return builtins[name]
    return _read(Path(name))


def _read(path: Path) -> str:
    if not path.is_file():
        raise quatrot.SceneError(f"no built-in scene or file named `{printable(str(path))}`")
    return path.read_text()


def apply(base: Mapping[str, Any], overrides: Mapping[str, Any]) -> dict[str, Any]:
    """A copy of `base` with the `overrides` (path -> value) set, shallowest
    path first and `kind` first among equal depths (see the module doc).
    Setting a table's `kind` to another kind starts the table afresh.

    Examples
    --------
    >>> base = {"integrator": {"kind": "gear_b", "c0": 0.1875}, "run": {"dt": 0.01}}
    >>> quatrot.sweep.apply(base, {"integrator.kind": "dlm", "run.dt": 0.005})
    {'integrator': {'kind': 'dlm'}, 'run': {'dt': 0.005}}
    """
    scene = copy.deepcopy(dict(base))
    parsed = {path: _segments(path) for path in overrides}
    order = sorted(overrides, key=lambda p: (len(parsed[p]), parsed[p][-1] != "kind"))
    for path in order:
        _set(scene, path, parsed[path], plain(overrides[path], path))
    return scene


def _segments(path: str) -> list[str | int]:
    if not isinstance(path, str) or not _PATH.fullmatch(path):
        raise ValueError(f"`{printable(str(path))}`: not a scene field path (keys joined by `.`, array items as `[n]`)")
    return [key if key else int(index) for key, index in _SEGMENT.findall(path)]


def _set(scene: dict[str, Any], path: str, segments: list[str | int], value: Any) -> None:
    here: Any = scene
    for depth, segment in enumerate(segments[:-1]):
        if value is None and isinstance(here, dict) and segment not in here:
            return  # nothing to remove
        here = _child(here, segment, path, segments[:depth])
    last = segments[-1]
    if isinstance(last, int):
        if not isinstance(here, list) or last >= len(here):
            raise ValueError(f"`{path}`: no item {last} to set")
        here[last] = value
        return
    if not isinstance(here, dict):
        raise ValueError(f"`{path}`: {_name(segments[:-1])} is not a table")
    if value is None:
        here.pop(last, None)
        return
    if last == "kind" and here.get("kind", value) != value:
        here.clear()
    here[last] = value


def _child(here: Any, segment: str | int, path: str, parents: list[str | int]) -> Any:
    if isinstance(segment, int):
        if not isinstance(here, list) or segment >= len(here):
            raise ValueError(f"`{path}`: {_name(parents)} has no item {segment}")
        return here[segment]
    if not isinstance(here, dict):
        raise ValueError(f"`{path}`: {_name(parents)} is not a table")
    return here.setdefault(segment, {})


def _name(segments: list[str | int]) -> str:
    text = "".join(f"[{s}]" if isinstance(s, int) else f".{s}" for s in segments).lstrip(".")
    return f"`{text}`" if text else "the scene"


def plain(value: Any, path: str) -> Any:
    """`value` as plain Python (dict, list, str, int, float, bool; numpy
    arrays and scalars through `tolist`), or a `SceneError` naming `path`
    (text that is not valid Unicode, such as a command-line word that was
    not UTF-8, is refused)."""
    if isinstance(value, str):
        return _text(value, path)
    if value is None or isinstance(value, (bool, int, float)):
        return value
    if isinstance(value, Mapping):
        return {_text(str(k), f"{path}: a key"): plain(v, f"{path}.{k}".lstrip(".")) for k, v in value.items()}
    if isinstance(value, (list, tuple)):
        return [plain(v, f"{path}[{i}]") for i, v in enumerate(value)]
    if hasattr(value, "tolist"):
        return plain(value.tolist(), path)
    raise quatrot.SceneError(f"{path or '(top level)'}: unsupported value of type {type(value).__name__}")


def _text(text: str, path: str) -> str:
    try:
        text.encode()
    except UnicodeEncodeError:
        raise quatrot.SceneError(f"{printable(path) or '(top level)'}: not valid text (a lone surrogate)") from None
    return text


#: The most characters of input a message quotes.
QUOTED_CHARS = 60


def printable(text: str, max_chars: int = QUOTED_CHARS) -> str:
    r"""Text from the input as a message quotes it, as the engine's messages
    do: control characters and lone surrogates escaped, at most `max_chars`
    characters shown (escapes counted as written), the length of the rest
    stated.

    Examples
    --------
    >>> print(quatrot.sweep.plan.printable("a\x1b[31mb\n" + "x" * 60))
    a\x1b[31mb\nxxxxxxxxxxxxxxxxxxxxxxxxxxxxxxxxxxxxxxxxxxxxxxxx... (12 more characters)
    """
    out, shown = [], 0
    for k, c in enumerate(text):
        piece = c if c.isprintable() else c.encode("unicode_escape", "backslashreplace").decode()
        if shown + len(piece) > max_chars:
            out.append(f"... ({len(text) - k} more characters)")
            break
        shown += len(piece)
        out.append(piece)
    return "".join(out)


def canonical_json(scene: Mapping[str, Any]) -> str:
    """The scene as JSON with sorted keys and no spaces (one text per scene;
    floats in Python's shortest round-trip form)."""
    return json.dumps(scene, sort_keys=True, separators=(",", ":"), ensure_ascii=False)


def scene_id(scene: Mapping[str, Any]) -> str:
    """The identifier of a fully resolved scene: the first `ID_DIGITS` hex
    digits of the SHA-256 of its canonical JSON.

    Examples
    --------
    >>> base = quatrot.sweep.load_base("dipole_in_field")
    >>> quatrot.sweep.scene_id(base) == quatrot.sweep.scene_id(dict(reversed(base.items())))
    True
    """
    return hashlib.sha256(canonical_json(scene).encode()).hexdigest()[:ID_DIGITS]


def _require_seed(scene: Mapping[str, Any], overrides: Mapping[str, Any]) -> None:
    """Random initial conditions need a seed: without one a retried or
    resumed run would not be the run its identifier names."""
    initial = scene.get("initial")
    if isinstance(initial, dict) and initial.get("kind") == "random" and "seed" not in initial:
        raise ValueError(
            f"initial.seed: a sweep's random initial conditions need a seed (run {format_overrides(overrides)}); "
            "set it in the scene or sweep over `initial.seed`"
        )


def format_value(value: Any) -> str:
    """A value as the results table and the messages show it: strings bare,
    numbers in their shortest round-trip form, anything else as JSON."""
    if isinstance(value, str):
        return value
    if isinstance(value, float) and not math.isfinite(value):
        return repr(value)
    return json.dumps(value, separators=(",", ":"))


def format_overrides(overrides: Mapping[str, Any]) -> str:
    """`{path=value, ...}`, or `{base scene}` for none."""
    if not overrides:
        return "{base scene}"
    return "{" + ", ".join(f"{p}={printable(format_value(v))}" for p, v in overrides.items()) + "}"
