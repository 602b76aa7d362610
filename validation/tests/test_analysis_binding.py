"""The analysis bindings against independent numpy/scipy computations of the
same definitions (direct double sums over time origins, numpy's symmetric
eigensolver, scipy rotations), and the GSD trajectory read back with the
format's own reader (`gsd.hoomd`)."""

from pathlib import Path

import gsd.hoomd
import numpy as np
import pytest
import quatrot
from scipy.spatial.transform import Rotation

from small_scenes import tops_bcc

# FFT against direct sums of unit-scale numbers: round-off only.
FFT_TOLERANCE = 1e-12
# Eigen decompositions and rotations in double precision.
DOUBLE_TOLERANCE = 1e-12
# GSD stores float32: relative rounding 6e-8 on unit-scale numbers.
FLOAT32_TOLERANCE = 3e-7


def random_walk(frames: int, rotors: int, seed: int, step: float = 0.2) -> np.ndarray:
    """Orientations (frames, rotors, 4) turned by random small rotations each frame."""
    rng = np.random.default_rng(seed)
    r = Rotation.random(rotors, random_state=seed)
    out = [r.as_quat(scalar_first=True)]
    for _ in range(frames - 1):
        r = Rotation.from_rotvec(step * rng.normal(size=(rotors, 3))) * r
        out.append(r.as_quat(scalar_first=True))
    return np.array(out)


def direct_correlations(u: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """C1 and C2 of unit vectors u (frames, n, 3) by the double sum over origins."""
    frames = u.shape[0]
    c1, c2 = np.empty(frames), np.empty(frames)
    for k in range(frames):
        x = np.sum(u[: frames - k] * u[k:], axis=-1)
        c1[k], c2[k] = x.mean(), (1.5 * x**2 - 0.5).mean()
    return c1, c2


def test_orientational_correlations_match_the_direct_sum():
    """C1 and C2 of two body axes: the FFT equals the direct origin average
    of u(0).u(t) with u = R(Q) e from scipy; orientations scaled by 3 and
    given as a float32 list are normalised and converted."""
    q = random_walk(50, 7, seed=4)
    axes = np.array([[0.0, 0.0, 1.0], [1.0, 1.0, 0.0]])
    out = quatrot.orientational_correlations(3.0 * q, 0.25, axes=axes)
    np.testing.assert_allclose(out["time"], 0.25 * np.arange(50))
    r = Rotation.from_quat(q.reshape(-1, 4), scalar_first=True)
    for a, axis in enumerate(axes / np.linalg.norm(axes, axis=1, keepdims=True)):
        u = r.apply(axis).reshape(50, 7, 3)
        c1, c2 = direct_correlations(u)
        np.testing.assert_allclose(out["c1"][a], c1, atol=FFT_TOLERANCE)
        np.testing.assert_allclose(out["c2"][a], c2, atol=FFT_TOLERANCE)
    single = quatrot.orientational_correlations(q.astype(np.float32).tolist(), 0.25, axes=[0, 0, 1], max_lag=9)
    assert single["c1"].shape == (10,)
    np.testing.assert_allclose(single["c1"], out["c1"][0][:10], atol=1e-6)  # float32 input


def test_angular_velocity_correlation_matches_the_direct_sum():
    rng = np.random.default_rng(8)
    w = np.cumsum(rng.normal(size=(40, 5, 3)), axis=0)
    out = quatrot.angular_velocity_correlation(w, 0.1)
    direct = [np.mean(np.sum(w[: 40 - k] * w[k:], axis=-1)) for k in range(40)]
    np.testing.assert_allclose(out["c"], direct, rtol=FFT_TOLERANCE)


def test_order_parameters_match_numpy_eigh():
    """P2 is the largest eigenvalue of numpy's Q tensor of the axes R(Q) e,
    the director its eigenvector (sign: <u>.d >= 0), P1 = <u>.d."""
    rng = np.random.default_rng(2)
    # A partly aligned set: small random turns about a common orientation.
    q = (Rotation.from_rotvec(0.6 * rng.normal(size=(200, 3))) * Rotation.from_euler("x", 0.4)).as_quat(scalar_first=True)
    axis = np.array([0.0, 1.0, 1.0]) / np.sqrt(2.0)
    out = quatrot.order_parameters(q, axis=axis, direction=[0, 0, 1])
    u = Rotation.from_quat(q, scalar_first=True).apply(axis)
    tensor = 1.5 * np.einsum("ia,ib->ab", u, u) / len(u) - 0.5 * np.eye(3)
    values, vectors = np.linalg.eigh(tensor)
    d = vectors[:, -1] * np.sign(vectors[:, -1] @ u.mean(axis=0))
    np.testing.assert_allclose(out["q_tensor"], tensor, atol=DOUBLE_TOLERANCE)
    assert abs(out["p2"] - values[-1]) < DOUBLE_TOLERANCE
    np.testing.assert_allclose(out["director"], d, atol=1e-10)
    assert abs(out["p1"] - u.mean(axis=0) @ d) < 1e-10
    assert abs(out["p1_direction"] - u[:, 2].mean()) < DOUBLE_TOLERANCE
    np.testing.assert_allclose(out["cos_director"], u @ d, atol=1e-10)
    np.testing.assert_allclose(out["cos_direction"], u[:, 2], atol=DOUBLE_TOLERANCE)
    frames = quatrot.order_parameters(np.stack([q, q[::-1]]), axis=axis)
    assert frames["p2"].shape == (2,) and frames["cos_director"].shape == (2, 200)
    assert "p1_direction" not in frames and "cos_direction" not in frames
    np.testing.assert_allclose(frames["p2"], out["p2"], atol=DOUBLE_TOLERANCE)
    down = quatrot.order_parameters(np.stack([q, q[::-1]]), axis=axis, direction=[0, 0, -2])
    assert down["p1_direction"].shape == (2,) and down["cos_direction"].shape == (2, 200)
    np.testing.assert_allclose(down["p1_direction"], -u[:, 2].mean(), atol=DOUBLE_TOLERANCE)
    np.testing.assert_allclose(down["cos_direction"][1], -u[::-1, 2], atol=DOUBLE_TOLERANCE)


def test_total_dipole_matches_scipy_rotations():
    q = Rotation.random(30, random_state=6).as_quat(scalar_first=True)
    mu = np.random.default_rng(6).normal(size=(30, 3))
    expected = Rotation.from_quat(q, scalar_first=True).apply(mu).sum(axis=0)
    np.testing.assert_allclose(quatrot.total_dipole(2.0 * q, mu), expected, atol=DOUBLE_TOLERANCE)
    series = quatrot.total_dipole(np.stack([q, q]), [0.0, 0.0, 1.5])
    assert series.shape == (2, 3)


def test_block_average_first_level_is_the_textbook_error():
    x = np.random.default_rng(1).normal(size=1000)
    out = quatrot.block_average(x)
    assert abs(out["mean"] - x.mean()) < 1e-15
    assert abs(out["levels"]["error"][0] - x.std() / np.sqrt(len(x) - 1)) < 1e-15
    np.testing.assert_array_equal(out["levels"]["block_length"][:3], [1, 2, 4])


def test_dielectric_constant_formulas_and_refusals():
    """The numpy formula on the same series, and the refusals by name."""
    rng = np.random.default_rng(3)
    m = rng.normal(size=(500, 3)) * 4.0 + [1.0, 0.0, 0.0]
    volume, temperature = 300.0, 1.2
    f = np.mean(np.sum(m**2, axis=1)) - np.sum(m.mean(axis=0) ** 2)
    out = quatrot.dielectric_constant(m, volume, temperature)
    assert abs(out["epsilon"] - (1 + 4 * np.pi * f / (3 * volume * temperature))) < DOUBLE_TOLERANCE
    y = 4 * np.pi * f / (9 * volume * temperature)
    vacuum = quatrot.dielectric_constant(m, volume, temperature, boundary="vacuum")
    assert abs(vacuum["epsilon"] - (1 + 2 * y) / (1 - y)) < DOUBLE_TOLERANCE
    for boundary in ("open", "cutoff"):
        with pytest.raises(ValueError, match=f"^boundary: {boundary}: no "):
            quatrot.dielectric_constant(m, volume, temperature, boundary=boundary)
    with pytest.raises(ValueError, match="^volume: must be finite and > 0"):
        quatrot.dielectric_constant(m, -1.0, temperature)
    with pytest.raises(ValueError, match=r"^dipoles: expected shape \(frames, 3\), got \(500, 3, 1\)"):
        quatrot.dielectric_constant(m[..., None], volume, temperature)


TOPS = tops_bcc("gear_b", {"kind": "periodic", "cutoff": 1.4}, {"every": 10})


@pytest.mark.parametrize("periodic", [True, False], ids=["periodic", "open"])
def test_gsd_round_trip_through_gsd_hoomd(tmp_path: Path, periodic: bool):
    """A run's trajectory written by `write_gsd` reads back with
    `gsd.hoomd.open`: frame count and steps, the box, the positions (wrapped
    into HOOMD's centred box), and the orientations as the normalised
    quaternions of the run, to float32 precision. The open cluster's box is
    the bounding box grown by the margin."""
    result = quatrot.run(TOPS)
    frames, sites = result["trajectory"], result["sites"]
    path = tmp_path / "run.gsd"
    box = np.full(3, 3.0)  # 2 cells of 1.5
    if periodic:
        quatrot.write_gsd(path, sites, frames["orientations"], frames["step"], box_lengths=box)
        corner, lengths = np.zeros(3), box
    else:
        quatrot.write_gsd(path, sites, frames["orientations"], frames["step"], margin=0.5)
        corner = sites.min(axis=0) - 0.5
        lengths = sites.max(axis=0) - sites.min(axis=0) + 1.0
    expected_positions = (sites - corner) % lengths - lengths / 2
    q = frames["orientations"] / np.linalg.norm(frames["orientations"], axis=-1, keepdims=True)
    with gsd.hoomd.open(path) as trajectory:
        assert len(trajectory) == len(frames["step"]) == 7
        for f, frame in enumerate(trajectory):
            assert frame.configuration.step == frames["step"][f]
            np.testing.assert_allclose(frame.configuration.box, [*lengths, 0, 0, 0], rtol=FLOAT32_TOLERANCE)
            assert frame.particles.N == len(sites)
            np.testing.assert_allclose(frame.particles.position, expected_positions, atol=FLOAT32_TOLERANCE * 3)
            np.testing.assert_allclose(frame.particles.orientation, q[f], atol=FLOAT32_TOLERANCE)


def test_write_gsd_refuses_mismatched_arrays(tmp_path: Path):
    q = np.tile([1.0, 0, 0, 0], (2, 3, 1))
    with pytest.raises(ValueError, match="^orientations: 3 rotors per frame, but sites has 2"):
        quatrot.write_gsd(tmp_path / "x.gsd", np.zeros((2, 3)), q, [0, 1])
    with pytest.raises(ValueError, match="^steps: 1 steps for 2 frames"):
        quatrot.write_gsd(tmp_path / "x.gsd", np.zeros((3, 3)), q, [0])


def test_dielectric_workflow_on_the_dipole_builtins():
    """The dipole lattice built-ins record M by default: the Ewald one gives
    eps with no edit; the canonical one (truncated sum) is refused with the
    reason, and gives eps once its boundary is the Ewald sum."""
    import tomllib

    eps = quatrot.run_dielectric_constant(quatrot.run("dipole_lattice_sc", steps=40))
    assert np.isfinite(eps["epsilon"]) and eps["epsilon"] > 1
    with pytest.raises(ValueError, match="cutoff"):
        quatrot.run_dielectric_constant(quatrot.run("dipole_lattice_sc_langevin", steps=40))
    scene = tomllib.loads(quatrot.builtin_scenes()["dipole_lattice_sc_langevin"])
    scene["interactions"]["boundary"] = {"kind": "periodic"}
    scene["rotors"]["cells"] = 4
    eps = quatrot.run_dielectric_constant(quatrot.run(scene, steps=40), temperature=1.0)
    assert np.isfinite(eps["epsilon"]) and eps["epsilon"] > 1


def test_what_the_analysis_fuzz_found():
    """Issue 37, item 10: an axis of 1e200 gave C1 = 0 (its norm overflowed
    to a zero "unit" axis) and one of 1e-300 was refused as zero; a bad axis
    was named `axes_body`, a name only the Rust library has; a series of
    1e231 gave an infinite blocking error; a `series` name that is not
    valid text raised a `UnicodeEncodeError` naming nothing; 10^5 axes of
    10^5 frames aborted the process on a failed allocation."""
    q = random_walk(8, 3, seed=4)
    reference = quatrot.orientational_correlations(q, 0.1, axes=[0.0, 0.6, 0.8])["c1"]
    for scale in (1e200, 1e-300):
        c1 = quatrot.orientational_correlations(q, 0.1, axes=np.array([0.0, 0.6, 0.8]) * scale)["c1"]
        np.testing.assert_allclose(c1, reference, rtol=0, atol=DOUBLE_TOLERANCE)
    order = quatrot.order_parameters(q[0], axis=[0.0, 0.0, 1e-310], direction=[1e300, 0.0, 0.0])
    np.testing.assert_allclose(order["p1_direction"], quatrot.order_parameters(q[0], direction=[1.0, 0.0, 0.0])["p1_direction"], rtol=0, atol=DOUBLE_TOLERANCE)
    with pytest.raises(ValueError, match=r"^axes: must be finite and nonzero, got \[0, 0, 0\]$"):
        quatrot.orientational_correlations(q, 0.1, axes=[0.0, 0.0, 0.0])
    with pytest.raises(ValueError, match=r"^axes\[1\]: must be finite and nonzero, got \[0, 0, 0\]$"):
        quatrot.orientational_correlations(q, 0.1, axes=[[1.0, 0.0, 0.0], [0.0, 0.0, 0.0]])
    with pytest.raises(ValueError, match=r"^series: its mean or variance overflows float64 \(values up to 3e231\)"):
        quatrot.block_average([1e231, -3e231, 2e231])
    many_axes = np.broadcast_to([1.0, 0.0, 0.0], (100_000, 3))  # 10^5 x 10^5 frames: terabytes
    with pytest.raises(ValueError, match=r"^axes, orientations: needs about .* of memory, more than the limit"):
        quatrot.orientational_correlations(np.broadcast_to(q[:1], (100_000, 3, 4)), 0.1, axes=many_axes)
    run = {"summary": {"interactions": None}, "series": {}}
    with pytest.raises(ValueError, match=r"^series: not valid text \(a lone surrogate\)$"):
        quatrot.run_dielectric_constant(run, series="bad\ud800")
