//! Internally tagged enums (`kind = "..."` inside the table) whose errors keep
//! the path into the variant. serde's derived internally tagged enums buffer
//! the table and lose the path below it; here the table is buffered as a
//! [`toml::Table`], the variant struct is read with its own path tracking,
//! and the inner path travels to [`super::parse`] inside the error message.

use serde::de::DeserializeOwned;

/// Marks an error message that carries an inner path: `MARK path MARK message`.
pub(super) const PATH_MARK: char = '\u{0}';

/// Splits an error message into (inner path, message) if it carries one.
pub(super) fn split_inner_path(message: &str) -> Option<(&str, &str)> {
    let rest = message.strip_prefix(PATH_MARK)?;
    rest.split_once(PATH_MARK)
}

/// Joins an outer path and an error message that may carry an inner path.
pub(super) fn join_path(outer: &str, message: &str) -> (String, String) {
    match split_inner_path(message) {
        Some((inner, msg)) if outer.is_empty() => (inner.to_string(), msg.to_string()),
        Some((inner, msg)) => (format!("{outer}.{inner}"), msg.to_string()),
        None => (outer.to_string(), message.to_string()),
    }
}

/// An error carrying `path` (relative to the tagged table) and `message`.
pub(super) fn with_inner_path<E: serde::de::Error>(path: &str, message: &str) -> E {
    E::custom(format!("{PATH_MARK}{path}{PATH_MARK}{message}"))
}

/// Reads the variant struct `T` from the rest of the table, with paths.
pub(super) fn variant<T: DeserializeOwned, E: serde::de::Error>(
    table: toml::Table,
) -> Result<T, E> {
    variant_with(table, |deserializer| T::deserialize(deserializer))
}

/// The table read through a deserializer that tracks paths.
pub(super) type Tracked<'a> = serde_path_to_error::Deserializer<'a, 'a, toml::Value>;

/// Reads a variant from the rest of the table with `read`, the error
/// carrying the path inside the table.
pub(super) fn variant_with<T, E: serde::de::Error>(
    table: toml::Table,
    read: impl FnOnce(Tracked<'_>) -> Result<T, toml::de::Error>,
) -> Result<T, E> {
    let mut track = serde_path_to_error::Track::new();
    let value = toml::Value::Table(table);
    read(serde_path_to_error::Deserializer::new(value, &mut track)).map_err(|e| {
        let outer = track.path().to_string();
        let outer = if outer == "." { "" } else { outer.as_str() };
        let (path, message) = join_path(outer, e.message());
        if path.is_empty() {
            E::custom(message)
        } else {
            with_inner_path(&path, &message)
        }
    })
}

/// Removes and returns the `kind` tag of a table.
pub(super) fn take_kind<E: serde::de::Error>(table: &mut toml::Table) -> Result<String, E> {
    match table.remove("kind") {
        Some(toml::Value::String(kind)) => Ok(kind),
        Some(other) => Err(with_inner_path(
            "kind",
            &format!("invalid type: {}, expected a string", other.type_str()),
        )),
        None => Err(E::missing_field("kind")),
    }
}

/// Implements `Deserialize` for an enum of newtype variants around structs,
/// tagged by `kind`.
macro_rules! tagged {
    ($enum:ident { $($tag:literal => $variant:ident($payload:ty)),+ $(,)? }) => {
        impl<'de> serde::Deserialize<'de> for $enum {
            fn deserialize<D: serde::Deserializer<'de>>(deserializer: D) -> Result<Self, D::Error> {
                use super::tagged::{take_kind, variant, with_inner_path};
                const TAGS: &[&str] = &[$($tag),+];
                let mut table = toml::Table::deserialize(deserializer)?;
                let kind = take_kind::<D::Error>(&mut table)?;
                match kind.as_str() {
                    $($tag => variant::<$payload, D::Error>(table).map($enum::$variant),)+
                    other => {
                        let e: D::Error = serde::de::Error::unknown_variant(other, TAGS);
                        Err(with_inner_path("kind", &e.to_string()))
                    }
                }
            }
        }
    };
}
pub(super) use tagged;
