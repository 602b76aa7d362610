"""The bindings' conventions against ASE and scipy called live on fresh random
inputs (seeded), the traps between the codes, and the bindings' input errors."""

import re

import numpy as np
import pytest
from ase import Atoms
from ase.build import molecule
from ase.quaternions import Quaternion
from scipy.spatial.transform import Rotation

from quatrot import quaternion as qr
from validation.shared.frames import (
    axis_angle_degrees,
    euler_y_to_ase_euler_rotate,
    euler_y_to_ase_zyz,
    same_rotation,
    scipy_q_dot,
    scipy_rotation,
    scipy_rotation_from_euler_y,
)

LIVE = 1e-12  # both sides round-off accurate on unit-scale numbers
FD = 1e-8  # central difference, h = 1e-5: truncation h^2 |Q'''| ~ 1e-10, round-off eps/h ~ 1e-11
N = 64
SEED = 7


@pytest.fixture
def rng():
    return np.random.default_rng(SEED)


@pytest.fixture
def quats(rng):
    q = rng.normal(size=(N, 4))
    return q / np.linalg.norm(q, axis=1, keepdims=True)


@pytest.fixture
def euler(rng):
    a = np.column_stack([rng.uniform(-np.pi, np.pi, N), np.arccos(rng.uniform(-1, 1, N)), rng.uniform(-np.pi, np.pi, N)])
    a[:4, 1] = [0.0, np.pi, 1e-9, np.pi - 1e-9]
    return a


def test_matrices_match_scipy_ase_and_nalgebra(quats):
    r = qr.body_to_space_matrix(quats)
    assert np.abs(r - scipy_rotation(quats).as_matrix()).max() < LIVE
    assert np.abs(r - np.array([Quaternion(q).rotation_matrix() for q in quats])).max() < LIVE
    assert np.abs(qr.space_to_body_matrix(quats) - r.transpose(0, 2, 1)).max() == 0.0
    assert np.abs(qr.nalgebra_body_to_space_matrix(quats) - r).max() < LIVE


def test_rotated_vectors_match_scipy_and_ase(quats, rng):
    v = rng.normal(size=(N, 3))
    rot = scipy_rotation(quats)
    assert np.abs(qr.body_to_space(quats, v) - rot.apply(v)).max() < LIVE
    assert np.abs(qr.space_to_body(quats, v) - rot.apply(v, inverse=True)).max() < LIVE
    assert np.abs(qr.body_to_space(quats, v) - np.array([Quaternion(q).rotate(x) for q, x in zip(quats, v)])).max() < LIVE


def test_product_matches_ase_and_scipy_composition(quats):
    p, q = quats, np.roll(quats, 1, axis=0)
    ours = qr.product(p, q)
    assert np.abs(ours - np.array([(Quaternion(a) * Quaternion(b)).q for a, b in zip(p, q)])).max() < LIVE
    assert same_rotation(ours, (scipy_rotation(p) * scipy_rotation(q)).as_quat(scalar_first=True)) < LIVE
    assert np.abs(qr.product(quats, qr.conjugate(quats)) - [1, 0, 0, 0]).max() < LIVE
    assert np.abs(qr.norm(quats) - 1).max() < LIVE


def test_euler_y_matches_scipy_zyz_and_ase(euler):
    q = qr.from_euler_y(euler)
    assert same_rotation(q, scipy_rotation_from_euler_y(euler).as_quat(scalar_first=True)) < LIVE
    ase_q = np.array([Quaternion.from_euler_angles(*a, mode="zyz").q for a in euler_y_to_ase_zyz(euler)])
    assert same_rotation(q, ase_q) < LIVE
    back = qr.to_euler_y(q)
    assert np.abs(qr.space_to_body_matrix(qr.from_euler_y(back)) - qr.space_to_body_matrix(q)).max() < LIVE
    generic = slice(4, None)  # scipy's as_euler treats theta within ~1e-7 of 0, pi as gimbal lock
    scipy_back = scipy_rotation(q[generic]).as_euler("ZYZ")
    wrapped = np.angle(np.exp(1j * (back[generic] - scipy_back)))
    assert np.abs(wrapped).max() < LIVE


def test_ase_atoms_rotate_and_euler_rotate(quats, euler):
    template = molecule("NH3").positions
    center = np.array([0.5, 1.0, -2.0])
    for q in quats[:16]:
        atoms = Atoms("NH3", positions=template + center)
        axis, angle_deg = axis_angle_degrees(q)
        atoms.rotate(angle_deg, axis, center=center)
        assert np.abs(atoms.positions - (center + qr.body_to_space(q, template.copy()))).max() < LIVE
    for angles, deg in zip(euler[:16], euler_y_to_ase_euler_rotate(euler[:16])):
        atoms = Atoms("NH3", positions=template + center)
        atoms.euler_rotate(*deg, center=center)
        a = qr.space_to_body_matrix(qr.from_euler_y(angles))
        assert np.abs(atoms.positions - (center + template @ a.T)).max() < LIVE


def test_axis_angle_exp_ln_match_scipy_and_ase(quats):
    assert np.abs(qr.ln(quats) - scipy_rotation(quats).as_rotvec()).max() < LIVE
    rotvec = scipy_rotation(quats).as_rotvec()
    assert same_rotation(qr.exp(rotvec), Rotation.from_rotvec(rotvec).as_quat(scalar_first=True)) < LIVE
    axis, angle = qr.to_axis_angle(quats)
    for q, a, t in zip(quats, axis, angle):
        ase_axis, ase_angle = Quaternion(q if q[0] >= 0 else -q).axis_angle()
        assert abs(t - ase_angle) < LIVE and np.abs(a - ase_axis).max() < LIVE
    assert same_rotation(qr.from_axis_angle(axis, angle), quats) < LIVE
    assert np.array_equal(qr.exp(np.zeros(3)), [1.0, 0.0, 0.0, 0.0])
    zero_axis, zero_angle = qr.to_axis_angle(np.array([1.0, 0.0, 0.0, 0.0]))
    assert zero_angle == 0.0 and np.array_equal(zero_axis, np.zeros(3))


def test_q_dot_is_the_derivative_of_scipy_motion(quats, rng):
    """Eq 10 against motion built by scipy alone: Q(t) = R(Q) Rot(w_b t) = Rot(w_s t) R(Q)."""
    omega_body = rng.normal(size=(N, 3))
    omega_space = scipy_rotation(quats).apply(omega_body)
    assert np.abs(scipy_q_dot(quats, omega_body, "body") - qr.q_dot_from_omega_body(quats, omega_body)).max() < FD
    assert np.abs(scipy_q_dot(quats, omega_space, "space") - qr.q_dot_from_omega_space(quats, omega_space)).max() < FD
    q_dot = qr.q_dot_from_omega_body(quats, omega_body)
    assert np.abs(qr.omega_body_from_q_dot(quats, q_dot) - omega_body).max() < LIVE
    assert np.abs(qr.omega_space_from_q_dot(quats, q_dot) - omega_space).max() < LIVE


def test_from_matrix_matches_scipy(quats):
    r = scipy_rotation(quats).as_matrix()
    q = qr.from_body_to_space_matrix(r)
    assert (q[:, 0] >= 0).all() and same_rotation(q, quats) < LIVE
    assert same_rotation(qr.from_space_to_body_matrix(r.transpose(0, 2, 1)), quats) < LIVE


# Traps between the codes (ERRATA.md, second table).


def test_trap_scipy_as_quat_is_scalar_last(quats):
    rot = scipy_rotation(quats)
    assert np.abs(rot.as_quat()[:, [3, 0, 1, 2]] - rot.as_quat(scalar_first=True)).max() == 0.0
    assert same_rotation(Rotation.from_quat(quats).as_quat(scalar_first=True), quats) > 1e-3


def test_trap_scipy_lower_case_euler_is_extrinsic(euler):
    generic = euler[4:]
    intrinsic = scipy_rotation_from_euler_y(generic).as_matrix()
    assert np.abs(Rotation.from_euler("zyz", generic[:, ::-1]).as_matrix() - intrinsic).max() < LIVE
    assert np.abs(Rotation.from_euler("zyz", generic).as_matrix() - intrinsic).max() > 1e-3


def test_trap_ase_from_euler_angles_takes_psi_first(euler):
    generic = euler[4:]
    ours = qr.from_euler_y(generic)
    note_order = np.array([Quaternion.from_euler_angles(*a, mode="zyz").q for a in generic])
    assert same_rotation(ours, note_order) > 1e-3


def test_trap_ase_euler_rotate_is_passive_x_convention_in_degrees(euler):
    template = molecule("NH3").positions
    angles = euler[10]
    expected = template @ qr.space_to_body_matrix(qr.from_euler_y(angles)).T
    for wrong in (angles, np.degrees(angles)):  # radians, or the y-convention angles as they are
        atoms = Atoms("NH3", positions=template.copy())
        atoms.euler_rotate(*wrong)
        assert np.abs(atoms.positions - expected).max() > 1e-3


# Bad input at the boundary.

Q = np.array([1.0, 0.0, 0.0, 0.0])
BAD = [
    (lambda: qr.norm("1, 0, 0, 0"), TypeError, "q: expected an array of numbers, got str"),
    (lambda: qr.conjugate([1.0, "x", 0.0, 0.0]), TypeError, "q: expected an array of numbers, got list"),
    (lambda: qr.norm(np.zeros((5, 3))), ValueError, "q: expected shape (n, 4) or (4,), got (5, 3)"),
    (lambda: qr.norm(np.zeros((2, 5, 4))), ValueError, "q: expected shape (n, 4) or (4,), got (2, 5, 4)"),
    (lambda: qr.body_to_space(Q, np.zeros(4)), ValueError, "v_body: expected shape (n, 3) or (3,), got (4,)"),
    (lambda: qr.from_body_to_space_matrix(np.zeros((3, 9))), ValueError, "r: expected shape (n, 3, 3) or (3, 3), got (3, 9)"),
    (lambda: qr.product(np.tile(Q, (5, 1)), np.tile(Q, (3, 1))), ValueError, "q: 3 items, but p has 5"),
    (lambda: qr.from_body_to_space_matrix(np.stack([np.eye(3), -np.eye(3)])), ValueError, "r[1]: not a proper rotation matrix"),
    (lambda: qr.from_axis_angle(np.zeros(3), np.array(0.5)), ValueError, "axis: must be finite and nonzero, got [0, 0, 0]"),
    (lambda: qr.ln(np.array([np.nan, 0.0, 0.0, 0.0])), ValueError, "q[0]: not finite (nan)"),
    (lambda: qr.ln(np.array([[1.0, 0.0, 0.0, 0.0], [0.0, 0.0, 0.0, 0.0]])), ValueError, "q[1]: quaternion is zero"),
    (lambda: qr.product(Q * 1e300, Q * 1e300), ValueError, "result[0]: not finite (inf) for finite arguments"),
]


@pytest.mark.parametrize("call,error,message", BAD, ids=[m.split(":")[0] + str(i) for i, (_, _, m) in enumerate(BAD)])
def test_bad_input_raises_a_clear_error(call, error, message):
    with pytest.raises(error, match=re.escape(message)):
        call()


def test_array_likes_are_converted_once(quats):
    """Lists, integer and float32 arrays and Python floats are converted to
    float64 (the float32 values exactly), giving the float64 results."""
    assert np.array_equal(qr.conjugate([1.0, 0.0, 0.0, 0.0]), qr.conjugate(Q))
    assert np.array_equal(qr.norm(np.array([1, 0, 0, 0])), qr.norm(Q))
    q32 = quats.astype(np.float32)
    assert np.array_equal(qr.norm(q32), qr.norm(q32.astype(np.float64)))
    assert np.array_equal(qr.from_axis_angle(np.ones(3), 0.5), qr.from_axis_angle(np.ones(3), np.array(0.5)))


def test_single_items_and_strided_views(quats):
    assert qr.product(quats[0], quats[1]).shape == (4,)
    assert qr.body_to_space_matrix(quats[0]).shape == (3, 3)
    assert qr.norm(quats[0]).shape == ()
    strided = quats[::2]
    assert np.array_equal(qr.conjugate(strided), qr.conjugate(np.ascontiguousarray(strided)))
    assert np.abs(qr.product(quats, quats[0]) - qr.product(quats, np.tile(quats[0], (N, 1)))).max() == 0.0
