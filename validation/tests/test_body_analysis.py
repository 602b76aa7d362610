"""The analysis of moving bodies (issue 39 item 6) from a run's GSD frames:
free bodies (no interactions, periodic box, Maxwell velocities at T) read
back with the gsd package give the ballistic mean-squared displacement
``3 T t^2 / m`` through the image counts, and their orientations the
free-spherical-top ``C1(t)``; ``radial_distribution`` of the first frame
(a perfect fcc lattice) has its first peak at the nearest-neighbour
distance with 12 neighbours; bad arguments are refused by name."""

import re
from pathlib import Path

import gsd.hoomd
import numpy as np
import pytest

import quatrot

N_SIDE = 5  # fcc: 4 * 5^3 = 500 bodies
TEMPERATURE, MASS, INERTIA = 1.0, 2.0, 0.1
DT, EVERY, STEPS = 0.01, 10, 300
GROUPS = 20
# |t| over groups (19 degrees of freedom): two-sided 1.4e-5 per lag at 6,
# < 1e-3 for the ~60 lags and functions tested.
T_MAX = 6.0


def free_bodies(out_dir: Path) -> dict:
    """500 free spherical tops on an fcc lattice at density 0.3, thermal."""
    scene = {
        "version": 1,
        "name": "free_bodies",
        "body_types": [{
            "mass": MASS,
            "inertia": (np.eye(3) * INERTIA).tolist(),
            "sites": [{"position": [0.0, 0.0, 0.0]}],
        }],
        "bodies": {"kind": "lattice", "lattice": "fcc", "counts": [4 * N_SIDE**3], "density": 0.3},
        "initial": {"kind": "random", "seed": 5, "temperature": TEMPERATURE},
        "integrator": {"kind": "no_squish"},
        "run": {"dt": DT, "steps": STEPS},
        "record": {"series": [], "trajectory": {"every": EVERY, "format": "gsd"}},
    }
    return quatrot.run(scene, out_dir=str(out_dir))


def gsd_frames(path: Path):
    with gsd.hoomd.open(str(path)) as frames:
        box = frames[0].configuration.box[:3].astype(float)
        x = np.array([f.particles.position for f in frames], dtype=float)
        n = np.array([f.particles.image for f in frames], dtype=float)
        q = np.array([f.particles.orientation for f in frames], dtype=float)
    return box, x, n, q


def largest_t(estimates: np.ndarray, exact: np.ndarray) -> float:
    """The largest |t| over lags >= 1 of group estimates (groups, lags)."""
    mean = estimates.mean(axis=0)
    error = estimates.std(axis=0, ddof=1) / np.sqrt(len(estimates))
    return float(np.max(np.abs(mean[1:] - exact[1:]) / error[1:]))


def test_free_bodies_from_gsd_have_ballistic_msd_and_free_top_c1(tmp_path):
    """MSD from the wrapped GSD positions and images is 3 T t^2 / m, and C1
    of a body axis is the free spherical top's 1/3 + 2/3 (1 - s^2 t^2)
    exp(-s^2 t^2 / 2), s^2 = T/I (B. J. Berne and G. D. Harp, Adv. Chem.
    Phys. 17, 63 (1970): a rotation by |w| t about a random axis averages
    u.Ru to (1 + 2 cos |w|t)/3, and E cos(|w|t) over Maxwell w is the
    bracket). Both at every lag within the spread over groups of bodies;
    each check would fail with T doubled. The thermal start rescales the
    velocities to T exactly with the 3N - 3 translational degrees of
    freedom: <|v|^2> = 3 (N - 1) T / (N m), 0.2 % below 3 T/m, far inside
    the group spread (~5 %)."""
    free_bodies(tmp_path)
    box, x, n, q = gsd_frames(tmp_path / "trajectory.gsd")
    assert n.any(), "some bodies must cross the box for the images to matter"
    frame_dt = DT * EVERY
    bodies = x.shape[1]
    parts = np.array_split(np.random.default_rng(3).permutation(bodies), GROUPS)
    msd = np.array([
        quatrot.mean_squared_displacement(x[:, g], frame_dt, images=n[:, g], box_lengths=box)["msd"] for g in parts
    ])
    time = np.arange(x.shape[0]) * frame_dt
    ballistic = 3 * TEMPERATURE / MASS * time**2
    assert largest_t(msd, ballistic) < T_MAX
    assert largest_t(msd, 2 * ballistic) > T_MAX
    # Wrapped positions alone do not give it: the images matter.
    wrapped = quatrot.mean_squared_displacement(x, frame_dt)["msd"]
    assert abs(wrapped[-1] / ballistic[-1] - 1) > 0.5
    c1 = np.array([quatrot.orientational_correlations(q[:, g], frame_dt, axes=[0.0, 0.0, 1.0])["c1"] for g in parts])
    for s2, verdict in ((TEMPERATURE / INERTIA, True), (2 * TEMPERATURE / INERTIA, False)):
        exact = 1 / 3 + 2 / 3 * (1 - s2 * time**2) * np.exp(-s2 * time**2 / 2)
        assert (largest_t(c1, exact) < T_MAX) == verdict


def test_fcc_start_has_twelve_neighbours_at_the_nearest_distance(tmp_path):
    """The free bodies' first GSD frame is the fcc lattice at density 0.3:
    nothing closer than a / sqrt 2 (a = (4 / 0.3)^(1/3)), 12 neighbours in
    the shell holding it, the first peak there."""
    free_bodies(tmp_path)
    box, x, _, _ = gsd_frames(tmp_path / "trajectory.gsd")
    rdf = quatrot.radial_distribution(x[0], box, r_max=3.0, bins=287)
    nearest = (4 / 0.3) ** (1 / 3) / np.sqrt(2)
    shell = np.searchsorted(rdf["edges"], nearest) - 1
    assert int(np.argmax(rdf["g"])) == shell
    assert rdf["coordination"][shell - 1] == 0 and rdf["coordination"][shell] == 12


@pytest.mark.parametrize(
    "kwargs, message",
    [
        (dict(images=np.zeros((3, 2, 3))), "images: needs box_lengths"),
        (dict(box_lengths=[2, 2, 2]), "box_lengths: is used only with images"),
        (dict(images=np.zeros((2, 2, 3)), box_lengths=[2, 2, 2]), "images: 2 frames of 2 bodies, but positions has 3 frames of 2"),
        (dict(images=np.zeros((3, 2, 3)), box_lengths=[2, -1, 2]), "box_lengths.y: must be finite and > 0, got -1"),
        (dict(fit_window=[0.5, 0.2]), "fit_window: must be finite with start < end, got (0.5, 0.2)"),
    ],
)
def test_bad_msd_arguments_are_named(kwargs, message):
    with pytest.raises(ValueError, match=re.escape(message)):
        quatrot.mean_squared_displacement(np.zeros((3, 2, 3)), 0.1, **kwargs)


def test_bad_rdf_arguments_are_named():
    x = np.random.default_rng(1).uniform(0, 4, (10, 3))
    with pytest.raises(ValueError, match=re.escape("r_max: must be at most half the shortest box side 2, got 2.5")):
        quatrot.radial_distribution(x, [4, 4, 4], r_max=2.5)
    with pytest.raises(ValueError, match="bins: must be between 1 and"):
        quatrot.radial_distribution(x, [4, 4, 4], bins=0)
