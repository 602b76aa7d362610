"""`quatrot.gear_corrections_table`: shapes and values are checked at the
boundary with messages naming the argument."""

import re

import numpy as np
import pytest

import quatrot


def arrays(n=1):
    return dict(
        sites=np.zeros((n, 3)),
        inertia=np.ones((n, 3)),
        orientations=np.tile([1.0, 0.0, 0.0, 0.0], (n, 1)),
        omega_body=np.ones((n, 3)),
    )


@pytest.mark.parametrize(
    "change, message",
    [
        (dict(orientations=np.zeros((1, 3))), "orientations: expected shape (n, 4) or (4,), got (1, 3)"),
        (dict(inertia=np.ones((2, 3))), "inertia: 2 items, but sites has 1"),
        (dict(field=np.ones(2)), "field: expected shape (n, 3) or (3,), got (2,)"),
        (dict(field=np.ones((1, 3))), "field: expected a single item"),
        (dict(sites=[["a", 0.0, 0.0]]), "sites: expected an array of numbers, got list"),
        (dict(omega_body=np.array([[0.0, np.inf, 0.0]])), "omega_body[0][1]: not finite (inf)"),
        (dict(orientations=np.zeros((1, 4))), "orientations[0]: quaternion is zero"),
        (dict(cutoff=1.0), "box_lengths, cutoff: give both"),
        (dict(dt=0.0), "dt: must be finite and > 0"),
        (dict(inertia=np.array([[1.0, 0.0, 1.0]])), "moments of inertia must all be > 0"),
    ],
)
def test_bad_input_is_a_value_error_naming_the_argument(change, message):
    args = arrays() | dict(dipoles=np.array([[0.0, 0.0, 1.0]]), field=np.array([0.0, 0.0, 1.0]))
    with pytest.raises((ValueError, TypeError), match=re.escape(message)):
        quatrot.gear_corrections_table(**(args | change))


def test_one_row_per_configuration_with_all_columns():
    rows = quatrot.gear_corrections_table(
        **arrays(), dipoles=np.array([[0.0, 0.0, 1.0]]), field=np.array([0.0, 0.0, 1.0]),
        dt=0.05, t_energy=1.0, t_error=0.5, t_stability=0.5,
    )
    assert len(rows) == 8
    assert rows[0]["label"].startswith("A")
    assert set(rows[0]) == {"label", "drift", "fluctuation", "global_error", "order", "largest_stable_dt", "max_q_dot_q_dot", "max_q_dot_force"}
