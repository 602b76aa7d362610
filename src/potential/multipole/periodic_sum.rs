//! How the images of a periodic box are summed: the one owner of the
//! options `sum`, `cutoff`, `accuracy` and `surface` (their names, rules,
//! defaults, checks and docs), read by the scene's `[interactions.boundary]`
//! table and by the Python keywords alike ([`super::Boundary::periodic`]), and the one
//! place where an Ewald sum's parameters are chosen ([`PeriodicSum::choose`]).
//!
//! The way of summing (`method`, [`super::SumMethod`]) is its own option:
//! a new way (a mesh) is a variant there, checked against the sum it needs
//! when the potential is built.

use super::ewald_parameters::{self, Cost, EwaldParameters};
use super::PotentialError;
use crate::checks::{named_choices, num};
use nalgebra::Vector3;

/// The requested relative accuracy of an Ewald sum, in (0, 1) (see
/// [`super::ewald_parameters`] for its meaning): made only by
/// [`Accuracy::new`], which checks it, so what holds one trusts it.
#[derive(Clone, Copy, Debug, PartialEq, PartialOrd)]
pub struct Accuracy(f64);

impl Accuracy {
    /// The default, `1e-12`.
    pub const DEFAULT: Accuracy = Accuracy(1e-12);

    /// The accuracy `value`, refused (path `accuracy`) outside (0, 1).
    pub fn new(value: f64) -> Result<Accuracy, PotentialError> {
        if value > 0.0 && value < 1.0 {
            Ok(Accuracy(value))
        } else {
            Err(PotentialError::new(
                "accuracy",
                format!("must be in (0, 1), got {value}"),
            ))
        }
    }

    /// The value, in (0, 1).
    pub fn get(self) -> f64 {
        self.0
    }
}

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
    /// relative `accuracy` (default [`Accuracy::DEFAULT`]; see
    /// [`super::ewald_parameters`] for its meaning and the estimates), and
    /// the medium around the sphere given by `surface`.
    Ewald {
        /// The requested relative accuracy.
        accuracy: Accuracy,
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
/// [`super::Boundary::periodic`].
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct SumOptions {
    /// `sum`: "ewald" (the default) or "cutoff" (the default when `cutoff`
    /// is given: the form of scene files written before the Ewald sum).
    pub sum: Option<SumKind>,
    /// `cutoff`: the spherical cutoff of `sum = "cutoff"` (required there, > 0).
    pub cutoff: Option<f64>,
    /// `accuracy`: the relative accuracy of `sum = "ewald"`, in (0, 1)
    /// (default [`Accuracy::DEFAULT`]).
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

impl SumOptions {
    /// The sum the options ask for, its `sum` or the one implied (`cutoff`
    /// given means a truncated sum), with only the keys of that sum (errors
    /// name the key: `accuracy`, `cutoff`, `surface`): `Some(cutoff)` for a
    /// truncated sum, `None` for the Ewald sum.
    pub(super) fn truncation(&self) -> Result<Option<f64>, PotentialError> {
        let kind = self.sum.unwrap_or(match self.cutoff {
            Some(_) => SumKind::Cutoff,
            None => SumKind::Ewald,
        });
        match kind {
            SumKind::Cutoff => {
                let why = if self.sum.is_some() {
                    "only for sum = \"ewald\", not with sum = \"cutoff\""
                } else {
                    "only for sum = \"ewald\" (a cutoff without sum means sum = \"cutoff\")"
                };
                if self.accuracy.is_some() {
                    return Err(PotentialError::new("accuracy", why));
                }
                if self.surface.is_some() {
                    return Err(PotentialError::new("surface", why));
                }
                let cutoff = self.cutoff.ok_or_else(|| {
                    PotentialError::new("cutoff", "required with sum = \"cutoff\"")
                })?;
                Ok(Some(cutoff))
            }
            SumKind::Ewald => {
                if self.cutoff.is_some() {
                    return Err(PotentialError::new(
                        "cutoff",
                        "not with sum = \"ewald\" (its real- and reciprocal-space cutoffs \
                         follow from accuracy)",
                    ));
                }
                Ok(None)
            }
        }
    }
}

impl PeriodicSum {
    /// The sum `options` ask for, given its [`SumOptions::truncation`]: the
    /// defaults applied and the accuracy checked ([`Accuracy::new`]); the
    /// cutoff is checked with the box by [`super::Boundary::validate`].
    pub(super) fn new(
        truncation: Option<f64>,
        options: &SumOptions,
    ) -> Result<PeriodicSum, PotentialError> {
        Ok(match truncation {
            Some(cutoff) => PeriodicSum::Cutoff { cutoff },
            None => PeriodicSum::Ewald {
                accuracy: options
                    .accuracy
                    .map_or(Ok(Accuracy::DEFAULT), Accuracy::new)?,
                surface: options.surface.unwrap_or_default(),
            },
        })
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
    /// quadrupoles)` carried and the `cost` of the way of summing; refused
    /// (naming `box_lengths`) when the lattice vectors within the cutoffs
    /// of the box `box_lengths` are too many to enumerate
    /// ([`MAX_LATTICE_VECTORS`]).
    pub(crate) fn choose(
        &self,
        density: f64,
        kinds: (bool, bool),
        cost: Cost,
        box_lengths: &Vector3<f64>,
    ) -> Result<ChosenSum, PotentialError> {
        match *self {
            PeriodicSum::Cutoff { cutoff } => Ok(ChosenSum {
                sum: *self,
                reach: cutoff,
                parameters: None,
            }),
            PeriodicSum::Ewald { accuracy, .. } => {
                let accuracy = accuracy.get();
                let parameters = ewald_parameters::choose(
                    accuracy,
                    density,
                    &ewald_parameters::ranks(kinds.0, kinds.1),
                    |rc, kc| cost.of(rc, kc),
                );
                let spacing = box_lengths.map(|l| std::f64::consts::TAU / l);
                enumerable("real-space", parameters.real_cutoff, box_lengths, accuracy)?;
                enumerable(
                    "reciprocal",
                    parameters.reciprocal_cutoff,
                    &spacing,
                    accuracy,
                )?;
                Ok(ChosenSum {
                    sum: *self,
                    reach: parameters.real_cutoff,
                    parameters: Some(parameters),
                })
            }
        }
    }
}

/// The most lattice vectors (real or reciprocal) an Ewald sum may
/// enumerate within its cutoff, counted over the cutoff's bounding box
/// (about 2 s of building at the limit): a cubic box of 1,000 sites needs
/// about 1e4 at 1e-12; a box 1e11 times longer than wide needed 1e9 and ran
/// for hours.
pub const MAX_LATTICE_VECTORS: f64 = 2e6;

/// Refuses a `cutoff` whose bounding box holds more than
/// [`MAX_LATTICE_VECTORS`] points of the lattice of `spacing` (the box, or
/// the reciprocal lattice `2 pi / L`), before any is enumerated.
fn enumerable(
    space: &str,
    cutoff: f64,
    spacing: &Vector3<f64>,
    accuracy: f64,
) -> Result<(), PotentialError> {
    let count: f64 = spacing
        .iter()
        .map(|l| 2.0 * (cutoff / l).floor() + 1.0)
        .product();
    if count <= MAX_LATTICE_VECTORS {
        return Ok(());
    }
    Err(PotentialError::new(
        "box_lengths",
        format!(
            "the Ewald sum at accuracy {} needs about {} {space} lattice vectors within its cutoff {} \
             (a box much longer than wide needs many), more than the {} it may enumerate; use a \
             less elongated box, fewer sites or sum = \"cutoff\"",
            num(accuracy),
            num(count),
            num(cutoff),
            num(MAX_LATTICE_VECTORS)
        ),
    ))
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

    /// The sum `o` asks for (the unit cube's boundary's).
    fn sum_of(o: SumOptions) -> Result<PeriodicSum, String> {
        match super::super::Boundary::periodic(Vector3::repeat(1.0), &o) {
            Ok(super::super::Boundary::Periodic { sum, .. }) => Ok(sum),
            Ok(open) => Err(format!("not periodic: {open:?}")),
            Err(e) => Err(e.to_string()),
        }
    }

    /// No option is the Ewald sum at 1e-12 in a conductor; a cutoff alone is
    /// the truncated sum of older scene files, the same as with `sum`.
    #[test]
    fn defaults_are_ewald_and_a_lone_cutoff_truncates() {
        assert_eq!(Accuracy::DEFAULT.get(), 1e-12);
        assert_eq!(
            sum_of(SumOptions::default()),
            Ok(PeriodicSum::Ewald {
                accuracy: Accuracy::DEFAULT,
                surface: Surface::Conducting
            })
        );
        let truncated = Ok(PeriodicSum::Cutoff { cutoff: 2.5 });
        assert_eq!(sum_of(options(None, Some(2.5), None)), truncated);
        let explicit = options(Some(SumKind::Cutoff), Some(2.5), None);
        assert_eq!(sum_of(explicit), truncated);
    }

    /// Each sum takes only its own keys, and the error names the key.
    #[test]
    fn keys_of_the_other_sum_are_refused_by_name() {
        let refused = |o: SumOptions| sum_of(o).unwrap_err();
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

    /// An accuracy is made only by [`Accuracy::new`], which takes (0, 1)
    /// exclusive and refuses the rest naming `accuracy`; the sum's options
    /// go through it.
    #[test]
    fn accuracies_outside_zero_one_are_refused() {
        for bad in [0.0, -0.0, 1.0, -1e-3, 2.0, f64::NAN, f64::INFINITY] {
            let e = Accuracy::new(bad).unwrap_err();
            assert_eq!(e.path, "accuracy", "{bad}");
            assert_eq!(
                e.to_string(),
                format!("accuracy: must be in (0, 1), got {bad}")
            );
        }
        for good in [f64::MIN_POSITIVE, 1e-12, 0.5, 1.0 - f64::EPSILON] {
            assert_eq!(Accuracy::new(good).map(Accuracy::get), Ok(good));
        }
        assert_eq!(
            sum_of(options(None, None, Some(1.0))).unwrap_err(),
            "accuracy: must be in (0, 1), got 1"
        );
    }

    /// A truncated sum's cutoff is checked with the box, after it.
    #[test]
    fn cutoffs_are_checked_with_the_box() {
        let check = |edge: f64, cutoff: f64| {
            super::super::Boundary::periodic_cutoff(Vector3::repeat(edge), cutoff)
                .validate(2)
                .unwrap_err()
                .to_string()
        };
        assert_eq!(check(1.0, -2.0), "cutoff: must be > 0, got -2");
        assert_eq!(check(-1.0, -2.0), "box_lengths[0]: must be > 0, got -1");
    }
}
