"""`python -m validation.report --out results [--quick] [--only NAME ...]`: run
every check module (``validation.checks.modules()``; with ``--only``, the named
ones), print a short summary on the terminal,
write ``<out>/report.md`` with its plots (and ``report.html``, the same page
self-contained), and exit non-zero if any check fails.

Generic: a new module in ``validation/checks/`` with ``run(ctx) -> list[Check]``
appears in the report without touching this file. Its docstring's first
paragraph introduces its section; each check's ``proves`` sentence, details and
plots follow."""

from __future__ import annotations

import argparse
import platform
import sys
import time
import traceback
from pathlib import Path

from validation.checks import modules
from validation.shared.check import Check, Context
from validation.report_html import to_html


def _module_name(module) -> str:
    return module.__name__.rsplit(".", 1)[-1]


def _crash(name: str, error: BaseException) -> Check:
    """A failed check standing for a module that raised, so the report still gets written."""
    return Check(
        name=f"{name}: module raised {type(error).__name__}",
        proves="Nothing: the check module did not complete.",
        tolerance=0.0,
        measured=float("inf"),
        references={},
        details="```\n" + "".join(traceback.format_exception(error)).strip() + "\n```",
    )


def run_all(out: Path, quick: bool, only: list[str] | None = None) -> list[tuple[object, list[Check], float]]:
    """Runs each module (or those named in `only`) with progress on the terminal: [(module, checks, seconds)]."""
    found = modules()
    if only:
        unknown = sorted(set(only) - {_module_name(m) for m in found})
        if unknown:
            raise SystemExit(f"--only: no check module {', '.join(unknown)}; modules: {', '.join(_module_name(m) for m in found)}")
        found = [m for m in found if _module_name(m) in only]
    results = []
    for i, module in enumerate(found, 1):
        name = _module_name(module)
        print(f"[{i}/{len(found)}] {name} ...", flush=True)
        start = time.perf_counter()
        try:
            checks = module.run(Context(out_dir=out / name, quick=quick))
            if not checks:
                raise RuntimeError("the module returned no checks")
        except Exception as error:  # reported as a failed check, not a crash of the report
            checks = [_crash(name, error)]
        seconds = time.perf_counter() - start
        failed = sum(not c.passed for c in checks)
        print(f"[{i}/{len(found)}] {name}: {len(checks)} checks, {failed} failed ({seconds:.1f} s)", flush=True)
        results.append((module, checks, seconds))
    return results


def _fmt(x: float) -> str:
    return f"{x:.3g}" if x == x else "nan"


def _status(check: Check) -> str:
    return "PASS" if check.passed else "FAIL"


def _versions(check: Check) -> str:
    return ", ".join(f"{code} {version}" for code, version in sorted(check.references.items()))


def terminal_table(results) -> str:
    """Per module: checks, failures, time; then every failed check with its numbers."""
    rows = [(_module_name(m), str(len(cs)), str(sum(not c.passed for c in cs)), f"{seconds:.1f}") for m, cs, seconds in results]
    header = ("module", "checks", "failed", "seconds")
    widths = [max(len(r[k]) for r in rows + [header]) for k in range(len(header))]
    line = lambda r: "  ".join(v.ljust(w) for v, w in zip(r, widths))  # noqa: E731
    total = ("total", str(sum(len(cs) for _, cs, _ in results)), str(sum(not c.passed for _, cs, _ in results for c in cs)), f"{sum(s for _, _, s in results):.1f}")
    widths = [max(w, len(v)) for w, v in zip(widths, total)]
    rule = line(tuple("-" * w for w in widths))
    lines = [line(header), rule] + [line(r) for r in rows] + [rule, line(total)]
    failed = [(m, c) for m, cs, _ in results for c in cs if not c.passed]
    if failed:
        lines += ["", "FAILED:"] + [f"  {_module_name(m)}: {c.name}: measured {_fmt(c.measured)} > tolerance {_fmt(c.tolerance)}" for m, c in failed]
    return "\n".join(lines)


def _all_versions(checks) -> str:
    seen = {}
    for c in checks:
        seen.update(c.references)
    return ", ".join(f"{code} {version}" for code, version in sorted(seen.items(), key=lambda kv: kv[0].lower()))


def _paragraphs(doc: str) -> str:
    """A module docstring as Markdown paragraphs (hard line breaks joined)."""
    return "\n\n".join(" ".join(p.split()).replace("``", "`") for p in doc.strip().split("\n\n"))


def _cell(text: str) -> str:
    return text.replace("|", "\\|").replace("\n", " ")


def markdown(results, out: Path, quick: bool) -> str:
    import quatrot

    checks = [c for _, cs, _ in results for c in cs]
    failed = [c for c in checks if not c.passed]
    verdict = "all checks pass" if not failed else f"{len(failed)} of {len(checks)} checks FAIL"
    lines = [
        "# quatrot validation report",
        "",
        f"{len(checks)} checks in {len(results)} module{'s' if len(results) != 1 else ''}: **{verdict}**"
        f"{' (quick subset)' if quick else ''}. quatrot {quatrot.__version__}, Python {platform.python_version()}, {platform.platform()}.",
        "",
        "How to read the table: each row is one check of quatrot (the code under test) against the independent code(s) in the "
        "last column, with their versions, or against an identity or exact solution of the note. *measured* is the check's error: "
        "the largest disagreement over every sample, frame and rotor it covers (relative or absolute as its section says; for "
        "an observed order, the distance of the fitted order from the expected one; for energy conservation, max |E(t) - E(0)| "
        "over the mean kinetic energy). The row PASSes when *measured* <= *tolerance*; each tolerance is a named constant in the "
        "check's module with its reason. The module link leads to what the checks prove and what they do not.",
        "",
        f"Codes compared: {_all_versions(checks)}.",
        "",
        "| module | check | tolerance | measured | result | compared with (versions) |",
        "|---|---|---|---|---|---|",
    ]
    for module, cs, _ in results:
        for c in cs:
            anchor = _module_name(module)
            lines.append(f"| [{anchor}](#{anchor}) | {_cell(c.name)} | {_fmt(c.tolerance)} | {_fmt(c.measured)} | {_status(c)} | {_cell(_versions(c))} |")
    for module, cs, seconds in results:
        name = _module_name(module)
        intro = _paragraphs(module.__doc__ or "")
        lines += ["", f'<a id="{name}"></a>', f"## {name}", "", intro, "", f"{len(cs)} checks, {seconds:.1f} s.", ""]
        for c in cs:
            lines += [f"### {_status(c)}: {c.name}", "", f"*Proves:* {c.proves}", ""]
            lines.append(f"Measured {_fmt(c.measured)} against tolerance {_fmt(c.tolerance)}; compared with {_versions(c) or 'the note itself'}.")
            if c.details:
                lines += ["", c.details]
            for plot in c.plots:
                path = Path(plot).resolve()
                rel = path.relative_to(out.resolve()) if path.is_relative_to(out.resolve()) else path
                lines += ["", f"![{c.name}]({rel.as_posix()})"]
            lines.append("")
    return "\n".join(lines).rstrip() + "\n"


def main(argv=None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--out", type=Path, default=Path("results"), help="output folder (default: results)")
    parser.add_argument("--quick", action="store_true", help="the few-second subset that `make test` runs")
    parser.add_argument("--only", nargs="+", metavar="NAME", help="run only these check modules (e.g. thermostat_sampling)")
    args = parser.parse_args(argv)
    args.out.mkdir(parents=True, exist_ok=True)
    results = run_all(args.out, args.quick, args.only)
    report = args.out / "report.md"
    text = markdown(results, args.out, args.quick)
    report.write_text(text)
    page = args.out / "report.html"
    page.write_text(to_html(text, args.out, "quatrot validation report"))
    print()
    print(terminal_table(results))
    failed = sum(not c.passed for _, cs, _ in results for c in cs)
    total = sum(len(cs) for _, cs, _ in results)
    print(f"\n{total - failed}/{total} checks pass; report: {report} (and {page.name}, self-contained)")
    return 1 if failed or not results else 0


if __name__ == "__main__":
    sys.exit(main())
