//! How the images of a periodic box are summed: the one owner of the
//! options `sum`, `cutoff`, `accuracy` and `surface` (their names, rules,
//! defaults, checks and docs), read by the scene's `[interactions.boundary]`
//! table and by the Python keywords alike ([`PeriodicSum::new`]), and the one
//! place where an Ewald sum's parameters are chosen ([`PeriodicSum::choose`]).
//!
//! The way of summing (`method`, [`super::SumMethod`]) is its own option:
//! a new way (a mesh) is a variant there, checked against the sum it needs
//! when the potential is built.

use super::ewald_parameters::{self, Cost, EwaldParameters};
use super::PotentialError;
use crate::checks::{named_choices, positive};

/// The default relative accuracy of the Ewald sum.
pub const DEFAULT_ACCURACY: f64 = 1e-12;

/// The periodic lattice sum
/// `V = sum_{i<j} sum_n v(r_j - r_i + n L) + 1/2 sum_i sum_{n != 0} v(n L)`
/// over the images `n L` (`n` integer, `L` the box), taken one of two ways.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum PeriodicSum {
    /// Truncated at `|r| <= cutoff` (> 0, any size): every image inside the
    /// cutoff, so a pair may interact through several images and a rotor with
    /// its own images (a plain spherical cutoff: no shift, no tail
    /// correction). The cutoff is limited only by the size of the sum: about
    /// `N^2 (4 pi / 3) cutoff^3 / (2 V)` pairs for `N` sites in a box of
    /// volume `V`, at most [`super::MAX_PAIRS`].
    Cutoff {
        /// The spherical cutoff (> 0).
        cutoff: f64,
    },
    /// The Ewald sum (the conditionally convergent dipolar sum taken over
    /// growing spheres, de Leeuw, Perram & Smith, Proc. R. Soc. A 373, 27
    /// (1980)), with the splitting parameter and both cutoffs chosen for the
    /// relative `accuracy` (in (0, 1), default [`DEFAULT_ACCURACY`]; see
    /// [`super::ewald_parameters`] for its meaning and the estimates), and
    /// the medium around the sphere given by `surface`.
    Ewald {
        /// The requested relative accuracy, in (0, 1).
        accuracy: f64,
        /// The medium around the sphere of boxes.
        surface: Surface,
    },
}

/// The medium surrounding the infinite sphere of periodic boxes in the Ewald
/// sum (de Leeuw, Perram & Smith 1980).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum Surface {
    /// A conductor ("tin foil"): no surface term (the default, as in LAMMPS
    /// and OpenMM).
    #[default]
    Conducting,
    /// Vacuum: adds `2 pi |M|^2 / (3 V)`, `M` the total dipole of the box.
    Vacuum,
}

named_choices!(Surface {
    "conducting" => Surface::Conducting,
    "vacuum" => Surface::Vacuum,
});

/// Which of the two sums (the option `sum`).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum SumKind {
    /// [`PeriodicSum::Ewald`].
    Ewald,
    /// [`PeriodicSum::Cutoff`].
    Cutoff,
}

named_choices!(SumKind {
    "ewald" => SumKind::Ewald,
    "cutoff" => SumKind::Cutoff,
});

/// The options of a periodic sum as a user gives them, each optional (a
/// scene's `[interactions.boundary]` keys, the Python keywords); read by
/// [`PeriodicSum::new`].
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct SumOptions {
    /// `sum`: "ewald" (the default) or "cutoff" (the default when `cutoff`
    /// is given: the form of scene files written before the Ewald sum).
    pub sum: Option<SumKind>,
    /// `cutoff`: the spherical cutoff of `sum = "cutoff"` (required there, > 0).
    pub cutoff: Option<f64>,
    /// `accuracy`: the relative accuracy of `sum = "ewald"`, in (0, 1)
    /// (default [`DEFAULT_ACCURACY`]).
    pub accuracy: Option<f64>,
    /// `surface`: the surroundings of `sum = "ewald"` (default conducting).
    pub surface: Option<Surface>,
}

/// A periodic sum with its Ewald parameters chosen ([`PeriodicSum::choose`]):
/// what the sums are built from.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(crate) struct ChosenSum {
    /// The sum.
    pub sum: PeriodicSum,
    /// The reach of its real-space (or truncated) tensor: the cutoff, or
    /// the Ewald sum's real-space cutoff.
    pub reach: f64,
    /// Its Ewald parameters (`None` for a truncated sum).
    pub parameters: Option<EwaldParameters>,
}

impl PeriodicSum {
    /// The sum the options ask for: its `sum` (or the one implied: `cutoff`
    /// given means a truncated sum), with only the keys of that sum, the
    /// defaults applied and the values checked ([`Self::check`]). Errors
    /// name the option (`accuracy`, `cutoff`, `surface`).
    pub fn new(options: &SumOptions) -> Result<PeriodicSum, PotentialError> {
        let kind = options.sum.unwrap_or(match options.cutoff {
            Some(_) => SumKind::Cutoff,
            None => SumKind::Ewald,
        });
        let sum = match kind {
            SumKind::Cutoff => {
                let why = if options.sum.is_some() {
                    "only for sum = \"ewald\", not with sum = \"cutoff\""
                } else {
                    "only for sum = \"ewald\" (a cutoff without sum means sum = \"cutoff\")"
                };
                if options.accuracy.is_some() {
                    return Err(PotentialError::new("accuracy", why));
                }
                if options.surface.is_some() {
                    return Err(PotentialError::new("surface", why));
                }
                let cutoff = options.cutoff.ok_or_else(|| {
                    PotentialError::new("cutoff", "required with sum = \"cutoff\"")
                })?;
                PeriodicSum::Cutoff { cutoff }
            }
            SumKind::Ewald => {
                if options.cutoff.is_some() {
                    return Err(PotentialError::new(
                        "cutoff",
                        "not with sum = \"ewald\" (its real- and reciprocal-space cutoffs \
                         follow from accuracy)",
                    ));
                }
                PeriodicSum::ewald(options.accuracy, options.surface)
            }
        };
        Ok(sum)
    }

    /// The Ewald sum, its accuracy and surface defaulted when not given.
    pub(crate) fn ewald(accuracy: Option<f64>, surface: Option<Surface>) -> PeriodicSum {
        PeriodicSum::Ewald {
            accuracy: accuracy.unwrap_or(DEFAULT_ACCURACY),
            surface: surface.unwrap_or_default(),
        }
    }

    /// Checks the value of the sum's option: the cutoff (path `cutoff`,
    /// finite and > 0) or the accuracy (path `accuracy`, in (0, 1)).
    pub fn check(&self) -> Result<(), PotentialError> {
        match *self {
            PeriodicSum::Cutoff { cutoff } => {
                let _ = positive(cutoff).map_err(|e| e.at("cutoff"))?;
            }
            PeriodicSum::Ewald { accuracy, .. } => {
                if !(accuracy > 0.0 && accuracy < 1.0) {
                    return Err(PotentialError::new(
                        "accuracy",
                        format!("must be in (0, 1), got {accuracy}"),
                    ));
                }
            }
        }
        Ok(())
    }

    /// The option `sum` this sum answers to.
    pub fn kind(&self) -> SumKind {
        match self {
            PeriodicSum::Cutoff { .. } => SumKind::Cutoff,
            PeriodicSum::Ewald { .. } => SumKind::Ewald,
        }
    }

    /// The sum with its Ewald parameters chosen for the accuracy, at the
    /// number density `density`, for the multipole kinds `(dipoles,
    /// quadrupoles)` carried and the `cost` of the way of summing.
    pub(crate) fn choose(&self, density: f64, kinds: (bool, bool), cost: Cost) -> ChosenSum {
        match *self {
            PeriodicSum::Cutoff { cutoff } => ChosenSum {
                sum: *self,
                reach: cutoff,
                parameters: None,
            },
            PeriodicSum::Ewald { accuracy, .. } => {
                let parameters = ewald_parameters::choose(
                    accuracy,
                    density,
                    &ewald_parameters::ranks(kinds.0, kinds.1),
                    |rc, kc| cost.of(rc, kc),
                );
                ChosenSum {
                    sum: *self,
                    reach: parameters.real_cutoff,
                    parameters: Some(parameters),
                }
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn options(sum: Option<SumKind>, cutoff: Option<f64>, accuracy: Option<f64>) -> SumOptions {
        SumOptions {
            sum,
            cutoff,
            accuracy,
            surface: None,
        }
    }

    /// No option is the Ewald sum at 1e-12 in a conductor; a cutoff alone is
    /// the truncated sum of older scene files, the same as with `sum`.
    #[test]
    fn defaults_are_ewald_and_a_lone_cutoff_truncates() {
        let ewald = PeriodicSum::new(&SumOptions::default());
        assert_eq!(
            ewald,
            Ok(PeriodicSum::Ewald {
                accuracy: 1e-12,
                surface: Surface::Conducting
            })
        );
        let truncated = Ok(PeriodicSum::Cutoff { cutoff: 2.5 });
        assert_eq!(PeriodicSum::new(&options(None, Some(2.5), None)), truncated);
        let explicit = options(Some(SumKind::Cutoff), Some(2.5), None);
        assert_eq!(PeriodicSum::new(&explicit), truncated);
    }

    /// Each sum takes only its own keys, and the error names the key.
    #[test]
    fn keys_of_the_other_sum_are_refused_by_name() {
        let refused = |o: SumOptions| PeriodicSum::new(&o).unwrap_err().to_string();
        assert_eq!(
            refused(options(Some(SumKind::Ewald), Some(1.0), None)),
            "cutoff: not with sum = \"ewald\" (its real- and reciprocal-space cutoffs follow \
             from accuracy)"
        );
        assert_eq!(
            refused(options(Some(SumKind::Cutoff), None, None)),
            "cutoff: required with sum = \"cutoff\""
        );
        assert_eq!(
            refused(options(None, Some(1.0), Some(1e-6))),
            "accuracy: only for sum = \"ewald\" (a cutoff without sum means sum = \"cutoff\")"
        );
        let surface = SumOptions {
            surface: Some(Surface::Vacuum),
            ..options(Some(SumKind::Cutoff), Some(1.0), None)
        };
        assert_eq!(
            refused(surface),
            "surface: only for sum = \"ewald\", not with sum = \"cutoff\""
        );
    }

    /// The values are checked once, by [`PeriodicSum::check`].
    #[test]
    fn values_out_of_range_are_refused() {
        let check = |o: SumOptions| {
            PeriodicSum::new(&o)
                .unwrap()
                .check()
                .unwrap_err()
                .to_string()
        };
        assert_eq!(
            check(options(None, None, Some(1.0))),
            "accuracy: must be in (0, 1), got 1"
        );
        assert_eq!(
            check(options(None, Some(-2.0), None)),
            "cutoff: must be > 0, got -2"
        );
        assert!(PeriodicSum::new(&options(None, None, Some(0.5)))
            .unwrap()
            .check()
            .is_ok());
    }
}
