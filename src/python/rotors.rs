//! Rotors and their initial states from per-rotor array arguments: the one
//! place the bindings build [`Rotor`]s and [`RotorState`]s (an item without
//! the leading `n` applies to every rotor).

use super::arrays::Items;
use crate::integrators::RotorState;
use crate::rotor::{Inertia, Rotor};

/// The inertia of item `i` of `inertia`: a scalar moment (a spherical top),
/// or three principal moments ([`Inertia::from_moments`]); no argument
/// (a potential alone, no dynamics) gives a unit spherical top.
fn inertia(inertia: Option<&Items<'_>>, i: usize) -> Inertia {
    match inertia {
        None => Inertia::Spherical(1.0),
        Some(m) if m.item_len() == 1 => Inertia::Spherical(m.scalar(i)),
        Some(m) => Inertia::from_moments(m.vector(i)),
    }
}

/// `n` rotors on `sites` with moments `moments` (items `()` or `(3,)`) and
/// the optional body-frame `dipoles` `(3,)` and `quadrupoles` `(3, 3)`.
pub(crate) fn rotors(
    n: usize,
    sites: &Items<'_>,
    moments: Option<&Items<'_>>,
    dipoles: Option<&Items<'_>>,
    quadrupoles: Option<&Items<'_>>,
) -> Vec<Rotor> {
    (0..n)
        .map(|i| Rotor {
            site: sites.vector(i),
            inertia: inertia(moments, i),
            dipole_body: dipoles.map(|d| d.vector(i)),
            quadrupole_body: quadrupoles.map(|t| t.matrix(i)),
        })
        .collect()
}

/// The `n` states of `orientations` (quaternions) and `omega_body` (3-vectors).
pub(crate) fn states(
    n: usize,
    orientations: &Items<'_>,
    omega_body: &Items<'_>,
) -> Vec<RotorState> {
    (0..n)
        .map(|i| RotorState {
            orientation: orientations.quat(i),
            omega_body: omega_body.vector(i),
        })
        .collect()
}
