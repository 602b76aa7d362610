"""The `quatrot.dlm_dipoles` binding: shapes are checked at the boundary, and
a free spherical top follows the closed form Q(t) = Q0 * exp(w_b t)."""

import numpy as np
import pytest
from scipy.spatial.transform import Rotation

import quatrot


def _args(n=1):
    return dict(
        sites=np.zeros((n, 3)),
        dipoles_body=np.tile([0.0, 0.0, 1.0], (n, 1)),
        inertia=np.full(n, 0.1),
        orientations=np.tile([1.0, 0.0, 0.0, 0.0], (n, 1)),
        omega_body=np.tile([0.3, -0.2, 0.5], (n, 1)),
        field=None,
        dt=0.01,
        steps=10,
        split=False,
    )


def test_wrong_shape_names_the_argument():
    args = _args()
    args["orientations"] = np.zeros((1, 3))
    with pytest.raises(ValueError, match="orientations: expected shape"):
        quatrot.dlm_dipoles(**args)


def test_bad_time_step_is_a_value_error():
    args = _args()
    args["dt"] = 0.0
    with pytest.raises(ValueError, match="dt"):
        quatrot.dlm_dipoles(**args)


def test_free_spherical_top_matches_closed_form():
    out = quatrot.dlm_dipoles(**_args())
    q = out["orientations"][-1, 0]
    # scipy stores (x, y, z, w); body-fixed omega: Q(t) = Q0 * exp(w_b t) = exp(w_b t) for Q0 = 1.
    exact = Rotation.from_rotvec(np.array([0.3, -0.2, 0.5]) * 0.1).as_quat()
    exact = np.array([exact[3], *exact[:3]])
    assert min(np.abs(q - exact).max(), np.abs(q + exact).max()) < 1e-14  # ten unit products: round-off
