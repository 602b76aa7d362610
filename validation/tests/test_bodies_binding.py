"""`quatrot.bodies_evaluate` (issue 39): the bindings convert and delegate;
bad input is refused naming the argument or the body type's field."""

import numpy as np
import pytest

import quatrot

SPHERE = {
    "sites": [{"position": [0, 0, 0], "lennard_jones": {"epsilon": 1.0, "sigma": 1.0}}],
    "mass": 1.0,
    "inertia": [[0.1, 0, 0], [0, 0.1, 0], [0, 0, 0.1]],
}


def evaluate(types=(SPHERE,), **kwargs):
    positions = kwargs.pop("positions", [[0, 0, 0], [1.5, 0, 0]])
    orientations = kwargs.pop("orientations", [[1, 0, 0, 0]] * len(positions))
    return quatrot.bodies_evaluate(list(types), positions, orientations, lj_cutoff=2.5, **kwargs)


def test_two_spheres_give_the_closed_form_energy_and_opposite_forces():
    """At r = 1.5: u = 4 (r^-12 - r^-6), the force -du/dr along the axis,
    equal and opposite, no torque, and the virial's trace r f."""
    r = 1.5
    state = evaluate()
    u = 4 * (r**-12 - r**-6)
    f = 4 * (12 * r**-13 - 6 * r**-7)
    assert state["energies"]["lennard_jones"] == pytest.approx(u, rel=1e-14)
    np.testing.assert_allclose(state["forces"], [[-f, 0, 0], [f, 0, 0]], rtol=1e-14)
    assert not state["torques"].any()
    assert np.trace(state["virial"]) == pytest.approx(r * f, rel=1e-14)
    assert state["pressure"] is None


def test_bad_body_types_are_refused_naming_the_field():
    with pytest.raises(quatrot.SceneError, match=r"^body_types\[0\]\.sites: a body needs at least one site$"):
        evaluate(types=[{"sites": [], "mass": 1.0}])
    bad_key = {**SPHERE, "sites": [{"position": [0, 0, 0], "colour": "red"}]}
    with pytest.raises(quatrot.SceneError, match=r"^body_types\[0\]\.sites\[0\]\.colour: unknown field `colour`, expected one of `position`"):
        evaluate(types=[bad_key])
    indefinite = {**SPHERE, "inertia": [[1, 0, 0], [0, -1, 0], [0, 0, 1]]}
    with pytest.raises(quatrot.SceneError, match=r"^body_types\[0\]\.inertia: must be symmetric positive-definite"):
        evaluate(types=[indefinite])


def test_bad_arguments_are_refused_naming_the_argument():
    with pytest.raises(ValueError, match=r"^kinds\[1\]: must be below the number of body types \(1\), got 3$"):
        evaluate(kinds=[0, 3])
    with pytest.raises(ValueError, match=r"^kinds: expected 2 kinds \(one per body\), got 1$"):
        evaluate(kinds=[0])
    with pytest.raises(ValueError, match=r"^truncation: "):
        evaluate(truncation="smooth")
    smooth = {"kind": "cutoff", "cutoff": 2.5, "truncation": "smooth"}
    with pytest.raises(quatrot.SceneError, match=r'^electrostatics\.truncation: must be "plain" or "shifted_force", got "smooth"$'):
        evaluate(electrostatics=smooth)
    quadrupolar = {**SPHERE, "sites": [{**SPHERE["sites"][0], "quadrupole": [[1, 0, 0], [0, 1, 0], [0, 0, -2]]}]}
    with pytest.raises(ValueError, match=r'^electrostatics\.truncation: "shifted_force" truncates charges and dipoles only'):
        evaluate(types=[quadrupolar], electrostatics={**smooth, "truncation": "shifted_force"})
    with pytest.raises(ValueError, match=r"^box_lengths\[0\]: must be at least twice the cutoff plus the skin"):
        evaluate(box_lengths=[5.0, 8.0, 8.0])


def _rock_salt(cells):
    """Ions of the rock-salt lattice (nearest-neighbour distance 1), `cells`
    conventional cells per side: positions, kinds (0: +1, 1: -1), box edge."""
    grid = np.stack(np.meshgrid(*[np.arange(2 * cells)] * 3, indexing="ij"), -1).reshape(-1, 3)
    return grid.astype(float), (grid.sum(axis=1) % 2).tolist(), 2.0 * cells


def test_the_ewald_sum_of_charged_bodies_gives_the_madelung_constant():
    """`electrostatics` takes a scene's table: rock salt by PME at 1e-8 gives
    the energy per ion pair -M / r0, M = 1.747564594633182 (Glasser & Zucker,
    1980), to 1e-7 relative (the request bounds the fields, not the energy)."""
    positions, kinds, edge = _rock_salt(2)
    ion = lambda q: {"sites": [{"position": [0, 0, 0], "charge": q}], "mass": 1.0, "inertia": np.eye(3).tolist()}  # noqa: E731
    state = quatrot.bodies_evaluate(
        [ion(1.0), ion(-1.0)],
        positions,
        [[1, 0, 0, 0]] * len(positions),
        kinds=kinds,
        box_lengths=[edge] * 3,
        electrostatics={"kind": "ewald", "accuracy": 1e-8, "method": "pme"},
    )
    pairs = len(positions) / 2
    assert state["energies"]["electrostatic"] / pairs == pytest.approx(-1.747564594633182, rel=1e-7)
    assert np.abs(state["forces"]).max() < 1e-6



def test_forced_pme_parameters_of_bodies_are_kept_or_refused_naming_the_key():
    """The `electrostatics` table takes the rotors' forced PME parameters:
    rock salt with a forced order and grid keeps the Madelung energy within
    the request; a grid too coarse is refused naming `electrostatics.grid`."""
    positions, kinds, edge = _rock_salt(2)
    ion = lambda q: {"sites": [{"position": [0, 0, 0], "charge": q}], "mass": 1.0, "inertia": np.eye(3).tolist()}  # noqa: E731
    args = ([ion(1.0), ion(-1.0)], positions, [[1, 0, 0, 0]] * len(positions))
    table = {"kind": "ewald", "accuracy": 1e-5, "method": "pme", "order": 6, "grid": 64}
    state = quatrot.bodies_evaluate(*args, kinds=kinds, box_lengths=[edge] * 3, electrostatics=table)
    assert state["energies"]["electrostatic"] / (len(positions) / 2) == pytest.approx(-1.747564594633182, rel=1e-5)
    with pytest.raises(ValueError, match=r"^electrostatics\.grid: \[4, 4, 4\] at order 4 reaches "):
        quatrot.bodies_evaluate(*args, kinds=kinds, box_lengths=[edge] * 3, electrostatics={**table, "order": 4, "grid": 4})
