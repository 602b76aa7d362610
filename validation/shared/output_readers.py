"""Independent references for what a scene records (docs/scenes.md), shared by
the tests and the ``scene_outputs`` check: the multipole quantities (``M``,
``M2``, ``P1_dipole``, ``P2_dipole``, ``P2_quadrupole`` with their directors)
recomputed with scipy's rotations and numpy's symmetric eigensolver from a
run's quaternions and its body multipoles, and a run's GSD trajectory read
back with the ``gsd`` package."""

from __future__ import annotations

from pathlib import Path

import gsd.hoomd
import numpy as np

from validation.shared.frames import scipy_rotation


def space_axes(orientations: np.ndarray, axes_body: np.ndarray) -> np.ndarray:
    """``u = R(Q) e`` for orientations (frames, n, 4) and one body axis per
    rotor (n, 3): (frames, n, 3). scipy normalises the quaternions."""
    frames, n, _ = orientations.shape
    rotated = scipy_rotation(orientations.reshape(-1, 4)).apply(np.tile(axes_body, (frames, 1)))
    return rotated.reshape(frames, n, 3)


def order(u: np.ndarray) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """P1, P2 and the director of unit axes u (frames, n, 3): the largest
    eigenvalue of <3/2 u u - 1/2 I> and its eigenvector signed along <u>,
    and P1 = <u>.d."""
    q = 1.5 * np.einsum("fna,fnb->fab", u, u) / u.shape[1] - 0.5 * np.eye(3)
    values, vectors = np.linalg.eigh(q)
    p2, d = values[:, -1], vectors[:, :, -1]
    mean = u.mean(axis=1)
    d *= np.where(np.sum(d * mean, axis=1) < 0, -1.0, 1.0)[:, None]
    return np.sum(mean * d, axis=1), p2, d


def quadrupole_axis(theta: np.ndarray) -> np.ndarray:
    """The body axis of a quadrupole: the eigenvector of its eigenvalue
    largest in magnitude, its first nonzero component positive."""
    values, vectors = np.linalg.eigh(theta)
    e = vectors[:, np.argmax(np.abs(values))]
    return e * np.sign(e[np.flatnonzero(e)[0]])


def expected_columns(orientations: np.ndarray, dipoles: np.ndarray | None, quadrupoles: np.ndarray | None) -> dict[str, np.ndarray]:
    """The columns of every multipole quantity the rotors carry, per frame,
    for body dipoles (n, 3) and quadrupoles (n, 3, 3) (None: not carried)."""
    out = {}
    if dipoles is not None:
        m = np.einsum("fna->fa", space_axes(orientations, dipoles))
        out |= {"M_x": m[:, 0], "M_y": m[:, 1], "M_z": m[:, 2], "M2": np.sum(m * m, axis=1)}
        p1, p2, d = order(space_axes(orientations, dipoles / np.linalg.norm(dipoles, axis=1)[:, None]))
        out |= {"P1_dipole": p1, "P2_dipole": p2} | {f"director_dipole_{c}": d[:, k] for k, c in enumerate("xyz")}
    if quadrupoles is not None:
        axes = np.array([quadrupole_axis(t) for t in quadrupoles])
        _, p2, d = order(space_axes(orientations, axes))
        out |= {"P2_quadrupole": p2} | {f"director_quadrupole_{c}": d[:, k] for k, c in enumerate("xyz")}
    return out


def column_differences(series: dict[str, np.ndarray], expected: dict[str, np.ndarray]) -> dict[str, float]:
    """The largest difference per column between a recorded series and the
    expected columns (every expected column must be recorded)."""
    return {name: float(np.max(np.abs(series[name] - values))) for name, values in expected.items()}


def gsd_differences(path: Path, result: dict, box_lengths: np.ndarray | None, margin: float = 1.0) -> dict[str, float]:
    """A run's ``trajectory.gsd`` read with ``gsd.hoomd`` against the run
    (``quatrot.run``'s dict with the trajectory kept): the largest
    differences of the steps, the box (the periodic box, or the sites'
    bounding box grown by ``margin``), the positions (wrapped into HOOMD's
    centred box) and the orientations (normalised quaternions), and the
    frame count's difference."""
    frames, sites = result["trajectory"], result["sites"]
    if box_lengths is None:
        corner = sites.min(axis=0) - margin
        lengths = sites.max(axis=0) - sites.min(axis=0) + 2 * margin
    else:
        corner, lengths = np.zeros(3), np.asarray(box_lengths, float)
    positions = (sites - corner) % lengths - lengths / 2
    q = frames["orientations"] / np.linalg.norm(frames["orientations"], axis=-1, keepdims=True)
    out = {"frames": 0.0, "step": 0.0, "box": 0.0, "position": 0.0, "orientation": 0.0}
    with gsd.hoomd.open(path) as trajectory:
        out["frames"] = float(abs(len(trajectory) - len(frames["step"])))
        for f, frame in enumerate(trajectory):
            out["step"] = max(out["step"], float(abs(int(frame.configuration.step) - int(frames["step"][f]))))
            box = np.asarray(frame.configuration.box, float)
            out["box"] = max(out["box"], float(np.max(np.abs(box - [*lengths, 0, 0, 0]) / np.max(lengths))))
            out["position"] = max(out["position"], float(np.max(np.abs(frame.particles.position - positions)) / np.max(lengths)))
            out["orientation"] = max(out["orientation"], float(np.max(np.abs(frame.particles.orientation - q[f]))))
    return out
