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
        ({"orientations": np.tile([1.0, 0, 0, 0], (3, 1))}, ValueError, "orientations: 3 items, but sites has 2"),
        ({"dipoles_body": np.zeros((2, 4))}, ValueError, "dipoles_body: expected shape (n, 3) or (3,), got (2, 4)"),
        ({"quadrupoles_body": np.zeros((2, 3))}, ValueError, "quadrupoles_body: expected shape (n, 3, 3) or (3, 3), got (2, 3)"),
        ({"dipoles_body": [[0.0, 0.0, "z"]] * 2}, TypeError, "dipoles_body: expected an array of numbers, got list"),
        ({"dipoles_body": np.array([[0.0, 0, 1], [0, 0, np.nan]])}, ValueError, "dipoles_body[1][2]: not finite (nan)"),
        ({"orientations": np.array([[1.0, 0, 0, 0], [0, 0, 0, 0]])}, ValueError, "orientations[1]: quaternion is zero"),
        ({"dipoles_body": np.full((2, 3), 1e300)}, ValueError, "the energy, gradient or torques of sites, dipoles_body, quadrupoles_body, field and field_gradient: not finite"),
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


# The same pair terms summed in another order (~400 terms of order 1).
IMAGE_SUM_RTOL = 1e-12


def test_periodic_sum_beyond_half_the_box_matches_numpy_image_sum():
    """Three dipoles in a box smaller than the cutoff: the energy is the numpy
    sum over every image inside the cutoff (pairs i < j over all shifts, plus
    half of each rotor's own images), and each torque is mu_i x E_i with E_i
    the field of every image of every rotor but rotor i itself at n = 0."""
    rng = np.random.default_rng(3)
    box, cutoff = np.array([1.1, 1.3, 0.9]), 2.7
    sites = rng.uniform(0, 1, (3, 3)) * box
    mu = rng.normal(size=(3, 3))
    m = np.ceil(cutoff / box).astype(int)
    shifts = np.array(np.meshgrid(*[np.arange(-k, k + 1) for k in m], indexing="ij")).reshape(3, -1).T * box
    energy, field = 0.0, np.zeros((3, 3))
    for i in range(3):
        for j in range(3):
            r = sites[j] - sites[i] + shifts
            d = np.linalg.norm(r, axis=1)
            keep = (d <= cutoff) & (d > 0)
            r, d = r[keep], d[keep]
            n = r / d[:, None]
            pair = (mu[i] @ mu[j] - 3 * (n @ mu[i]) * (n @ mu[j])) / d**3
            energy += 0.5 * pair.sum()  # each i != j pair seen from both ends; self images from both signs
            field[i] += ((3 * n * (n @ mu[j])[:, None] - mu[j]) / d[:, None] ** 3).sum(axis=0)
    e, _, t = quatrot.multipole_evaluate(
        sites, np.array([[1.0, 0, 0, 0]] * 3), dipoles_body=mu, box_lengths=box, cutoff=cutoff
    )
    assert e == pytest.approx(energy, rel=IMAGE_SUM_RTOL)
    np.testing.assert_allclose(t, np.cross(mu, field), rtol=0, atol=IMAGE_SUM_RTOL * np.abs(np.cross(mu, field)).max())


def _lattice_args():
    sites = np.array([[x, y, z] for x in range(3) for y in range(3) for z in range(3)], float)
    return sites, np.tile([1.0, 0, 0, 0], (27, 1)), np.tile([0, 0, 1.0], (27, 1))


def test_ewald_keyword_lorentz_energy_and_details():
    """sum="ewald" on an aligned sc lattice: the Lorentz energy -(2 pi/3) n mu^2
    per dipole (to 1e-13), the FFT path reported, the direct path on request
    equal to it, and a (3, 3) diagonal box accepted."""
    sites, q, mu = _lattice_args()
    e, g, t, info = quatrot.multipole_evaluate(sites, q, dipoles_body=mu, box_lengths=np.array([3.0, 3, 3]), sum="ewald", accuracy=1e-14, details=True)
    assert e / 27 == pytest.approx(-2 * np.pi / 3, rel=1e-13)
    assert info["path"] == "ewald_lattice_fft" and info["cells"] == [3, 3, 3] and info["basis"] == 1
    e2, _, _, info2 = quatrot.multipole_evaluate(sites, q, dipoles_body=mu, box_lengths=np.diag([3.0, 3, 3]), sum="ewald", accuracy=1e-14, method="direct", details=True)
    assert info2["path"] == "ewald_direct" and e2 == pytest.approx(e, rel=1e-13)
    # Existing calls keep returning three values.
    assert len(quatrot.multipole_evaluate(sites, q, dipoles_body=mu, box_lengths=np.array([3.0, 3, 3]), cutoff=1.5)) == 3


def test_a_box_alone_is_the_ewald_sum_as_in_scenes():
    """box_lengths without cutoff or sum is the Ewald sum at its default
    accuracy (1e-12), as a periodic scene boundary without sum is: the
    Lorentz energy -(2 pi/3) n mu^2 per dipole of an aligned sc lattice."""
    sites, q, mu = _lattice_args()
    e, _, _, info = quatrot.multipole_evaluate(sites, q, dipoles_body=mu, box_lengths=np.array([3.0, 3, 3]), details=True)
    assert info["path"] == "ewald_lattice_fft"
    assert e / 27 == pytest.approx(-2 * np.pi / 3, rel=1e-11)


@pytest.mark.parametrize(
    "kwargs, message",
    [
        ({"sum": "ewald", "accuracy": 0.0}, "accuracy: must be in (0, 1), got 0"),
        ({"sum": "ewald", "accuracy": 1.5}, "accuracy: must be in (0, 1), got 1.5"),
        ({"sum": "ewald", "surface": "metal"}, 'surface: must be "conducting" or "vacuum", got "metal"'),
        ({"sum": "pme"}, 'sum: must be "ewald" or "cutoff", got "pme"'),
        ({"sum": "ewald", "cutoff": 1.0}, 'cutoff: not with sum = "ewald"'),
        ({"sum": "ewald", "method": "fast"}, 'method: must be "auto", "direct", "lattice_fft" or "pme", got "fast"'),
        ({"sum": "ewald", "box_lengths": np.array([[3.0, 0.5, 0], [0, 3, 0], [0, 0, 3]])}, "box_lengths: the box must be orthorhombic"),
        ({"cutoff": 1.0, "method": "lattice_fft", "box_lengths": None}, "box_lengths, cutoff: give both"),
    ],
)
def test_bad_ewald_inputs_name_the_field(kwargs, message):
    sites, q, mu = _lattice_args()
    args = {"box_lengths": np.array([3.0, 3, 3]), **kwargs}
    if args["box_lengths"] is None:
        del args["box_lengths"]
    with pytest.raises(ValueError, match=re.escape(message)):
        quatrot.multipole_evaluate(sites, q, dipoles_body=mu, **args)


def test_pme_keyword_lorentz_energy_and_details():
    """method="pme" on the aligned sc lattice: the Lorentz energy
    -(2 pi/3) n mu^2 per dipole within the requested accuracy (relative to
    the field scale mu n = 1), the path and the mesh reported; refused with
    a truncated sum."""
    sites, q, mu = _lattice_args()
    e, _, t, info = quatrot.multipole_evaluate(sites, q, dipoles_body=mu, box_lengths=[3.0, 3, 3], accuracy=1e-6, method="pme", details=True)
    assert abs(e / 27 + 2 * np.pi / 3) <= 1e-6
    assert np.abs(t).max() <= 1e-6
    assert info["path"] == "ewald_pme" and len(info["grid"]) == 3 and 4 <= info["order"] <= 8
    assert info["real_estimate"] + info["mesh_estimate"] <= 1e-6
    with pytest.raises(ValueError, match='method: the mesh Ewald sum needs sum = "ewald", got sum = "cutoff"'):
        quatrot.multipole_evaluate(sites, q, dipoles_body=mu, box_lengths=[3.0, 3, 3], cutoff=1.4, method="pme")


def _jittered(cells, seed):
    """cells^3 unit dipoles on a simple-cubic lattice of unit spacing, each
    site moved within +-0.25 per axis (not a lattice), random orientations."""
    rng = np.random.default_rng(seed)
    grid = np.stack(np.meshgrid(*[np.arange(cells)] * 3, indexing="ij"), -1).reshape(-1, 3)
    sites = grid + 0.5 + rng.uniform(-0.25, 0.25, grid.shape)
    q = rng.normal(size=(len(sites), 4))
    return sites, q / np.linalg.norm(q, axis=1)[:, None], float(cells)


@pytest.mark.parametrize("cells, accuracy, path", [(4, 1e-5, "ewald_direct"), (12, 1e-4, "ewald_pme"), (4, 1e-12, "ewald_direct")])
def test_auto_chooses_as_scenes_do_and_reports_why(cells, accuracy, path):
    """method="auto" (the default) on irregular sites takes the direct sum for
    64 dipoles and PME for 1,728 at 1e-4 (the cost models' crossover is 550
    dipoles there), and the direct sum at 1e-12, beyond PME's range; `details`
    reports both estimates and the reason, and the energy equals the forced
    path's bit for bit."""
    sites, q, edge = _jittered(cells, 5)
    kwargs = {"dipoles_body": [0, 0, 1.0], "box_lengths": [edge] * 3, "accuracy": accuracy, "details": True}
    e, _, _, info = quatrot.multipole_evaluate(sites, q, **kwargs)
    assert info["path"] == path
    choice = info["choice"]
    assert choice["direct_seconds"] > 0
    if accuracy < 1e-10:
        assert choice["pme_seconds"] is None and "accuracy: must be from 1e-10 to 1e-2" in choice["reason"]
    else:
        assert (choice["pme_seconds"] < choice["direct_seconds"]) == (path == "ewald_pme")
    forced, _, _, forced_info = quatrot.multipole_evaluate(sites, q, method=path.removeprefix("ewald_"), **kwargs)
    assert forced == e and "choice" not in forced_info


def test_pme_forced_parameters_are_kept_and_refused_when_they_miss():
    """order, grid, real_cutoff and alpha force PME's parameters (details
    report them as given, the rest chosen for the accuracy) and the Lorentz
    energy -(2 pi/3) n mu^2 holds within the request; a grid too coarse for
    the accuracy is refused saying what it reaches, and forcing with another
    method is refused naming the keyword."""
    sites, q, mu = _lattice_args()
    kwargs = {"dipoles_body": mu, "box_lengths": [3.0, 3, 3], "accuracy": 1e-5, "method": "pme", "details": True}
    e, _, _, info = quatrot.multipole_evaluate(sites, q, order=6, grid=[75, 80, 81], real_cutoff=1.45, alpha=3.0, **kwargs)
    assert (info["order"], list(info["grid"]), info["real_cutoff"], info["alpha"]) == (6, [75, 80, 81], 1.45, 3.0)
    assert abs(e / 27 + 2 * np.pi / 3) <= 1e-5
    _, _, _, info = quatrot.multipole_evaluate(sites, q, grid=40, **kwargs)
    assert list(info["grid"]) == [40, 40, 40]
    with pytest.raises(ValueError, match=r"^grid: \[6, 6, 6\] at order 4 reaches .* at best .*, not the requested 0\.00001$"):
        quatrot.multipole_evaluate(sites, q, order=4, grid=6, **kwargs)
    with pytest.raises(ValueError, match=r'^order: forces a parameter of the mesh Ewald sum: only with method = "pme", got method = "auto"$'):
        quatrot.multipole_evaluate(sites, q, dipoles_body=mu, box_lengths=[3.0, 3, 3], order=6)
    with pytest.raises(ValueError, match=r"^grid: expected an int or a sequence of 3 ints$"):
        quatrot.multipole_evaluate(sites, q, grid="fine", **kwargs)
