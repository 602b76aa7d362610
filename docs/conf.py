"""Sphinx configuration of quatrot's documentation site (`make docs`).

Pages are MyST Markdown; the Python API comes from the docstrings of the
built module (autodoc, numpydoc sections through napoleon) and their
examples run under `sphinx-build -b doctest`; the gallery runs
docs/examples/ at build time (quick settings when QUATROT_DOCS_QUICK=1, as
`make test` sets); the command-line page is generated from the command's
own `--help`; the validation report is included when `make validate` has
written one (QUATROT_REPORT, default results/report.md).
"""

from __future__ import annotations

import os
import re
import shutil
import subprocess
import sys
import tempfile
from pathlib import Path

import quatrot

DOCS = Path(__file__).resolve().parent
ROOT = DOCS.parent
GENERATED = DOCS / "_generated"
QUICK = os.environ.get("QUATROT_DOCS_QUICK") == "1"

project = "quatrot"
author = "the quatrot developers"
copyright = "the quatrot developers (MIT License)"
release = version = quatrot.__version__

extensions = [
    "myst_parser",
    "sphinx.ext.autodoc",
    "sphinx.ext.napoleon",
    "sphinx.ext.doctest",
    "sphinx_gallery.gen_gallery",
]
source_suffix = {".md": "markdown", ".rst": "restructuredtext"}
exclude_patterns = ["_build", "examples", "**/*.ipynb", "auto_examples/*.ipynb"]
myst_heading_anchors = 4
myst_enable_extensions = ["colon_fence"]
# Single backquotes in docstrings are code, as in the Rust doc comments.
default_role = "literal"
nitpicky = True
# Type hints of the sweep's signatures name standard and Dask types that no
# page of this site documents.
nitpick_ignore_regex = [("py:class", r"(collections\.abc|os|pathlib|distributed(\.client)?)\.\w+"), ("py:class", "ndarray")]
# benchmarks/RESULTS.md (written by `make bench`) skips heading levels; the
# pickled gallery configuration only costs a full rebuild (made every time).
suppress_warnings = ["myst.header", "config.cache"]

html_theme = "furo"
html_title = f"quatrot {release}"
html_static_path: list[str] = []

# -- The Python API ------------------------------------------------------
autodoc_default_options = {"members": True, "undoc-members": False}
autodoc_member_order = "bysource"
napoleon_numpy_docstring = True
napoleon_google_docstring = False
napoleon_use_rtype = False
napoleon_use_param = False
napoleon_use_keyword = False
napoleon_preprocess_types = False
doctest_global_setup = "import numpy as np\nimport quatrot\nimport quatrot.sweep\nfrom quatrot import quaternion\nnp.set_printoptions(precision=6, suppress=True)\n"
# Only the docstrings' examples are doctests (the pages show commands too).
doctest_test_doctest_blocks = "default"


def strip_fences(app, what, name, obj, options, lines):
    """The Rust doc comments fence their Examples as ```python (rustdoc
    would read `x["key"]` as a link); the fence lines go, the doctests stay."""
    lines[:] = [line for line in lines if line.strip() not in ("```python", "```")]


def require_examples(app, what, name, obj, options, lines):
    """A public function or class without an Examples section with a `>>>`
    line is a warning (an error under -W), so every one of them has an
    example that runs under the doctest builder."""
    if what in ("function", "class", "method") and not name.split(".")[-1].startswith("_"):
        text = "\n".join(lines)
        if not text.strip():
            logger.warning("%s has no docstring", name)
        elif what != "method" and ">>>" not in text:
            logger.warning("%s has no example (an Examples section with >>>)", name)


# -- The gallery -----------------------------------------------------------
GALLERY_OUT = Path(tempfile.mkdtemp(prefix="quatrot-gallery-"))


def gallery_argv(gallery_conf, script_vars):
    """Each example's command line: --quick under QUATROT_DOCS_QUICK=1, and
    an output folder outside the source tree for the files it writes."""
    return (["--quick"] if QUICK else []) + ["--out", str(GALLERY_OUT / Path(script_vars["src_file"]).stem)]


sphinx_gallery_conf = {
    "examples_dirs": "examples",
    "gallery_dirs": "auto_examples",
    "filename_pattern": r"\.py$",
    "reset_argv": gallery_argv,
    "abort_on_example_error": True,
    "download_all_examples": False,
    "remove_config_comments": True,
    "matplotlib_animations": False,
    "show_memory": False,
}


# -- Generated pages -------------------------------------------------------
def command_line_page() -> str:
    """The command-line reference from the command's own help texts (clap's
    for `quatrot` and its subcommands, argparse's for the sweep)."""
    env = os.environ | {"QUATROT_PYTHON": sys.executable, "COLUMNS": "100"}

    def help_of(*args: str) -> str:
        done = subprocess.run([sys.executable, "-m", "quatrot", *args, "--help"], env=env, capture_output=True, text=True, check=True)
        return done.stdout.rstrip()

    page = [
        "# Command line",
        "",
        "The `quatrot` command (installed by `pip install .`, also `python -m quatrot`;",
        "the Rust binary `cargo run --release --` takes the same arguments). This page is",
        "generated from the command's own `--help` when the site is built.",
        "",
        "```text",
        help_of(),
        "```",
    ]
    for sub in ("run", "scenes", "check", "sweep"):
        page += ["", f"## quatrot {sub}", "", "```text", help_of(sub), "```"]
    return "\n".join(page) + "\n"


def report_page() -> str:
    """The latest validation report when `make validate` wrote one (its
    plots copied beside it), else how to make one."""
    report = Path(os.environ.get("QUATROT_REPORT", ROOT / "results" / "report.md"))
    if not report.is_file():
        return (
            "# Validation report\n\n"
            "No report in this build: `make validate` runs every check module of\n"
            "`validation/checks/`, writes `results/report.md` and builds this site\n"
            "again with the report on this page.\n"
        )
    text = report.read_text()
    for image in re.findall(r"!\[[^\]]*\]\(([^)]+)\)", text):
        source, target = report.parent / image, GENERATED / image
        if source.is_file():
            target.parent.mkdir(parents=True, exist_ok=True)
            shutil.copy(source, target)
    return text


def generate(app):
    GENERATED.mkdir(exist_ok=True)
    (GENERATED / "cli.md").write_text(command_line_page())
    (GENERATED / "report.md").write_text(report_page())


from sphinx.util import logging  # noqa: E402

logger = logging.getLogger(__name__)


def setup(app):
    app.connect("builder-inited", generate)
    app.connect("autodoc-process-docstring", strip_fences)
    app.connect("autodoc-process-docstring", require_examples)
