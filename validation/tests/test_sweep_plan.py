"""The sweep's plan and table without a cluster: overrides by field path,
the grid's expansion, run identifiers, the command line's values, and the
table's atomic replacement."""

import csv
import subprocess
import sys
import tomllib
from pathlib import Path

import pytest
import quatrot
from quatrot.sweep import apply, expand, load_base, scene_id
from quatrot.sweep.cli import parse_case, parse_grid, parse_value, split_top_level
from quatrot.sweep.plan import Run
from quatrot.sweep.table import Table

BASE = quatrot.builtin_scenes()["dipole_in_field"]


def test_paths_set_nested_fields_and_create_missing_tables():
    scene = apply(tomllib.loads(BASE), {"run.dt": 0.01, "record.trajectory.every": 5, "fields.uniform[2]": 2.0})
    assert scene["run"]["dt"] == 0.01
    assert scene["record"]["trajectory"] == {"every": 5}
    assert scene["fields"]["uniform"][2] == 2.0


def test_the_base_is_not_changed_and_values_are_copied():
    base = tomllib.loads(BASE)
    dipole = [0.0, 0.0, 1.0]
    scene = apply(base, {"rotors.default.dipole": dipole})
    scene["rotors"]["default"]["dipole"][0] = 9.0
    assert dipole == [0.0, 0.0, 1.0]
    assert base == tomllib.loads(BASE)


def test_a_new_kind_starts_its_table_afresh_and_is_applied_first():
    """`integrator.kind` on a table with another kind's options drops them
    (they would be unknown fields of the new kind); the options given with
    it are applied after it, whatever the order of the overrides."""
    base = apply(tomllib.loads(BASE), {"integrator.c0": "3/20"})
    scene = apply(base, {"integrator.substeps": 10, "integrator.kind": "no_squish"})
    assert scene["integrator"] == {"kind": "no_squish", "substeps": 10}
    same_kind = apply(base, {"integrator.kind": "gear_b"})
    assert same_kind["integrator"] == {"kind": "gear_b", "c0": "3/20"}
    quatrot.run(scene, steps=2)  # a valid scene


def test_none_removes_a_key():
    base = apply(tomllib.loads(BASE), {"run.time": 1.0})
    scene = apply(base, {"run.time": None, "run.steps": 5, "record.nothing": None})
    assert "time" not in scene["run"] and scene["run"]["steps"] == 5
    assert "nothing" not in scene.get("record", {})


@pytest.mark.parametrize(
    ("overrides", "message"),
    [
        ({"run..dt": 1}, r"`run\.\.dt`: not a scene field path"),
        ({"run.dt.x": 1}, r"`run\.dt\.x`: `run\.dt` is not a table"),
        ({"fields.uniform[7]": 1.0}, r"`fields\.uniform\[7\]`: no item 7 to set"),
        ({"rotors.sites[5].position": [0, 0, 0]}, r"`rotors\.sites\[5\]\.position`: `rotors\.sites` has no item 5"),
    ],
)
def test_bad_paths_are_refused_by_name(overrides, message):
    with pytest.raises(ValueError, match=message):
        apply(tomllib.loads(BASE), overrides)


def test_the_identifier_is_the_resolved_scene_whatever_its_form(tmp_path: Path):
    """A built-in name, its TOML text, its file and its dict with keys in
    another order give one identifier; any change of the scene another."""
    path = tmp_path / "scene.toml"
    path.write_text(BASE)
    as_dict = tomllib.loads(BASE)
    reordered = dict(reversed(list(as_dict.items())))
    ids = {scene_id(load_base(s)) for s in ("dipole_in_field", BASE, path, str(path), reordered)}
    assert len(ids) == 1
    assert scene_id(apply(as_dict, {"run.dt": 0.0051})) not in ids
    assert len(ids.pop()) == 16


def test_the_grid_is_the_product_then_the_cases_without_repeats():
    runs = expand(
        "dipole_in_field",
        grid={"integrator.kind": ["gear_b", "dlm"], "run.dt": [0.01, 0.005]},
        cases=[{"integrator.kind": "no_squish"}, {"integrator.kind": "dlm", "run.dt": 0.005}],
    )
    assert [r.overrides for r in runs] == [
        {"integrator.kind": "gear_b", "run.dt": 0.01},
        {"integrator.kind": "gear_b", "run.dt": 0.005},
        {"integrator.kind": "dlm", "run.dt": 0.01},
        {"integrator.kind": "dlm", "run.dt": 0.005},
        {"integrator.kind": "no_squish"},
    ]
    assert all(r.id == scene_id(r.scene) for r in runs)
    assert [r.overrides for r in expand("dipole_in_field")] == [{}]


def test_random_initial_conditions_need_a_seed():
    scene = tomllib.loads(quatrot.builtin_scenes()["dipole_lattice_sc"])
    del scene["initial"]["seed"]
    with pytest.raises(ValueError, match=r"^initial\.seed: a sweep's random initial conditions need a seed \(run \{run\.dt=0\.001\}\)"):
        expand(scene, grid={"run.dt": [0.001]})
    assert len(expand(scene, grid={"initial.seed": [1, 2]})) == 2


def test_a_missing_base_scene_is_a_scene_error():
    with pytest.raises(quatrot.SceneError, match="no built-in scene or file named `no_such_scene`"):
        expand("no_such_scene")
    with pytest.raises(quatrot.SceneError, match=r"^syntax: "):
        expand("version = = 1")


def test_command_line_values_are_toml_literals_or_bare_words():
    assert parse_value("0.01") == 0.01 and parse_value("7") == 7 and parse_value("true") is True
    assert parse_value("gear_b") == "gear_b" and parse_value("3/16") == "3/16" and parse_value('"a b"') == "a b"
    assert parse_value("{ kind = \"dlm\" }") == {"kind": "dlm"}
    with pytest.raises(ValueError, match="neither a TOML value nor a bare word"):
        parse_value("[1, 2")
    assert split_top_level('[0, 0, 1],{ a = "x,y" },"p,q",3', ",") == ["[0, 0, 1]", '{ a = "x,y" }', '"p,q"', "3"]
    assert parse_grid(["run.dt=0.01, 0.005", "integrator.kind=gear_b,dlm", "rotors.default.dipole=[0,0,1],[0,0,2]"]) == {
        "run.dt": [0.01, 0.005],
        "integrator.kind": ["gear_b", "dlm"],
        "rotors.default.dipole": [[0, 0, 1], [0, 0, 2]],
    }
    assert parse_case("integrator.kind=no_squish; integrator.substeps=10") == {
        "integrator.kind": "no_squish",
        "integrator.substeps": 10,
    }
    with pytest.raises(ValueError, match="given twice"):
        parse_grid(["run.dt=1", "run.dt=2"])
    with pytest.raises(ValueError, match="expected PATH=VALUE"):
        parse_case("run.dt")


def test_help_documents_the_options():
    out = subprocess.run([sys.executable, "-m", "quatrot.sweep", "--help"], capture_output=True, text=True, check=True)
    for option in ("--set PATH=V1,V2,...", "--case", "--out DIR", "--scheduler ADDRESS", "--workers N", "--threads-per-run N"):
        assert option in out.stdout, option


def test_a_failed_write_leaves_the_previous_table(tmp_path: Path):
    """The table is replaced by a rename: an error half-way through writing
    the new one leaves the old file whole and no temporary file behind."""
    path = tmp_path / "results.csv"
    table = Table(path)
    run = Run("a" * 16, {"run.dt": 0.01}, {})
    table.record(run, {"status": "completed", "final_total_energy": -0.5})
    table.write([run.id])
    before = path.read_bytes()

    class Unprintable:
        def __str__(self):
            raise RuntimeError("disk full")

    table.rows["b" * 16] = {"id": "b" * 16, "status": Unprintable()}
    with pytest.raises(RuntimeError, match="disk full"):
        table.write([run.id, "b" * 16])
    assert path.read_bytes() == before
    assert [p.name for p in tmp_path.iterdir()] == ["results.csv"]
    rows = list(csv.DictReader(path.open()))
    assert rows[0]["run.dt"] == "0.01" and float(rows[0]["final_total_energy"]) == -0.5


def test_without_dask_the_import_says_what_to_install():
    code = "import sys; sys.modules['distributed'] = None; import quatrot.sweep"
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True)
    assert out.returncode == 1
    assert "ImportError: quatrot.sweep runs on Dask: install it with `pip install 'quatrot[sweep]'`" in out.stderr
    subprocess.run([sys.executable, "-c", "import sys; sys.modules['distributed'] = None; import quatrot"], check=True)


def test_an_override_named_as_a_summary_column_keeps_its_own_column(tmp_path: Path):
    """The path `integrator` (a whole table) and the summary's `integrator`
    (the integrator's name) are two columns: neither overwrites the other."""
    table = Table(tmp_path / "results.csv")
    run = quatrot.sweep.expand("dipole_in_field", cases=[{"integrator": {"kind": "dlm"}}])[0]
    table.record(run, {"status": "completed", "integrator": "dlm"})
    table.write([run.id])
    with (tmp_path / "results.csv").open() as f:
        row = next(csv.DictReader(f))
    assert row["set:integrator"] == '{"kind":"dlm"}' and row["integrator"] == "dlm"


def test_text_that_is_not_unicode_is_refused_naming_its_path(tmp_path: Path, capsys):
    """Found by the sweep fuzz (issue 37): a command-line word that is not
    UTF-8 (`--set run.dt=$'\\xff'`) ended in "error: 'utf-8' codec can't
    encode character '\\udcff' in position 534", naming nothing."""
    from quatrot.sweep.cli import main

    with pytest.raises(quatrot.SceneError, match=r"^run\.dt: not valid text \(a lone surrogate\)$"):
        expand(BASE, {"run.dt": ["\udcff"]})
    with pytest.raises(quatrot.SceneError, match=r"^initial: a key: not valid text"):
        expand({"initial": {"\udcff": 1}})
    code = main(["dipole_in_field", "--set", "run.dt=\udcff", "--out", str(tmp_path), "--dry-run"])
    assert (code, capsys.readouterr().err) == (2, "error: run.dt: not valid text (a lone surrogate)\n")


def test_messages_quote_input_with_control_characters_escaped_and_long_text_cut():
    """Found by the sweep fuzz (issue 37): a value such as `a ESC [31m b`
    was echoed raw to the terminal, a 5000-character one whole."""
    with pytest.raises(ValueError, match=r"^`a\\x1b\[31mb\\n` is neither a TOML value nor a bare word$"):
        parse_value("a\x1b[31mb\n")
    with pytest.raises(ValueError) as e:
        expand(BASE, {"x" * 5000 + " ": [1]})
    assert str(e.value) == "`" + "x" * 60 + "... (4941 more characters)`: not a scene field path (keys joined by `.`, array items as `[n]`)"
