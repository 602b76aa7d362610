"""Conventions of eqs 1-10 (quaternion algebra, the matrix A of eq 7, Euler angles, the sandwich of eq 9, the angular velocity of eq 10): quatrot's Python bindings against ASE, scipy and nalgebra on seeded random inputs, the printed forms that the note gets wrong, and the Rust tests that back ERRATA.md.

Agreement is to round-off (1e-12) on unit quaternions, unit-scale vectors and
matrices; Euler triples include theta = 0, pi and 1e-9 from them."""

from __future__ import annotations

import re
import subprocess
import sys
from pathlib import Path

import ase
import numpy as np
import scipy
from ase import Atoms
from ase.build import molecule
from ase.quaternions import Quaternion
from scipy.spatial.transform import Rotation

import quatrot
from quatrot import quaternion as qr
from validation.shared.check import Check, Context
from validation.shared.frames import (
    axis_angle_degrees,
    euler_y_to_ase_euler_rotate,
    euler_y_to_ase_zyz,
    same_rotation,
    scipy_q_dot,
    scipy_rotation,
    scipy_rotation_from_euler_y,
)

ROOT = Path(__file__).resolve().parents[2]
ROUND_OFF = 1e-12  # both codes round-off accurate on unit-scale numbers
FD = 1e-8  # central difference with h = 1e-5 (truncation ~1e-10, round-off ~1e-11)
AGREE = 1e-6  # a printed form "agrees" on a sample when within this; the errata need it never to
SINGULAR = [0.0, np.pi, 1e-9, np.pi - 1e-9]


def _nalgebra_version() -> str:
    lock = (ROOT / "Cargo.lock").read_text()
    found = re.search(r'name = "nalgebra"\nversion = "([^"]+)"', lock)
    return found.group(1) if found else "unknown"


def _inputs(ctx: Context):
    rng = np.random.default_rng(ctx.seed)
    n = 32 if ctx.quick else 2000
    q = rng.normal(size=(n, 4))
    q /= np.linalg.norm(q, axis=1, keepdims=True)
    v = rng.normal(size=(n, 3))
    angles = np.column_stack([rng.uniform(-np.pi, np.pi, n), np.arccos(rng.uniform(-1, 1, n)), rng.uniform(-np.pi, np.pi, n)])
    singular = np.column_stack([rng.uniform(-np.pi, np.pi, 4 * 8), np.repeat(SINGULAR, 8), rng.uniform(-np.pi, np.pi, 4 * 8)])
    return q, v, np.vstack([angles, singular])


def _printed_product(p, q):
    """Eq 2 as printed: (p0 q0 - p.q, p0 q + q0 p - p x q)."""
    scalar = p[:, 0] * q[:, 0] - np.sum(p[:, 1:] * q[:, 1:], axis=1)
    vector = p[:, :1] * q[:, 1:] + q[:, :1] * p[:, 1:] - np.cross(p[:, 1:], q[:, 1:])
    return np.column_stack([scalar, vector])


def _pure(v):
    return np.column_stack([np.zeros(len(v)), v])


def _goldstein_bottom_row(angles, angle_index):
    """Bottom row of Goldstein's (B-3y): (sin theta cos x, sin theta sin x, cos theta),
    x = phi (correct) or psi (the p607 printing, footnote 4)."""
    theta, x = angles[:, 1], angles[:, angle_index]
    return np.column_stack([np.sin(theta) * np.cos(x), np.sin(theta) * np.sin(x), np.cos(theta)])


def _rows_err(a, b):
    """Per-sample largest absolute difference."""
    return np.abs(np.asarray(a) - np.asarray(b)).reshape(len(a), -1).max(axis=1)


def _sign_blind_err(a, b):
    return np.minimum(_rows_err(a, b), _rows_err(a, -np.asarray(b)))


def errata_citations(text: str) -> list[tuple[str, str]]:
    """The tests cited in ERRATA.md as `file::name` (or `::name` after a cited file)."""
    cited, last = [], None
    for path, name in re.findall(r"`((?:tests|validation/tests)/[\w/]+\.(?:rs|py))?::(\w+)`", text):
        last = path or last
        if last:
            cited.append((last, name))
    return cited


def _errata_tests() -> tuple[float, str]:
    """Runs every test cited in ERRATA.md: (number not passing, summary)."""
    cited = errata_citations((ROOT / "ERRATA.md").read_text())
    rust = sorted({(Path(f).stem, n) for f, n in cited if f.endswith(".rs")})
    python = sorted({f"{f}::{n}" for f, n in cited if f.endswith(".py")})
    cmd = ["cargo", "test", "--release"] + [a for stem in sorted({s for s, _ in rust}) for a in ("--test", stem)] + ["--"] + [n for _, n in rust]
    pycmd = [sys.executable, "-m", "pytest", "-q", "-rfE", "-p", "no:cacheprovider"] + python
    try:
        done = subprocess.run(cmd, cwd=ROOT, capture_output=True, text=True, timeout=1200)
        pydone = subprocess.run(pycmd, cwd=ROOT, capture_output=True, text=True, timeout=600)
    except (OSError, subprocess.TimeoutExpired) as error:
        return float("inf"), f"the ERRATA tests could not run: {error}"
    passed = set(re.findall(r"^test (\w+) \.\.\. ok$", done.stdout, re.M))
    missing = [f"{s}::{n}" for s, n in rust if n not in passed]
    if pydone.returncode != 0:
        # Each failing test by name (pytest -rfE's "FAILED path::name - reason" lines), else the tail.
        failing = re.findall(r"^(?:FAILED|ERROR) (\S+)", pydone.stdout, re.M)
        tail = pydone.stdout.strip().splitlines()[-1] if pydone.stdout.strip() else pydone.stderr[-500:]
        missing.extend(failing or [f"pytest: {tail}"])
    summary = (
        f"{len(rust)} Rust tests (`cargo test --release --test ... -- <names>`) and {len(python)} pytest tests cited in ERRATA.md; "
        + (f"not passing: {', '.join(missing)}" if missing else "all pass.")
    )
    return float(len(missing)), summary


def _plot(errors: dict[str, tuple[np.ndarray, float, bool]], out_dir: Path) -> Path:
    """Every sample of every check: a row per check, its tolerance as a black
    tick; printed forms of the errata in red, which must miss their tick."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    out_dir.mkdir(parents=True, exist_ok=True)
    names = list(errors)
    fig, ax = plt.subplots(figsize=(9, 0.3 * len(names) + 1.4))
    floor = 1e-18  # exact agreement is drawn at the floor of the log axis
    for i, name in enumerate(names):
        err, tolerance, erratum = errors[name]
        jitter = np.random.default_rng(i).uniform(-0.25, 0.25, len(err))
        ax.scatter(np.maximum(err, floor), i + jitter, s=3, alpha=0.5, color="tab:red" if erratum else "tab:blue")
        ax.plot([tolerance, tolerance], [i - 0.4, i + 0.4], color="k", lw=1.5)
    ax.set_xscale("log")
    ax.set_yticks(range(len(names)), names, fontsize=7)
    ax.set_xlabel("per-sample error, largest component (exact agreement drawn at 1e-18)")
    ax.set_title("blue: quatrot vs ASE, scipy, nalgebra; red: printed errata; black: tolerance", fontsize=9)
    fig.tight_layout()
    path = out_dir / "conventions_errors.png"
    fig.savefig(path, dpi=120)
    plt.close(fig)
    return path


class _Recorder:
    """The checks of this module and every sample of their errors (for the plot)."""

    def __init__(self):
        self.errors: dict[str, tuple[np.ndarray, float, bool]] = {}
        self.checks: list[Check] = []

    def check(self, name, proves, err, references, tolerance=ROUND_OFF, details=""):
        err = np.asarray(err, float)
        self.errors[name] = (err, tolerance, False)
        self.checks.append(Check(name, proves, tolerance, float(err.max()), references, details or f"{len(err)} samples."))

    def never_agrees(self, name, proves, err, references):
        """An erratum: the printed form must disagree on every sample; measured is
        the fraction of samples on which it agrees."""
        err = np.asarray(err, float)
        self.errors[name] = (err, AGREE, True)
        fraction = float(np.mean(err <= AGREE))
        details = f"Measured: the fraction of {len(err)} samples on which the printed form agrees (to {AGREE:g}); it must be 0. Its smallest miss is {err.min():.3g}, median {np.median(err):.3g}."
        self.checks.append(Check(name, proves, 0.0, fraction, references, details))


REFS_ASE = {"ASE": ase.__version__}
REFS_SCIPY = {"scipy": scipy.__version__}


def _product_checks(rec: _Recorder, q, rot) -> None:
    """Eqs 1-5: component order, product, conjugate and norm."""
    n = len(q)
    p = np.roll(q, 1, axis=0)
    rec.check(
        "eq 2 Hamilton product vs ASE Quaternion.__mul__",
        "quatrot's product is ASE's (scalar first, + p x q) on random unit quaternions; it says nothing about non-unit inputs.",
        _rows_err(qr.product(p, q), [(Quaternion(a) * Quaternion(b)).q for a, b in zip(p, q)]),
        REFS_ASE,
    )
    rec.check(
        "eq 2 Hamilton product vs scipy composition",
        "quatrot's P*Q is scipy's rotation composition R(P) R(Q) (sign-blind, scalar-first after reordering scipy's scalar-last output).",
        _sign_blind_err(qr.product(p, q), (scipy_rotation(p) * rot).as_quat(scalar_first=True)),
        REFS_SCIPY,
    )
    rec.never_agrees(
        "erratum eq 2: printed - p x q, fraction agreeing with ASE",
        "The note's printed sign of the cross product is not the product ASE and scipy use for rotations (ERRATA.md E-2).",
        _sign_blind_err(_printed_product(p, q), [(Quaternion(a) * Quaternion(b)).q for a, b in zip(p, q)]),
        REFS_ASE,
    )
    rec.check(
        "eqs 3-5 conjugate is scipy's inverse, Q*Q~ = (|Q|^2, 0)",
        "The conjugate of eq 3 is the inverse rotation in scipy and Q*Q~ is (1, 0) for unit Q (eqs 4-5).",
        np.maximum(
            _sign_blind_err(qr.conjugate(q), rot.inv().as_quat(scalar_first=True)),
            _rows_err(qr.product(q, qr.conjugate(q)), np.tile([1.0, 0, 0, 0], (n, 1))),
        ),
        REFS_SCIPY,
    )


def _matrix_checks(rec: _Recorder, q, v, rot) -> None:
    """Eqs 6-7: the matrices A(Q) and R(Q)."""
    rec.check(
        "eq 7 A(Q) vs scipy as_matrix().T",
        "The printed A of eq 7 maps space to body: it is the transpose of scipy's active matrix.",
        _rows_err(qr.space_to_body_matrix(q), rot.as_matrix().transpose(0, 2, 1)),
        REFS_SCIPY,
    )
    rec.check(
        "eq 7 R(Q) = A^T vs ASE rotation_matrix()",
        "ASE's quaternion matrix is the active body-to-space R = A^T.",
        _rows_err(qr.body_to_space_matrix(q), [Quaternion(x).rotation_matrix() for x in q]),
        REFS_ASE,
    )
    rec.check(
        "eq 7 R(Q) vs nalgebra Rotation3",
        "nalgebra's UnitQuaternion -> Rotation3 of Q (built from Quaternion::new(q0, q1, q2, q3), stored [q1, q2, q3, q0]) is R(Q).",
        _rows_err(qr.body_to_space_matrix(q), qr.nalgebra_body_to_space_matrix(q)),
        {"nalgebra": _nalgebra_version()},
    )
    rec.check(
        "eq 6 r_b = A r_s vs scipy apply(inverse=True)",
        "space_to_body applies A and body_to_space applies R, as scipy's inverse and direct apply.",
        np.maximum(_rows_err(qr.space_to_body(q, v), rot.apply(v, inverse=True)), _rows_err(qr.body_to_space(q, v), rot.apply(v))),
        REFS_SCIPY,
    )


def _euler_checks(rec: _Recorder, angles, generic: slice) -> None:
    """Eq 8 and footnote 4: Euler angles (`generic` selects the random triples)."""
    q_euler = qr.from_euler_y(angles)
    scipy_euler = scipy_rotation_from_euler_y(angles)
    rec.check(
        "eq 8 y-convention vs scipy from_euler('ZYZ')",
        "The note's eq 8 is scipy's intrinsic ZYZ of (phi, theta, psi), including theta = 0, pi and 1e-9 from them.",
        _sign_blind_err(q_euler, scipy_euler.as_quat(scalar_first=True)),
        REFS_SCIPY,
    )
    rec.check(
        "eq 8 y-convention vs ASE from_euler_angles(psi, theta, phi)",
        "ASE's zyz Euler quaternion with the angles reversed is the note's eq 8.",
        _sign_blind_err(q_euler, [Quaternion.from_euler_angles(*a, mode="zyz").q for a in euler_y_to_ase_zyz(angles)]),
        REFS_ASE,
    )
    back = qr.from_euler_y(qr.to_euler_y(q_euler))
    rec.check(
        "eq 8 inverse: Q -> Euler -> Q, incl. theta = 0, pi, 1e-9 from them",
        "to_euler_y recovers the rotation to round-off everywhere, where ASE's and scipy's inverses lose O(theta) near the singularities.",
        _rows_err(qr.space_to_body_matrix(back), scipy_euler.as_matrix().transpose(0, 2, 1)),
        REFS_SCIPY,
    )
    a_rows = scipy_euler.as_matrix().transpose(0, 2, 1)[:, 2, :]
    rec.check(
        "footnote 4: Goldstein (B-3y) bottom row with phi vs scipy",
        "With phi in its bottom row, Goldstein's y-convention matrix is scipy's ZYZ (the note's correction of p607 is right).",
        _rows_err(_goldstein_bottom_row(angles[generic], 0), a_rows[generic]),
        REFS_SCIPY,
    )
    rec.never_agrees(
        "erratum Goldstein p607: psi in bottom row, fraction agreeing with scipy",
        "Goldstein's printed bottom row (psi for phi) is wrong, as the note's footnote 4 says.",
        _rows_err(_goldstein_bottom_row(angles[generic], 2), a_rows[generic]),
        REFS_SCIPY,
    )


def _sandwich_and_velocity_checks(rec: _Recorder, q, v, rot) -> None:
    """Eq 9 (the sandwich) and eq 10 (the angular velocity), each with the
    printed product of eq 2 as an erratum."""
    sandwich = qr.product(qr.product(qr.conjugate(q), _pure(v)), q)[:, 1:]
    rec.check(
        "eq 9 Q~*(0,r_s)*Q vs scipy apply(inverse=True)",
        "With the Hamilton product (and the tilde read as the conjugate of eq 3), eq 9 gives the body components A r_s.",
        _rows_err(sandwich, rot.apply(v, inverse=True)),
        REFS_SCIPY,
    )
    printed = _printed_product(_printed_product(qr.conjugate(q), _pure(v)), q)[:, 1:]
    rec.never_agrees(
        "erratum eq 2 in eq 9: fraction agreeing with scipy's A r_s",
        "With the printed product, eq 9 gives R r_s, not A r_s: the printed eq 2 contradicts eqs 6-7.",
        _rows_err(printed, rot.apply(v, inverse=True)),
        REFS_SCIPY,
    )
    omega_body = v
    omega_space = rot.apply(omega_body)
    rec.check(
        "eq 10 Q' (body and space forms) vs scipy motion",
        "1/2 Q*(0,w_b) and 1/2 (0,w_s)*Q are the time derivative of scipy's R(Q) Rot(w_b t) = Rot(w_s t) R(Q) (central differences).",
        np.maximum(
            _rows_err(qr.q_dot_from_omega_body(q, omega_body), scipy_q_dot(q, omega_body, "body")),
            _rows_err(qr.q_dot_from_omega_space(q, omega_space), scipy_q_dot(q, omega_space, "space")),
        ),
        REFS_SCIPY,
        tolerance=FD,
    )
    rec.never_agrees(
        "erratum eq 2 in eq 10: fraction agreeing with scipy's Q'",
        "With the printed product, 1/2 Q*(0,w_b) turns the body about w_b taken in the space frame.",
        _rows_err(0.5 * _printed_product(q, _pure(omega_body)), scipy_q_dot(q, omega_body, "body")),
        REFS_SCIPY,
    )
    rec.check(
        "ln / exp vs scipy as_rotvec / from_rotvec",
        "quatrot's logarithm and exponential map are scipy's rotation vectors (angle in [0, pi]).",
        np.maximum(_rows_err(qr.ln(q), rot.as_rotvec()), _sign_blind_err(qr.exp(rot.as_rotvec()), q)),
        REFS_SCIPY,
    )


def _ase_atoms_checks(rec: _Recorder, q, angles, n_atoms: int) -> None:
    """ASE's Atoms methods moving an NH3 body template."""
    template = molecule("NH3").positions
    center = np.array([0.25, -1.5, 2.0])
    moved, expected = [], []
    for x in q[:n_atoms]:
        atoms = Atoms("NH3", positions=template + center)
        axis, angle_deg = axis_angle_degrees(x)
        atoms.rotate(angle_deg, axis, center=center)
        moved.append(atoms.positions)
        expected.append(center + qr.body_to_space(x, template.copy()))
    rec.check(
        "Atoms.rotate (axis, degrees, center) vs body_to_space",
        "ASE's Atoms.rotate with Q's axis and angle (degrees) about the centre moves an NH3 body template to center + R(Q) r_b.",
        _rows_err(moved, expected),
        REFS_ASE,
    )
    moved, expected = [], []
    for a, deg in zip(angles, euler_y_to_ase_euler_rotate(angles)):
        atoms = Atoms("NH3", positions=template + center)
        atoms.euler_rotate(*deg, center=center)
        moved.append(atoms.positions)
        expected.append(center + qr.space_to_body(qr.from_euler_y(a), template.copy()))
    rec.check(
        "Atoms.euler_rotate (x-convention, degrees) vs space_to_body",
        "ASE's euler_rotate with (phi + 90, theta, psi - 90) degrees applies the note's passive A(phi, theta, psi), singular triples included.",
        _rows_err(moved, expected),
        REFS_ASE,
    )


def _errata_check() -> Check:
    """The Rust tests that ERRATA.md cites, run and counted."""
    failed, summary = _errata_tests()
    return Check(
        "ERRATA.md: every cited test passes (count not passing)",
        "Each erratum and trap in ERRATA.md is backed by a test that runs and passes: the printed form fails its identity by a margin and the correction passes. It proves nothing about rows without a cited test.",
        0.0,
        failed,
        {"quatrot": quatrot.__version__} | REFS_ASE | REFS_SCIPY | {"nalgebra": _nalgebra_version()},
        summary,
    )


def run(ctx: Context) -> list[Check]:
    q, v, angles = _inputs(ctx)
    rot = scipy_rotation(q)
    rec = _Recorder()
    _product_checks(rec, q, rot)
    _matrix_checks(rec, q, v, rot)
    # The random Euler triples come first; the singular ones follow.
    _euler_checks(rec, angles, slice(0, len(q)))
    _sandwich_and_velocity_checks(rec, q, v, rot)
    _ase_atoms_checks(rec, q, angles, 16 if ctx.quick else 200)
    checks = rec.checks
    checks[0].plots.append(_plot(rec.errors, ctx.out_dir))
    checks[0].details += " The plot shows every sample of every round-off check of this module."
    if not ctx.quick:
        checks.append(_errata_check())
    return checks
