//! Checks of input values, shared by every physics constructor, in one
//! message style: `must be > 0, got 0`, with the path of the offending value
//! relative to the checked object (`[1]`, `cutoff`, `rotors[3].site[0]`).
//! Outer layers add their own path in front ([`InputError::at`]): the scene
//! turns `[1]` of a field into `fields.uniform[1]`. Each fact is checked by
//! one function here or on the type that owns it, with one tolerance.

use crate::parallel::{fixed_threads, ThreadCount, MAX_THREADS};
use crate::quaternion::Quat;
use nalgebra::Matrix3;
use serde::de::{Deserialize, DeserializeOwned, Deserializer, Error as _, IntoDeserializer};
use serde::Serialize;
use std::num::NonZeroU32;

/// Relative tolerance of the symmetry and tracelessness of tensors (body
/// quadrupoles, field gradients), relative to their largest entry. A real
/// mistake (a forgotten symmetric entry, a trace left in) is of relative
/// size ~1; the tolerance admits tensors computed in floating point (a
/// rotation, a change of convention) and values written with 11 or more
/// significant digits, such as `1/3, 1/3, -2/3` to 12 digits (trace 1.5e-12
/// of the largest entry).
pub const TENSOR_TOLERANCE: f64 = 1e-10;

/// A value that failed a check: where (relative path, empty for the checked
/// value itself) and what is wrong with it, with the value found.
#[derive(Clone, Debug, PartialEq, thiserror::Error)]
#[error("{path}: {message}")]
pub struct InputError {
    /// The offending value, relative to the checked object (may be empty).
    pub path: String,
    /// What is wrong, with the value found.
    pub message: String,
}

impl InputError {
    /// An error at `path`.
    pub fn new(path: impl Into<String>, message: impl Into<String>) -> Self {
        InputError {
            path: path.into(),
            message: message.into(),
        }
    }

    /// The same error seen from `parent`: the path becomes `parent.path`,
    /// `parent[k]...` for a path that starts with an index, or `parent` for
    /// an empty one.
    pub fn at(self, parent: &str) -> Self {
        let path = match self.path.as_str() {
            "" => parent.to_string(),
            p if parent.is_empty() => p.to_string(),
            p if p.starts_with('[') => format!("{parent}{p}"),
            p => format!("{parent}.{p}"),
        };
        InputError { path, ..self }
    }
}

/// A number as a message shows it: plain in the usual range, in exponent
/// form when very large or very small (Rust's `{}` would print 300 digits).
pub fn num(x: f64) -> String {
    let a = x.abs();
    if a != 0.0 && a.is_finite() && !(1e-5..1e16).contains(&a) {
        format!("{x:e}")
    } else {
        format!("{x}")
    }
}

/// A number a message derives from input values by arithmetic (twice a
/// cutoff plus a skin), rounded to 12 significant digits so that binary
/// round-off (`0.8999999999999999` for `2 (0.3 + 0.15)`) does not show.
pub fn derived(x: f64) -> String {
    num(format!("{x:.11e}").parse().unwrap_or(x))
}

/// Text from the input as a message quotes it: control characters escaped
/// as Rust writes them (`\n`, `\u{1b}`), at most `max_chars` characters
/// shown (escapes counted as written), the length of the rest stated.
pub fn printable(text: &str, max_chars: usize) -> String {
    let mut out = String::new();
    let mut shown = 0;
    for (k, c) in text.chars().enumerate() {
        let piece: String = if c.is_control() {
            c.escape_default().collect()
        } else {
            c.to_string()
        };
        if shown + piece.chars().count() > max_chars {
            let rest = text.chars().count() - k;
            out.push_str(&format!("... ({rest} more characters)"));
            break;
        }
        shown += piece.chars().count();
        out.push_str(&piece);
    }
    out
}

/// `x` if it is finite.
pub fn finite(x: f64) -> Result<f64, InputError> {
    if x.is_finite() {
        Ok(x)
    } else {
        Err(InputError::new(
            "",
            format!("must be finite, got {}", num(x)),
        ))
    }
}

/// `x` if it is finite and `> 0`.
pub fn positive(x: f64) -> Result<f64, InputError> {
    if finite(x)? > 0.0 {
        Ok(x)
    } else {
        Err(InputError::new("", format!("must be > 0, got {}", num(x))))
    }
}

/// `value` if it is finite and `> 0`, else the error at `path` in the
/// wording of the analyses, the experiments and the integrators' time step:
/// `must be finite and > 0, got 0`.
pub fn finite_and_positive(path: &str, value: f64) -> Result<f64, InputError> {
    if value.is_finite() && value > 0.0 {
        Ok(value)
    } else {
        Err(InputError::new(
            path,
            format!("must be finite and > 0, got {value}"),
        ))
    }
}

/// `x` if it is finite and `>= 0`.
pub fn non_negative(x: f64) -> Result<f64, InputError> {
    if finite(x)? >= 0.0 {
        Ok(x)
    } else {
        Err(InputError::new("", format!("must be >= 0, got {}", num(x))))
    }
}

/// `v` as a count if it is `>= 1`.
pub fn at_least_one(v: i64) -> Result<u64, InputError> {
    u64::try_from(v)
        .ok()
        .filter(|&n| n >= 1)
        .ok_or_else(|| InputError::new("", format!("must be >= 1, got {v}")))
}

/// Applies `check` to every component, the path of a failure naming the
/// component (`[k]`).
pub fn each(values: &[f64], check: fn(f64) -> Result<f64, InputError>) -> Result<(), InputError> {
    for (k, x) in values.iter().enumerate() {
        let _ = check(*x).map_err(|e| e.at(&format!("[{k}]")))?;
    }
    Ok(())
}

/// The unit orientation of `q`: every component finite (path `[k]`), and
/// not all zero (a tiny or huge `q` is normalised all the same).
pub fn orientation(q: &Quat) -> Result<Quat, InputError> {
    each(&q.0, finite)?;
    q.try_normalize().ok_or_else(|| {
        let [a, b, c, d] = q.0.map(num);
        InputError::new(
            "",
            format!("must be a non-zero quaternion, got [{a}, {b}, {c}, {d}]"),
        )
    })
}

/// Every entry finite, a failure naming the entry (`[i][j]`).
pub fn finite_matrix(m: &Matrix3<f64>) -> Result<(), InputError> {
    for i in 0..3 {
        for j in 0..3 {
            let _ = finite(m[(i, j)]).map_err(|e| e.at(&format!("[{i}][{j}]")))?;
        }
    }
    Ok(())
}

/// The largest entry of `m` in magnitude (the scale of the tensor checks).
fn tensor_scale(m: &Matrix3<f64>) -> f64 {
    m.amax().max(f64::MIN_POSITIVE)
}

/// `m` symmetric within [`TENSOR_TOLERANCE`] of its largest entry.
pub fn symmetric(m: &Matrix3<f64>) -> Result<(), InputError> {
    let scale = tensor_scale(m);
    for (i, j) in [(0, 1), (0, 2), (1, 2)] {
        if (m[(i, j)] - m[(j, i)]).abs() > TENSOR_TOLERANCE * scale {
            return Err(InputError::new(
                "",
                format!(
                    "must be symmetric, got [{i}][{j}] = {} but [{j}][{i}] = {}",
                    m[(i, j)],
                    m[(j, i)]
                ),
            ));
        }
    }
    Ok(())
}

/// `m` traceless within [`TENSOR_TOLERANCE`] of its largest entry.
pub fn traceless(m: &Matrix3<f64>) -> Result<(), InputError> {
    if m.trace().abs() > TENSOR_TOLERANCE * tensor_scale(m) {
        return Err(InputError::new(
            "",
            format!("must be traceless, got trace {}", m.trace()),
        ));
    }
    Ok(())
}

/// Deserialises a count `>= 1` (read as an integer, so that `0` and `-3` get
/// the message of [`at_least_one`]).
pub fn deserialize_at_least_one<'de, D: Deserializer<'de>>(
    deserializer: D,
) -> Result<NonZeroU32, D::Error> {
    let v = i64::deserialize(deserializer)?;
    let n = at_least_one(v).map_err(|e| D::Error::custom(e.message))?;
    u32::try_from(n)
        .ok()
        .and_then(NonZeroU32::new)
        .ok_or_else(|| D::Error::custom(format!("must be <= {}, got {n}", u32::MAX)))
}

/// The largest seed: seeds drawn when a scene gives none are below 2^63, so
/// that every seed a summary records can be written back into a TOML scene
/// (whose integers are 64-bit signed).
pub const MAX_SEED: u64 = i64::MAX as u64;

/// Deserialises an optional seed, an integer in `[0, MAX_SEED]`, refusing
/// anything else with one message: `must be an integer between 0 and
/// 9223372036854775807, got -1` (also for `1.5`, `"3"` or `true`).
pub fn deserialize_seed<'de, D: Deserializer<'de>>(
    deserializer: D,
) -> Result<Option<u64>, D::Error> {
    struct Seed;
    fn refuse<E: serde::de::Error>(got: impl std::fmt::Display) -> E {
        E::custom(format!(
            "must be an integer between 0 and {MAX_SEED}, got {got}"
        ))
    }
    impl serde::de::Visitor<'_> for Seed {
        type Value = u64;
        fn expecting(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
            write!(f, "an integer between 0 and {MAX_SEED}")
        }
        fn visit_i64<E: serde::de::Error>(self, v: i64) -> Result<u64, E> {
            u64::try_from(v).map_err(|_| refuse(v))
        }
        fn visit_u64<E: serde::de::Error>(self, v: u64) -> Result<u64, E> {
            (v <= MAX_SEED).then_some(v).ok_or_else(|| refuse(v))
        }
        fn visit_f64<E: serde::de::Error>(self, v: f64) -> Result<u64, E> {
            Err(refuse(num(v)))
        }
        fn visit_bool<E: serde::de::Error>(self, v: bool) -> Result<u64, E> {
            Err(refuse(v))
        }
        fn visit_str<E: serde::de::Error>(self, v: &str) -> Result<u64, E> {
            Err(refuse(format!("\"{}\"", printable(v, 40))))
        }
    }
    deserializer.deserialize_any(Seed).map(Some)
}

/// A scene's `run.threads`: an integer from 1 to `MAX_THREADS` or
/// `"auto"`, anything else refused with one message: `must be an integer
/// between 1 and 1024 or "auto", got 0` (also for `2.5`, `"two"` or `true`).
impl<'de> Deserialize<'de> for ThreadCount {
    fn deserialize<D: Deserializer<'de>>(deserializer: D) -> Result<Self, D::Error> {
        struct Count;
        fn refuse<E: serde::de::Error>(got: impl std::fmt::Display) -> E {
            E::custom(format!(
                "must be an integer between 1 and {MAX_THREADS} or \"auto\", got {got}"
            ))
        }
        impl serde::de::Visitor<'_> for Count {
            type Value = ThreadCount;
            fn expecting(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
                write!(f, "an integer between 1 and {MAX_THREADS} or \"auto\"")
            }
            fn visit_i64<E: serde::de::Error>(self, v: i64) -> Result<ThreadCount, E> {
                fixed_threads(v)
                    .map(ThreadCount::Fixed)
                    .ok_or_else(|| refuse(v))
            }
            fn visit_u64<E: serde::de::Error>(self, v: u64) -> Result<ThreadCount, E> {
                let fixed = i64::try_from(v).ok().and_then(fixed_threads);
                fixed.map(ThreadCount::Fixed).ok_or_else(|| refuse(v))
            }
            fn visit_f64<E: serde::de::Error>(self, v: f64) -> Result<ThreadCount, E> {
                Err(refuse(num(v)))
            }
            fn visit_bool<E: serde::de::Error>(self, v: bool) -> Result<ThreadCount, E> {
                Err(refuse(v))
            }
            fn visit_str<E: serde::de::Error>(self, v: &str) -> Result<ThreadCount, E> {
                match v {
                    "auto" => Ok(ThreadCount::Automatic),
                    _ => Err(refuse(format!("\"{}\"", printable(v, 40)))),
                }
            }
        }
        deserializer.deserialize_any(Count)
    }
}

/// A thread count as a scene writes it: its number, or `"auto"`.
impl Serialize for ThreadCount {
    fn serialize<S: serde::Serializer>(&self, serializer: S) -> Result<S::Ok, S::Error> {
        match self {
            ThreadCount::Automatic => serializer.serialize_str("auto"),
            ThreadCount::Fixed(n) => serializer.serialize_u64(n.get() as u64),
        }
    }
}

/// Implements `Deserialize` and `Serialize` for a field-less enum by names,
/// and `as_str` giving a value's name:
/// `named_choices!(Startup { "consistent" => Startup::Consistent, ... })`
/// reads and writes `"consistent"` for `Startup::Consistent` and refuses any
/// other string ([`deserialize_named`]); [`from_name`] reads a name given
/// outside a scene (a Python keyword).
macro_rules! named_choices {
    ($enum:ty { $($name:literal => $value:path),+ $(,)? }) => {
        impl $enum {
            /// The name of the value in scenes, summaries and Python.
            pub fn as_str(self) -> &'static str {
                match self {
                    $($value => $name),+
                }
            }
        }

        impl<'de> serde::Deserialize<'de> for $enum {
            fn deserialize<D: serde::Deserializer<'de>>(deserializer: D) -> Result<Self, D::Error> {
                $crate::checks::deserialize_named(deserializer, &[$(($name, $value)),+])
            }
        }

        impl serde::Serialize for $enum {
            fn serialize<S: serde::Serializer>(&self, serializer: S) -> Result<S::Ok, S::Error> {
                serializer.serialize_str(self.as_str())
            }
        }
    };
}
pub(crate) use named_choices;

/// Deserialises a string naming one of `choices`, refusing any other with
/// `must be "a" or "b", got "c"` (`"a", "b" or "c"` for three).
pub fn deserialize_named<'de, D: Deserializer<'de>, T: Copy>(
    deserializer: D,
    choices: &[(&str, T)],
) -> Result<T, D::Error> {
    let name = String::deserialize(deserializer)?;
    if let Some((_, value)) = choices.iter().find(|(n, _)| *n == name) {
        return Ok(*value);
    }
    let quoted: Vec<String> = choices.iter().map(|(n, _)| format!("\"{n}\"")).collect();
    let expected = match quoted.split_last() {
        Some((last, rest)) if !rest.is_empty() => format!("{} or {last}", rest.join(", ")),
        _ => quoted.join(""),
    };
    Err(D::Error::custom(format!(
        "must be {expected}, got \"{name}\""
    )))
}

/// The value of an enum of `named_choices!` called `name`, given outside a
/// scene (a Python keyword argument `path`), with the scene's message.
pub fn from_name<T: DeserializeOwned>(path: &str, name: &str) -> Result<T, InputError> {
    T::deserialize(IntoDeserializer::<serde::de::value::Error>::into_deserializer(name))
        .map_err(|e| InputError::new(path, e.to_string()))
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Paths join with a dot, indices without, and an empty path takes the
    /// parent's.
    #[test]
    fn paths_join_as_the_scene_writes_them() {
        let e = || InputError::new("", "m");
        assert_eq!(e().at("run.dt").path, "run.dt");
        assert_eq!(e().at("[1]").at("fields.uniform").path, "fields.uniform[1]");
        assert_eq!(
            InputError::new("site[0]", "m").at("rotors[3]").to_string(),
            "rotors[3].site[0]: m"
        );
        assert_eq!(InputError::new("cutoff", "m").at("").path, "cutoff");
    }

    /// The messages of the corpus of bad scenes, and numbers in exponent form
    /// outside the usual range.
    #[test]
    fn messages_show_the_value() {
        assert_eq!(positive(0.0).unwrap_err().message, "must be > 0, got 0");
        assert_eq!(
            positive(-1e300).unwrap_err().message,
            "must be > 0, got -1e300"
        );
        assert_eq!(
            positive(f64::NAN).unwrap_err().message,
            "must be finite, got NaN"
        );
        assert_eq!(
            at_least_one(-3).unwrap_err().message,
            "must be >= 1, got -3"
        );
        assert_eq!(at_least_one(2), Ok(2));
        assert_eq!(derived(2.0 * (0.3 + 0.15)), "0.9");
        assert_eq!(derived(1.0 / 3.0), "0.333333333333");
        assert_eq!(
            non_negative(-0.5).unwrap_err().message,
            "must be >= 0, got -0.5"
        );
        assert_eq!(non_negative(0.0), Ok(0.0));
        assert_eq!(
            finite_and_positive("volume", -1.0).unwrap_err().to_string(),
            "volume: must be finite and > 0, got -1"
        );
        assert_eq!(finite_and_positive("dt", 0.5), Ok(0.5));
        let e = each(&[1.0, f64::INFINITY], finite).unwrap_err();
        assert_eq!(e.to_string(), "[1]: must be finite, got inf");
    }

    /// Quoted input loses its control characters and its length beyond the
    /// excerpt.
    #[test]
    fn printable_escapes_control_characters_and_cuts_long_text() {
        assert_eq!(printable("a\u{1b}[31mb\n", 20), "a\\u{1b}[31mb\\n");
        assert_eq!(
            printable(&"x".repeat(1000), 3),
            "xxx... (997 more characters)"
        );
        assert_eq!(printable("dipole_lattice_sc", 80), "dipole_lattice_sc");
    }

    /// Asymmetry and trace are judged relative to the largest entry, at
    /// [`TENSOR_TOLERANCE`]: a tensor typed to 12 digits passes, a real
    /// mistake does not.
    #[test]
    fn tensor_checks_are_relative_to_the_largest_entry() {
        let third = 0.333_333_333_333;
        let typed =
            Matrix3::from_diagonal(&nalgebra::Vector3::new(third, third, -0.666_666_666_667));
        assert!(traceless(&typed).is_ok());
        assert!(traceless(&(typed * 1e-8)).is_ok());
        assert_eq!(
            traceless(&Matrix3::identity()).unwrap_err().message,
            "must be traceless, got trace 3"
        );
        let mut m = Matrix3::zeros();
        m[(0, 1)] = 1.0;
        assert_eq!(
            symmetric(&m).unwrap_err().message,
            "must be symmetric, got [0][1] = 1 but [1][0] = 0"
        );
        m[(1, 0)] = 1.0 + 1e-11;
        assert!(symmetric(&m).is_ok());
    }
}
