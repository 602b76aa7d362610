//! The one error type of the potential layer.

/// An invalid potential definition: the offending input (`cutoff`,
/// `rotors[3].quadrupole_body`, `field[1]`) and what is wrong with it, with
/// the value found ([`crate::InputError`]).
pub type PotentialError = crate::checks::InputError;
