"""The size rules of the crate's sources (issue 35): no function in src/ over
MAX_FUNCTION_LINES lines, no file in src/ over MAX_FILE_LINES lines without
its test module.

Counting rules (on rustfmt-formatted sources, which `make test` checks):

* A function runs from the line of its `fn` keyword (attributes and doc
  comments above it not counted) to the line of its closing brace, both
  included; blank and comment lines inside count. Its closing brace is the
  first later line that is `}` at the indentation of the `fn` line (rustfmt
  puts it there). Declarations without a body (`fn f(&self);` in a trait)
  are not functions here, nor a `fn` in a macro's input. Functions inside other functions, impls, traits,
  macros and test modules are counted like any other.
* A file's production lines are all its lines minus those of its test
  module: from a `#[cfg(test)]` line at column 0 followed by `mod tests {`
  to the `}` at column 0 that closes it.
"""

import re
from pathlib import Path

import pytest

SRC = Path(__file__).resolve().parents[2] / "src"
MAX_FUNCTION_LINES = 80
MAX_FILE_LINES = 500

FN = re.compile(r"^(\s*)(?:pub(?:\([a-z:]+\))?\s+)?(?:const\s+)?(?:async\s+)?(?:unsafe\s+)?(?:extern\s+\"C\"\s+)?fn\s+(\w+)")


def rust_files():
    return sorted(SRC.rglob("*.rs"))


def closes_outside(line, indent):
    """Whether `line` is a closing brace left of (or at) `indent`."""
    text = line.rstrip()
    return text.lstrip() == "}" and len(text) - 1 <= len(indent)


def functions(lines):
    """(name, first line number, line count) of each function with a body."""
    out = []
    for start, line in enumerate(lines):
        m = FN.match(line)
        if not m:
            continue
        indent, name = m.group(1), m.group(2)
        if line.rstrip().endswith("}") and line.count("{") == line.count("}") > 0:
            out.append((name, start + 1, 1))
            continue
        end = start
        # The signature ends at the first line ending in `{` (a body) or `;`
        # (none); a `fn` in a macro's input may end at neither before the
        # macro's closing brace, and is not a function.
        while not lines[end].rstrip().endswith(("{", ";")) and not closes_outside(lines[end + 1], indent):
            end += 1
        if not lines[end].rstrip().endswith("{"):
            continue
        close = end + 1
        while lines[close].rstrip() != indent + "}":
            close += 1
        out.append((name, start + 1, close - start + 1))
    return out


def production_lines(lines):
    """The number of lines of the file outside its test module."""
    for k, line in enumerate(lines[:-1]):
        if line.rstrip() == "#[cfg(test)]" and lines[k + 1].startswith("mod tests {"):
            end = next(j for j in range(k + 1, len(lines)) if lines[j].rstrip() == "}")
            return len(lines) - (end - k + 1)
    return len(lines)


def read(path):
    return path.read_text(encoding="utf-8").splitlines()


def test_the_counting_rules_on_a_known_text():
    """The rules above on a small text: a trait declaration is skipped, a
    one-line function is one line, a nested function counts on its own, the
    test module is left out of the file's lines."""
    text = [
        "trait T {",
        "    fn declared(&self);",
        "}",
        "pub(crate) fn outer(",
        "    x: u8,",
        ") -> u8 {",
        "    fn inner() -> u8 { 1 }",
        "    x + inner()",
        "}",
        "",
        "#[cfg(test)]",
        "mod tests {",
        "    fn helper() {",
        "    }",
        "}",
    ]
    assert functions(text) == [("outer", 4, 6), ("inner", 7, 1), ("helper", 13, 2)]
    assert production_lines(text) == 10


def test_the_walk_finds_the_known_functions():
    """The walk sees the crate: every file has functions or is a table of
    contents, and a function known to be short is measured as in the file."""
    files = rust_files()
    assert len(files) > 100
    lines = read(SRC / "quaternion.rs")
    found = {name: count for name, _, count in functions(lines)}
    assert "conjugate" in found and found["conjugate"] <= 10


@pytest.mark.parametrize("path", rust_files(), ids=lambda p: str(p.relative_to(SRC)))
def test_no_function_over_the_limit(path):
    long = [
        f"{name} (line {line}): {count} lines"
        for name, line, count in functions(read(path))
        if count > MAX_FUNCTION_LINES
    ]
    assert not long, f"{path.relative_to(SRC)}: over {MAX_FUNCTION_LINES} lines: {long}"


@pytest.mark.parametrize("path", rust_files(), ids=lambda p: str(p.relative_to(SRC)))
def test_no_file_over_the_limit_without_its_tests(path):
    count = production_lines(read(path))
    assert count <= MAX_FILE_LINES, f"{path.relative_to(SRC)}: {count} lines without its test module"
