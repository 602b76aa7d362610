"""Hostile input at the Python boundary (issue 19): every public function of
`quatrot` and `quatrot.quaternion`, found by introspection, refuses
non-finite numbers and zero quaternions with a `ValueError` naming the
argument and the first bad row, accepts array-likes (lists, float32,
strided and Fortran-order arrays) with the float64 result, and refuses bad
text with the module's error; integer arguments are range-checked and
results sized before allocation; scene dicts that nest too deep or refer
to themselves are refused with the path (the interpreter used to crash)."""

import copy
import inspect
import re
import tomllib

import numpy as np
import pytest

import quatrot
from quatrot import quaternion as qr

SEED = 20261123
N = 3  # rotors (items) in every batch below


def _rng():
    return np.random.default_rng(SEED)


def _unit(shape):
    q = _rng().normal(size=(*shape, 4))
    return q / np.linalg.norm(q, axis=-1, keepdims=True)


def _vectors(shape=(N,)):
    return _rng().normal(size=(*shape, 3))


def _quadrupoles():
    a = _rng().normal(size=(N, 3, 3))
    a = a + a.transpose(0, 2, 1)
    return a - np.trace(a, axis1=1, axis2=2)[:, None, None] * np.eye(3) / 3


def _sites():
    return np.array([[0.0, 0.0, 0.0], [1.1, 0.0, 0.0], [0.0, 1.3, 0.2]])


# One valid call of each public function (a factory of keyword arguments,
# given a temporary folder). A function missing here fails
# `test_every_public_function_has_a_valid_call`.
def _dielectric_run():
    """A short run of a small Ewald lattice recording M and T (what
    `run_dielectric_constant` reads)."""
    scene = tomllib.loads(quatrot.builtin_scenes()["dipole_lattice_sc"])
    scene["rotors"]["cells"] = 2
    scene["run"]["steps"] = 40
    scene["record"] = {"series": [{"name": "m", "every": 1, "quantities": ["M", "temperature"]}]}
    return quatrot.run(scene)


VALID = {
    "multipole_evaluate": lambda tmp: dict(
        sites=_sites(), orientations=_unit((N,)), dipoles_body=_vectors(), quadrupoles_body=_quadrupoles(),
        field=np.array([0.1, 0.0, 0.2]), field_gradient=np.diag([0.1, 0.2, -0.3]),
    ),
    "bodies_evaluate": lambda tmp: dict(
        body_types=[{"sites": [{"position": [0.0, 0.0, 0.0], "lennard_jones": {"epsilon": 1.0, "sigma": 1.0}, "dipole": [0.0, 0.0, 1.0]}],
                     "mass": 1.0, "inertia": np.eye(3) * 0.1}],
        positions=_sites(), orientations=_unit((N,)), velocities=_vectors(), box_lengths=np.array([6.0, 6.0, 6.0]),
        lj_cutoff=2.5, electrostatic_cutoff=2.5,
    ),
    "dlm_dipoles": lambda tmp: dict(
        sites=_sites(), dipoles_body=_vectors(), inertia=np.full(N, 0.5), orientations=_unit((N,)),
        omega_body=_vectors(), field=np.array([0.0, 0.0, 0.3]), dt=0.01, steps=3, split=False,
    ),
    "gear_corrections_table": lambda tmp: dict(
        sites=_sites(), inertia=np.tile([1.0, 1.0, 1.0], (N, 1)), orientations=_unit((N,)), omega_body=_vectors(),
        dipoles=_vectors(), dt=0.05, t_energy=0.5, t_error=0.2, t_stability=0.2,
    ),
    "orientational_correlations": lambda tmp: dict(orientations=_unit((6, N)), dt=0.1, axes=np.eye(3)[:2]),
    "angular_velocity_correlation": lambda tmp: dict(omega=_vectors((6, N)), dt=0.1),
    "order_parameters": lambda tmp: dict(orientations=_unit((N,)), axis=np.array([0.0, 0.0, 1.0]), direction=np.array([1.0, 0.0, 0.0])),
    "mean_squared_displacement": lambda tmp: dict(
        positions=_vectors((6, N)), dt=0.1, images=np.ones((6, N, 3)), box_lengths=np.array([5.0, 5.0, 5.0]),
        fit_window=np.array([0.1, 0.4]),
    ),
    "radial_distribution": lambda tmp: dict(positions=_vectors((4, N)), box_lengths=np.array([6.0, 6.0, 6.0]), r_max=2.0),
    "total_dipole": lambda tmp: dict(orientations=_unit((N,)), dipoles_body=_vectors()),
    "block_average": lambda tmp: dict(series=_rng().normal(size=64)),
    "dielectric_constant": lambda tmp: dict(dipoles=_vectors((64,)), volume=10.0, temperature=1.0),
    "run_dielectric_constant": lambda tmp: dict(run=_dielectric_run()),
    "write_gsd": lambda tmp: dict(path=str(tmp / "t.gsd"), sites=_sites(), orientations=_unit((2, N)), steps=[0, 1]),
    "run": lambda tmp: dict(scene="dipole_in_field", steps=2),
    "builtin_scenes": lambda tmp: dict(),
    "cli_main": lambda tmp: dict(argv=["quatrot", "scenes"]),
    "quaternion.product": lambda tmp: dict(p=_unit((N,)), q=_unit((N,))[::-1].copy()),
    "quaternion.conjugate": lambda tmp: dict(q=_unit((N,))),
    "quaternion.norm": lambda tmp: dict(q=_unit((N,)) * 2.0),
    "quaternion.space_to_body_matrix": lambda tmp: dict(q=_unit((N,))),
    "quaternion.body_to_space_matrix": lambda tmp: dict(q=_unit((N,))),
    "quaternion.nalgebra_body_to_space_matrix": lambda tmp: dict(q=_unit((N,))),
    "quaternion.space_to_body": lambda tmp: dict(q=_unit((N,)), v_space=_vectors()),
    "quaternion.body_to_space": lambda tmp: dict(q=_unit((N,)), v_body=_vectors()),
    "quaternion.from_euler_y": lambda tmp: dict(angles=_vectors()),
    "quaternion.to_euler_y": lambda tmp: dict(q=_unit((N,))),
    "quaternion.from_axis_angle": lambda tmp: dict(axis=_vectors(), angle=np.array([0.1, 0.2, 0.3])),
    "quaternion.to_axis_angle": lambda tmp: dict(q=_unit((N,))),
    "quaternion.exp": lambda tmp: dict(rotvec=_vectors()),
    "quaternion.ln": lambda tmp: dict(q=_unit((N,))),
    "quaternion.q_dot_from_omega_body": lambda tmp: dict(q=_unit((N,)), omega_body=_vectors()),
    "quaternion.q_dot_from_omega_space": lambda tmp: dict(q=_unit((N,)), omega_space=_vectors()),
    "quaternion.omega_body_from_q_dot": lambda tmp: dict(q=_unit((N,)), q_dot=_unit((N,)) * 0.1),
    "quaternion.omega_space_from_q_dot": lambda tmp: dict(q=_unit((N,)), q_dot=_unit((N,)) * 0.1),
    "quaternion.from_body_to_space_matrix": lambda tmp: dict(r=qr.body_to_space_matrix(_unit((N,)))),
    "quaternion.from_space_to_body_matrix": lambda tmp: dict(a=qr.space_to_body_matrix(_unit((N,)))),
}

QUATERNION_ARGUMENTS = {"p", "q", "orientations"}


def public_functions():
    """Every public callable of `quatrot` and `quatrot.quaternion` (not the
    exception classes, not the pure-Python subpackages)."""
    names = []
    for prefix, module in (("", quatrot), ("quaternion.", qr)):
        for name in dir(module):
            value = getattr(module, name)
            if not name.startswith("_") and callable(value) and not inspect.isclass(value):
                names.append(prefix + name)
    return sorted(names)


def function(name):
    module, _, short = name.rpartition(".")
    return getattr(qr if module else quatrot, short)


def test_every_public_function_has_a_valid_call():
    assert public_functions() == sorted(VALID)


def cases(kind):
    """(function, argument) pairs of every float argument (arrays, and for
    `finite` the float scalars too) of the valid calls."""
    out = []
    for name in public_functions():
        for arg, value in VALID.get(name, lambda tmp: {})(_Dummy()).items():
            is_array = isinstance(value, np.ndarray) and value.dtype == np.float64
            if kind == "arrays" and is_array:
                out.append((name, arg))
            if kind == "finite" and (is_array or isinstance(value, float)):
                out.append((name, arg))
            if kind == "quaternions" and is_array and arg in QUATERNION_ARGUMENTS:
                out.append((name, arg))
    return out


class _Dummy:
    """Stands for the temporary folder while the cases are listed."""

    def __truediv__(self, other):
        return other


def call(name, kwargs):
    return function(name)(**kwargs)


def outcome(name, kwargs):
    """The result, or the type and message of the exception raised."""
    try:
        return call(name, kwargs)
    except Exception as e:  # noqa: BLE001 (compared as data)
        return (type(e), str(e))


def same(a, b):
    if isinstance(a, dict):
        return isinstance(b, dict) and a.keys() == b.keys() and all(same(a[k], b[k]) for k in a)
    if isinstance(a, (list, tuple)) and not (len(a) == 2 and inspect.isclass(a[0])):
        return type(a) is type(b) and len(a) == len(b) and all(same(x, y) for x, y in zip(a, b))
    if isinstance(a, (np.ndarray, float, np.floating)):
        return np.array_equal(a, b, equal_nan=True)
    return a == b


def bad_position(value):
    """The last item's last number: the first bad row when it is the only one."""
    return tuple(d - 1 for d in value.shape)


def label(arg, index):
    return arg + "".join(f"[{i}]" for i in index)


@pytest.mark.filterwarnings("ignore::RuntimeWarning")
@pytest.mark.parametrize("name,arg", cases("finite"))
@pytest.mark.parametrize("bad", [np.nan, np.inf, -np.inf], ids=["nan", "inf", "-inf"])
def test_non_finite_input_is_refused_naming_the_argument_and_row(name, arg, bad, tmp_path):
    kwargs = VALID[name](tmp_path)
    value = kwargs[arg]
    if isinstance(value, float):
        kwargs[arg] = bad
        with pytest.raises(ValueError, match=rf"^{arg}\b"):
            call(name, kwargs)
        return
    value = value.copy()
    value[bad_position(value)] = bad
    kwargs[arg] = value
    shown = "nan" if np.isnan(bad) else ("inf" if bad > 0 else "-inf")
    message = f"{label(arg, bad_position(value))}: not finite ({shown})"
    with pytest.raises(ValueError, match="^" + re.escape(message) + "$"):
        call(name, kwargs)


@pytest.mark.parametrize("name,arg", cases("quaternions"))
def test_zero_quaternions_are_refused_naming_the_argument_and_row(name, arg, tmp_path):
    kwargs = VALID[name](tmp_path)
    value = kwargs[arg].copy()
    row = bad_position(value)[:-1]
    value[row] = 0.0
    kwargs[arg] = value
    with pytest.raises(ValueError, match="^" + re.escape(f"{label(arg, row)}: quaternion is zero") + "$"):
        call(name, kwargs)


def _strided(x):
    """The same values as a non-contiguous view (every other element of a larger array)."""
    big = np.empty((*x.shape[:-1], 2 * x.shape[-1])) if x.ndim else np.empty(2)
    if not x.ndim:
        big[0] = x
        return big[0:1].reshape(())
    big[..., ::2] = x
    view = big[..., ::2]
    assert not view.flags.c_contiguous
    return view


ARRAY_LIKES = {
    "list": lambda x: x.tolist(),
    "tuple": lambda x: tuple(x.tolist()) if x.ndim else float(x),
    "strided": _strided,
    "fortran": np.asfortranarray,
    "float32": lambda x: x.astype(np.float32),
}


@pytest.mark.filterwarnings("ignore::RuntimeWarning")
@pytest.mark.parametrize("name,arg", cases("arrays"))
@pytest.mark.parametrize("like", sorted(ARRAY_LIKES))
def test_array_likes_give_the_float64_result(name, arg, like, tmp_path):
    kwargs = VALID[name](tmp_path)
    converted = ARRAY_LIKES[like](kwargs[arg])
    expected_kwargs = dict(kwargs)
    # float32 rounds the values: the reference is the float64 call on the rounded values.
    expected_kwargs[arg] = np.asarray(converted, dtype=np.float64)
    expected = outcome(name, expected_kwargs)
    kwargs[arg] = converted
    got = outcome(name, kwargs)
    assert same(got, expected), (got, expected)
    if like != "float32":
        assert not isinstance(expected, tuple) or not inspect.isclass(expected[0]), expected


TEXT_ARGUMENTS = [
    ("multipole_evaluate", "method"),
    ("multipole_evaluate", "sum"),
    ("dielectric_constant", "boundary"),
    ("write_gsd", "path"),
    ("run", "scene"),
    ("run", "integrator"),
    ("run", "out_dir"),
]


@pytest.mark.parametrize("name,arg", TEXT_ARGUMENTS)
def test_lone_surrogates_raise_the_modules_error_naming_the_argument(name, arg, tmp_path):
    kwargs = VALID[name](tmp_path)
    kwargs[arg] = "bad\ud800text"
    with pytest.raises(ValueError, match=rf"^{arg}: not (a )?valid") as e:
        call(name, kwargs)
    assert not isinstance(e.value, UnicodeError)
    if name == "run":
        assert isinstance(e.value, quatrot.SceneError)


def test_scene_dict_keys_with_lone_surrogates_raise_scene_error():
    d = tomllib.loads(quatrot.builtin_scenes()["dipole_in_field"])
    d["initial"]["bad\udcff"] = 1
    with pytest.raises(quatrot.SceneError, match=r"^initial: a key: not valid text"):
        quatrot.run(d, steps=3)


@pytest.mark.parametrize(
    "name,change,error,message",
    [
        ("dlm_dipoles", dict(steps=2**64 - 1), ValueError, "steps: needs about 2^64 bytes or more of memory, more than the limit"),
        ("dlm_dipoles", dict(steps=10**12), ValueError, "steps: needs about 248.0 TB of memory, more than the limit"),
        ("dlm_dipoles", dict(steps=2**64), ValueError, "steps: must be between 0 and 18446744073709551615, got 18446744073709551616"),
        ("dlm_dipoles", dict(steps=-1), ValueError, "steps: must be between 0 and"),
        ("dlm_dipoles", dict(steps=1e12), TypeError, "steps: expected an integer, got float"),
        ("dlm_dipoles", dict(steps=True), TypeError, "steps: expected an integer, got bool"),
        ("gear_corrections_table", dict(sample_every=0), ValueError, "sample_every: must be >= 1, got 0"),
        ("gear_corrections_table", dict(t_energy=1e300), ValueError, "t_energy, dt, sample_every: needs about 2^64 bytes or more of memory"),
        ("orientational_correlations", dict(max_lag=-1), ValueError, "max_lag: must be between 0 and"),
        ("angular_velocity_correlation", dict(max_lag=2**70), ValueError, "max_lag: must be between 0 and"),
        ("write_gsd", dict(steps=[0, -1]), ValueError, "steps[1]: must be between 0 and"),
        ("run", dict(steps=2**70), quatrot.SceneError, "steps: must be at most 9223372036854775807"),
        ("run", dict(threads=2**70), ValueError, "threads: must be between 1 and 1024, got 1180591620717411303424"),
    ],
)
def test_integer_arguments_are_range_checked_and_results_sized_first(name, change, error, message, tmp_path):
    kwargs = VALID[name](tmp_path) | change
    with pytest.raises(error, match="^" + re.escape(message)):
        call(name, kwargs)


def float_scalars():
    """(function, argument) pairs of the float scalars of the valid calls."""
    return [
        (name, arg)
        for name in public_functions()
        for arg, value in VALID.get(name, lambda tmp: {})(_Dummy()).items()
        if isinstance(value, float)
    ]


@pytest.mark.parametrize("name,arg", float_scalars())
def test_a_number_of_the_wrong_type_is_a_type_error_naming_the_argument(name, arg, tmp_path):
    """Issue 37: `dt='0.1'` raised a TypeError naming no argument (pyo3 names
    it only in a note, which `str(e)` does not show)."""
    kwargs = VALID[name](tmp_path) | {arg: "0.1"}
    with pytest.raises(TypeError, match="^" + re.escape(arg + ": ")):
        call(name, kwargs)


def test_float_scalar_cases_are_listed():
    assert len(float_scalars()) >= 8


@pytest.mark.parametrize(
    "seed,message",
    [
        (-1, "initial.seed: must be an integer between 0 and 9223372036854775807, got -1"),
        (1.5, "initial.seed: must be an integer between 0 and 9223372036854775807, got 1.5"),
        ("3", 'initial.seed: must be an integer between 0 and 9223372036854775807, got "3"'),
        (True, "initial.seed: must be an integer between 0 and 9223372036854775807, got true"),
        (2**63, "initial.seed: must be an integer between -9223372036854775808 and 9223372036854775807"),
    ],
)
def test_seeds_are_range_checked_with_one_wording(seed, message):
    """Issue 37: -1 said "expected u64" and 2^63 "integer out of range"."""
    scene = {
        "version": 1,
        "rotors": {"kind": "sites", "sites": [{"position": [0.0, 0.0, 0.0]}], "default": {"inertia": 1.0}},
        "initial": {"kind": "random", "seed": seed, "temperature": 1.0},
        "integrator": {"kind": "dlm"},
        "run": {"dt": 0.01, "steps": 1},
    }
    with pytest.raises(quatrot.SceneError, match="^" + re.escape(message)):
        quatrot.run(scene)


def test_numpy_integers_are_integers():
    kwargs = VALID["dlm_dipoles"](None) | dict(steps=np.int64(3))
    assert quatrot.dlm_dipoles(**kwargs)["potential"].shape == (4,)


def test_multipole_overflow_is_an_error_not_nan():
    """Dipoles of 1e300 overflow the energy (mu^2 / r^3): an error naming the
    arguments, never a silent NaN."""
    kwargs = VALID["multipole_evaluate"](None) | dict(dipoles_body=np.full((N, 3), 1e300), quadrupoles_body=None)
    with pytest.raises(ValueError, match=r"dipoles_body.*not finite \((inf|-inf|nan)\) for finite arguments"):
        quatrot.multipole_evaluate(**kwargs)


def test_quaternion_ln_of_nan_or_zero_is_refused():
    """`ln([nan, 0, 0, 0])` gave [0, 0, 0]."""
    with pytest.raises(ValueError, match=re.escape("q[0]: not finite (nan)")):
        qr.ln([np.nan, 0.0, 0.0, 0.0])
    with pytest.raises(ValueError, match=re.escape("q: quaternion is zero")):
        qr.ln([0.0, 0.0, 0.0, 0.0])


# Scene dicts.


def _scene():
    return tomllib.loads(quatrot.builtin_scenes()["dipole_in_field"])


def test_self_referential_scene_dict_is_refused_with_its_path():
    """The issue's reproducer: the interpreter crashed (exit 139)."""
    d = _scene()
    x = [0.0, 0.0]
    x.append(x)
    d["initial"]["omega_body"] = x
    with pytest.raises(quatrot.SceneError, match=re.escape("initial.omega_body[2]: refers to itself (it is initial.omega_body)")):
        quatrot.run(d, steps=3)
    d = _scene()
    d["initial"]["again"] = d
    with pytest.raises(quatrot.SceneError, match=re.escape("initial.again: refers to itself (it is (top level))")):
        quatrot.run(d, steps=3)


def test_deeply_nested_scene_dict_is_refused_with_its_path():
    """5,500 levels crashed the interpreter; the limit is 32 levels."""
    d = _scene()
    deep = 0.0
    for _ in range(5500):
        deep = [deep]
    d["initial"]["omega_body"] = deep
    path = "initial.omega_body" + "[0]" * 30
    with pytest.raises(quatrot.SceneError, match="^" + re.escape(f"{path}: nested deeper than 32 levels") + "$"):
        quatrot.run(d, steps=3)


def test_shared_values_are_not_cycles_and_scenes_as_dicts_of_arrays_still_run():
    """A scene dict with numpy arrays, tuples and one list used twice (shared,
    not a cycle) runs as its TOML text does, value for value."""
    text = quatrot.builtin_scenes()["dipole_in_field"]
    reference = quatrot.run(text, steps=20)
    d = copy.deepcopy(tomllib.loads(text))
    for key, value in d["initial"].items():
        if isinstance(value, list):
            d["initial"][key] = np.array(value)
    shared = [1.0, 2.0]
    d["unused_a"], d["unused_b"] = shared, shared  # refused as unknown keys, not as a cycle
    with pytest.raises(quatrot.SceneError) as e:
        quatrot.run(d, steps=20)
    assert "refers to itself" not in str(e.value)
    del d["unused_a"], d["unused_b"]
    got = quatrot.run(d, steps=20)
    for name, columns in reference["series"].items():
        for column, values in columns.items():
            np.testing.assert_array_equal(got["series"][name][column], values)


def test_nesting_at_the_limit_reaches_the_scene_checks():
    """31 levels below `initial` (32 containers) pass the conversion: the
    scene's own check answers."""
    d = _scene()
    deep = 0.0
    for _ in range(30):
        deep = [deep]
    d["initial"]["omega_body"] = deep
    with pytest.raises(quatrot.SceneError) as e:
        quatrot.run(d, steps=3)
    assert "nested deeper" not in str(e.value)
