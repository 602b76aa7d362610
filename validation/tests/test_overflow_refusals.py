"""Results that would overflow or underflow to inf or NaN are refused with
an error naming the argument, and nothing that a user passes panics (issue
37): each case here returned inf or NaN, or raised `PanicException`, before.
Valid extremes (a tiny or huge quaternion) give the result of their unit
quaternion instead."""

import numpy as np
import pytest
import quatrot

H = np.sqrt(0.5)


def test_huge_and_tiny_orientations_give_the_order_of_their_unit_quaternions():
    extreme = np.array([[[1e300, 1e300, 0.0, 0.0], [0.0, 0.0, 1e-300, 0.0], [1.0, 0.0, 0.0, 0.0]]])
    unit = np.array([[[H, H, 0.0, 0.0], [0.0, 0.0, 1.0, 0.0], [1.0, 0.0, 0.0, 0.0]]])
    got, want = quatrot.order_parameters(extreme), quatrot.order_parameters(unit)
    for key in ("p2", "p1", "director", "q_tensor", "cos_director"):
        np.testing.assert_allclose(got[key], want[key], rtol=0, atol=1e-15, err_msg=key)
        assert np.all(np.isfinite(got[key])), key


def test_an_overflowing_angular_velocity_correlation_is_refused():
    omega = np.full((4, 2, 3), 1e200)
    with pytest.raises(ValueError, match=r"^omega: the correlation is not finite: the values. products overflow float64"):
        quatrot.angular_velocity_correlation(omega, 0.1)


def test_lag_times_that_overflow_are_refused():
    q = np.tile([1.0, 0.0, 0.0, 0.0], (3, 2, 1))
    with pytest.raises(ValueError, match=r"^dt: the time of lag 2 overflows float64, got 1e308"):
        quatrot.orientational_correlations(q, 1e308)


def test_no_axis_is_an_error_not_a_panic():
    q = np.tile([1.0, 0.0, 0.0, 0.0], (3, 2, 1))
    with pytest.raises(ValueError, match=r"^axes: needs at least one axis"):
        quatrot.orientational_correlations(q, 0.1, axes=np.zeros((0, 3)))


@pytest.mark.parametrize(
    "scale, volume, temperature, message",
    [
        (1.0, 1e-320, 1.0, r"^volume, temperature: 4 pi / \(9 V T\) overflows float64"),
        (1.0, 1.0, 1e-320, r"^volume, temperature: 4 pi / \(9 V T\) overflows float64"),
        (1e200, 1.0, 1.0, r"^dipoles: \|M\|\^2 overflows float64"),
        (1e75, 1e-160, 1.0, r"^volume, temperature: eps = inf is not finite"),
        # The blocking error of F (values near 1e300) overflows too: refused
        # first (issue 37's analysis fuzz: block_average returned inf).
        (1e150, 1e-150, 1e-10, r"^dipoles: \|M - <M>\|\^2: its mean or variance overflows float64"),
    ],
)
def test_a_dielectric_constant_that_overflows_is_refused(scale, volume, temperature, message):
    dipoles = scale * np.random.default_rng(5).standard_normal((64, 3))
    with pytest.raises(ValueError, match=message):
        quatrot.dielectric_constant(dipoles, volume, temperature)


def test_an_empty_out_dir_is_refused_not_the_current_directory(tmp_path, monkeypatch):
    """`out_dir=''` used to write into the current directory, replacing a
    user's `energies.csv` there."""
    monkeypatch.chdir(tmp_path)
    (tmp_path / "energies.csv").write_text("a user's table")
    with pytest.raises(quatrot.SceneError, match=r'^out_dir: must be a folder\'s path, got an empty one'):
        quatrot.run("dipole_lattice_sc", out_dir="", steps=2)
    assert [p.name for p in tmp_path.iterdir()] == ["energies.csv"]
    assert (tmp_path / "energies.csv").read_text() == "a user's table"


def test_an_internal_panic_is_the_modules_error():
    """A Rust panic would reach Python as pyo3's `PanicException`, a
    `BaseException` that `except Exception` does not catch (issue 37:
    `orientational_correlations(q, 0.1, axes=np.zeros((0, 3)))` raised one).
    A planted panic comes out as `quatrot.InternalError`, naming the
    function; every native function is guarded."""
    with pytest.raises(quatrot.InternalError, match="^_panic_for_tests: internal error of quatrot .*: planted$"):
        quatrot._native._panic_for_tests("planted")
    assert issubclass(quatrot.InternalError, Exception)
    import types

    for module in (quatrot._native, quatrot.quaternion):
        native = [n for n, v in vars(module).items() if isinstance(v, types.BuiltinFunctionType)]
        assert native == [], f"{module.__name__}: unguarded {native}"
    assert quatrot.run is quatrot._native.run and quatrot.run.__wrapped__.__name__ == "run"


def test_a_gsd_box_beyond_float32_is_refused(tmp_path):
    """GSD stores float32: coordinates beyond its range were written as inf
    and reported as success."""
    sites = np.array([[0.0, 0.0, 0.0], [1e39, 0.0, 0.0]])
    q = np.tile([1.0, 0.0, 0.0, 0.0], (1, 2, 1))
    with pytest.raises(ValueError, match=r"^sites: the box edge 0 \(1e39\) is beyond the range of GSD's float32"):
        quatrot.write_gsd(tmp_path / "t.gsd", sites, q, [0])
    assert not (tmp_path / "t.gsd").exists()
