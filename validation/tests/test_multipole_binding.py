"""The numpy boundary of quatrot.multipole_evaluate: shapes are checked with
messages naming the argument, and arrays arrive in the documented layout."""

import re

import numpy as np
import pytest
import quatrot


def test_head_to_tail_dipoles_closed_form():
    """Two unit dipoles along z at distance 2: V = -2/2^3; torques vanish; the
    gradient rows are laid out (q0, q1, q2, q3) per rotor."""
    sites = np.array([[0.0, 0, 0], [0, 0, 2.0]])
    q = np.array([[1.0, 0, 0, 0]] * 2)
    e, g, t = quatrot.multipole_evaluate(sites, q, dipoles_body=np.array([[0, 0, 1.0]] * 2))
    assert e == pytest.approx(-0.25, rel=1e-14)
    assert g.shape == (2, 4) and t.shape == (2, 3)
    assert np.abs(t).max() < 1e-15
    # Euler's theorem (degree 2 per dipole rotor): Q.dV/dQ = 2 V for each of the two rotors.
    assert (q * g).sum() == pytest.approx(4 * e, rel=1e-14)


@pytest.mark.parametrize(
    "kwargs, error, message",
    [
        ({"orientations": np.zeros((3, 4))}, ValueError, "orientations: 3 items, but sites has 2"),
        ({"dipoles_body": np.zeros((2, 4))}, ValueError, "dipoles_body: expected shape (n, 3) or (3,), got (2, 4)"),
        ({"quadrupoles_body": np.zeros((2, 3))}, ValueError, "quadrupoles_body: expected shape (n, 3, 3) or (3, 3), got (2, 3)"),
        ({"dipoles_body": np.zeros((2, 3), dtype=np.float32)}, TypeError, "dipoles_body: expected a numpy array of dtype float64"),
        ({"field": np.zeros((2, 3))}, ValueError, "field: expected a single item of shape (3,), not a batch"),
        ({"cutoff": 1.0}, ValueError, "box_lengths, cutoff: give both"),
        ({"box_lengths": np.array([4.0, 4, 4]), "cutoff": 1e4}, ValueError, "cutoff: 10000 gives about 1.31e11 interacting pairs (periodic images included) for 2 rotors, more than the limit 100000000"),
    ],
)
def test_bad_inputs_name_the_argument(kwargs, error, message):
    args = {"sites": np.array([[0.0, 0, 0], [0, 0, 1.0]]), "orientations": np.array([[1.0, 0, 0, 0]] * 2)}
    args.update(kwargs)
    with pytest.raises(error, match=re.escape(message)):
        quatrot.multipole_evaluate(args.pop("sites"), args.pop("orientations"), **args)
