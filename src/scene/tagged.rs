//! Internally tagged enums (`kind = "..."` inside the table) whose errors keep
//! the path into the variant. serde's derived internally tagged enums buffer
//! the table and lose the path below it; here the table is buffered as a
//! [`toml::Table`] and the variant struct is read with its own path tracking
//! ([`read_variant`]), giving a [`TaggedError`] with that path.
//!
//! A serde error holds only a message, so when a tagged enum is read inside
//! serde (the scene's sections), the path below its table travels beside
//! the error, never inside the message: [`TaggedError::into_serde`] leaves it
//! in a slot of the thread, and [`locate`], called by the reader that sees
//! the error come out of serde ([`read_variant`] or the scene's parser),
//! takes it and joins it to the path where serde stopped.

use serde::de::DeserializeOwned;
use std::cell::RefCell;

/// An error inside a tagged table: the path below it and what is wrong.
#[derive(Debug, Clone, PartialEq)]
pub(super) struct TaggedError {
    /// The path below the table (`substeps`, `sites[3].inertia`); empty for
    /// the table itself.
    pub path: String,
    /// What is wrong, with the value found.
    pub message: String,
}

thread_local! {
    /// The path below a tagged table of the error on its way out of serde
    /// (see the module doc).
    static PENDING_PATH: RefCell<Option<String>> = const { RefCell::new(None) };
}

impl TaggedError {
    /// An error at `path` below the table.
    pub(super) fn at(path: &str, message: impl Into<String>) -> TaggedError {
        TaggedError {
            path: path.to_string(),
            message: message.into(),
        }
    }

    /// The error with `outer` put in front of its path (the path of the
    /// table in what holds it).
    pub(super) fn below(self, outer: &str) -> TaggedError {
        let path = match (outer, self.path.as_str()) {
            (outer, "") => outer.to_string(),
            ("", inner) => inner.to_string(),
            (outer, inner) => format!("{outer}.{inner}"),
        };
        TaggedError { path, ..self }
    }

    /// The error as serde's error type (its message), its path left for
    /// [`locate`].
    pub(super) fn into_serde<E: serde::de::Error>(self) -> E {
        PENDING_PATH.with(|pending| *pending.borrow_mut() = Some(self.path));
        E::custom(self.message)
    }
}

/// Forgets the path of an earlier error: called before a read whose error
/// [`locate`] will place.
pub(super) fn forget_pending_path() {
    PENDING_PATH.with(|pending| *pending.borrow_mut() = None);
}

/// The error `message` that serde raised at `outer` (as tracked by
/// `serde_path_to_error`), at its full path: `outer` joined to the path
/// below a tagged table that [`TaggedError::into_serde`] left, if any.
pub(super) fn locate(outer: &serde_path_to_error::Path, message: &str) -> TaggedError {
    let outer = outer.to_string();
    let outer = if outer == "." { "" } else { outer.as_str() };
    match PENDING_PATH.with(|pending| pending.borrow_mut().take()) {
        Some(inner) => TaggedError::at(&inner, message).below(outer),
        None => TaggedError::at(outer, message),
    }
}

/// The table read through a deserializer that tracks paths.
pub(super) type Tracked<'a> = serde_path_to_error::Deserializer<'a, 'a, toml::Value>;

/// Reads a variant from the rest of the table (its `kind` removed) with
/// `read`, the error at its path inside the table.
pub(super) fn read_variant<T>(
    table: toml::Table,
    read: impl FnOnce(Tracked<'_>) -> Result<T, toml::de::Error>,
) -> Result<T, TaggedError> {
    forget_pending_path();
    let mut track = serde_path_to_error::Track::new();
    let value = toml::Value::Table(table);
    read(serde_path_to_error::Deserializer::new(value, &mut track))
        .map_err(|e| locate(&track.path(), e.message().trim_end()))
}

/// Reads the struct `T` from a table, the error at its path inside it.
pub(super) fn read_table<T: DeserializeOwned>(table: toml::Table) -> Result<T, TaggedError> {
    read_variant(table, |deserializer| T::deserialize(deserializer))
}

/// Removes and returns the `kind` tag of a table (the error's path is
/// `kind`, or the table's when it is missing).
pub(super) fn take_kind(table: &mut toml::Table) -> Result<String, TaggedError> {
    match table.remove("kind") {
        Some(toml::Value::String(kind)) => Ok(kind),
        Some(other) => Err(TaggedError::at(
            "kind",
            format!("invalid type: {}, expected a string", other.type_str()),
        )),
        None => Err(TaggedError::at("", "missing field `kind`")),
    }
}

/// The error for a `kind` that is none of `kinds`.
pub(super) fn unknown_kind(kind: &str, kinds: &'static [&'static str]) -> TaggedError {
    let e: toml::de::Error = serde::de::Error::unknown_variant(kind, kinds);
    TaggedError::at("kind", e.message().trim_end())
}

/// Implements `Deserialize` for an enum of newtype variants around structs,
/// tagged by `kind`.
macro_rules! tagged {
    ($enum:ident { $($tag:literal => $variant:ident($payload:ty)),+ $(,)? }) => {
        impl<'de> serde::Deserialize<'de> for $enum {
            fn deserialize<D: serde::Deserializer<'de>>(deserializer: D) -> Result<Self, D::Error> {
                use super::tagged::{read_table, take_kind, unknown_kind};
                const TAGS: &[&str] = &[$($tag),+];
                let mut table = toml::Table::deserialize(deserializer)?;
                let read = take_kind(&mut table).and_then(|kind| match kind.as_str() {
                    $($tag => read_table::<$payload>(table).map($enum::$variant),)+
                    other => Err(unknown_kind(other, TAGS)),
                });
                read.map_err(|e| e.into_serde())
            }
        }
    };
}
pub(super) use tagged;

#[cfg(test)]
mod tests {
    use super::*;
    use crate::scene::parse::parse_toml;

    /// The error of `text` (a scene) as written.
    fn error(text: &str) -> String {
        parse_toml(text).expect_err("refused").to_string()
    }

    /// A scene whose `[integrator]` table holds `options`.
    fn with_integrator(options: &str) -> String {
        format!(
            "version = 1\n[rotors]\nkind = 'sites'\nsites = [{{ position = [0.0, 0.0, 0.0], inertia = 1.0 }}]\n\
             [initial]\nkind = 'uniform'\norientation = [1.0, 0.0, 0.0, 0.0]\nomega_body = [0.0, 0.0, 1.0]\n\
             [integrator]\n{options}\n[run]\ndt = 0.01\nsteps = 1\n"
        )
    }

    /// The path below a tagged table reaches the scene's error beside the
    /// message (which holds no path), nested tables included.
    #[test]
    fn paths_below_tagged_tables_are_joined() {
        assert_eq!(
            error(&with_integrator("kind = 'no_squish'\nsubsteps = 0")),
            "integrator.substeps: must be >= 1, got 0"
        );
        assert_eq!(
            error(&with_integrator("kind = 'gear'")),
            "integrator.kind: unknown variant `gear`, expected one of `gear_a`, `gear_b`, \
             `no_squish`, `dlm`, `richardson`"
        );
        assert_eq!(error(&with_integrator("")), "integrator.kind: missing");
        let text = with_integrator("kind = 'dlm'").replace("inertia = 1.0", "inertia = 'x'");
        assert!(
            error(&text).starts_with("rotors.sites[0].inertia: "),
            "{}",
            error(&text)
        );
    }

    /// A path left by an error that never reached a reader is not joined to
    /// the next error.
    #[test]
    fn a_stale_path_is_forgotten() {
        let _: toml::de::Error = TaggedError::at("stale", "m").into_serde();
        assert_eq!(
            error(&with_integrator("kind = 'dlm'").replace("steps = 1", "steps = true")),
            "run.steps: invalid type: boolean `true`, expected i64"
        );
    }
}
