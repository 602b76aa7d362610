//! The memory limit every size that input decides is checked against before
//! anything is allocated: lattices, pair lists, images, trajectories and
//! series kept in memory, energy histories, per-step samples of the Python
//! functions.
//!
//! The limit is [`DEFAULT_FRACTION`] of the memory the process may use (the
//! least of the physical memory, the cgroup's `memory.max` and the
//! address-space limit `ulimit -v`), or the size given in the environment
//! variable [`LIMIT_VARIABLE`] (`QUATROT_MEMORY_LIMIT=16G`; suffixes K, M,
//! G, T are powers of 1024, a plain number is bytes), or the command line's
//! `--memory-limit` ([`set_limit`]). Estimates are computed in `f64`, so no
//! count from input can wrap them.

use crate::checks::InputError;
use std::sync::OnceLock;

/// The environment variable that sets the limit.
pub const LIMIT_VARIABLE: &str = "QUATROT_MEMORY_LIMIT";
/// The share of the available memory allowed by default: the rest is for
/// the interpreter, the thread stacks and what the estimates leave out.
pub const DEFAULT_FRACTION: f64 = 0.5;
/// The limit when the available memory cannot be found (4 GiB).
const FALLBACK_AVAILABLE: f64 = 4.0 * GIB;
const GIB: f64 = 1024.0 * 1024.0 * 1024.0;

/// The limit in force and where it comes from.
#[derive(Clone, Debug, PartialEq)]
pub struct Limit {
    /// Bytes.
    pub bytes: f64,
    /// How it was set, for messages.
    pub origin: String,
}

/// The limit of this process, once decided.
static LIMIT: OnceLock<Result<Limit, InputError>> = OnceLock::new();

/// Sets the limit from `text` (a size as [`LIMIT_VARIABLE`] takes it), set
/// by `origin` (for messages, e.g. `--memory-limit`); it replaces the
/// environment's and the default. Only before the limit was first used.
pub fn set_limit(text: &str, origin: &str) -> Result<(), InputError> {
    let bytes = parse_size(text).map_err(|e| InputError::new(origin, e.message))?;
    LIMIT
        .set(Ok(Limit {
            bytes,
            origin: format!("set by {origin}"),
        }))
        .map_err(|_| InputError::new(origin, "the memory limit is already in use"))
}

/// The limit (read once per process).
pub fn limit() -> &'static Result<Limit, InputError> {
    LIMIT.get_or_init(|| match std::env::var(LIMIT_VARIABLE) {
        Ok(text) => parse_size(&text).map(|bytes| Limit {
            bytes,
            origin: format!("set by {LIMIT_VARIABLE}"),
        }),
        Err(_) => Ok(Limit {
            bytes: DEFAULT_FRACTION * available(),
            origin: format!(
                "half the memory available; set {LIMIT_VARIABLE} (e.g. {LIMIT_VARIABLE}=16G) to change it"
            ),
        }),
    })
}

/// Refuses an allocation of about `bytes` (an estimate) decided by the input
/// at `path` when it exceeds the limit.
pub fn check(path: &str, bytes: f64) -> Result<(), InputError> {
    let limit = limit().clone()?;
    if bytes.is_nan() || bytes > limit.bytes {
        return Err(InputError::new(
            path,
            format!(
                "needs about {} of memory, more than the limit {} ({})",
                show(bytes),
                show(limit.bytes),
                limit.origin
            ),
        ));
    }
    Ok(())
}

/// A size for messages: `12.3 GB` (decimal units); an infinite estimate
/// (a count that overflowed) is `2^64 bytes or more`.
pub fn show(bytes: f64) -> String {
    if !bytes.is_finite() {
        // An estimate whose count overflowed.
        return "2^64 bytes or more".to_string();
    }
    const UNITS: [&str; 6] = ["bytes", "kB", "MB", "GB", "TB", "PB"];
    let mut value = bytes;
    for unit in UNITS {
        if value < 1000.0 || unit == "PB" {
            return if unit == "bytes" {
                format!("{value:.0} {unit}")
            } else if value < 1e6 {
                format!("{value:.1} {unit}")
            } else {
                format!("{value:.1e} {unit}")
            };
        }
        value /= 1000.0;
    }
    unreachable!("the last unit returns")
}

/// Parses a size: bytes, or a number with a suffix K, M, G or T (powers of
/// 1024, optionally followed by `B` or `iB`).
fn parse_size(text: &str) -> Result<f64, InputError> {
    let bad = || {
        InputError::new(
            LIMIT_VARIABLE,
            format!(
                "expected a size such as 16G, 512M or 1000000000, got \"{}\"",
                crate::checks::printable(text, 40)
            ),
        )
    };
    let t = text.trim();
    let t = t
        .strip_suffix("iB")
        .or_else(|| t.strip_suffix('B'))
        .unwrap_or(t);
    let (number, scale) = match t.chars().last().map(|c| c.to_ascii_uppercase()) {
        Some('K') => (&t[..t.len() - 1], 1024.0),
        Some('M') => (&t[..t.len() - 1], 1024.0 * 1024.0),
        Some('G') => (&t[..t.len() - 1], GIB),
        Some('T') => (&t[..t.len() - 1], 1024.0 * GIB),
        _ => (t, 1.0),
    };
    let value: f64 = number.trim().parse().map_err(|_| bad())?;
    if !(value.is_finite() && value > 0.0) {
        return Err(bad());
    }
    let bytes = value * scale;
    if bytes > MAX_LIMIT {
        return Err(InputError::new(
            LIMIT_VARIABLE,
            format!(
                "must be at most 2^64 bytes (16777216T), got \"{}\"",
                crate::checks::printable(text, 40)
            ),
        ));
    }
    Ok(bytes)
}

/// The largest limit: 2^64 bytes, more than any address space.
const MAX_LIMIT: f64 = 18_446_744_073_709_551_616.0;

/// The memory this process may use: the least of the physical memory, the
/// cgroup limit and the address-space limit.
fn available() -> f64 {
    [physical(), cgroup_limit(), address_space_limit()]
        .into_iter()
        .flatten()
        .fold(None, |m: Option<f64>, x| Some(m.map_or(x, |m| m.min(x))))
        .unwrap_or(FALLBACK_AVAILABLE)
}

#[cfg(unix)]
fn physical() -> Option<f64> {
    // SAFETY: sysconf only reads system configuration.
    let (pages, size) = unsafe {
        (
            libc::sysconf(libc::_SC_PHYS_PAGES),
            libc::sysconf(libc::_SC_PAGESIZE),
        )
    };
    (pages > 0 && size > 0).then_some(pages as f64 * size as f64)
}

#[cfg(unix)]
fn address_space_limit() -> Option<f64> {
    let mut limit = libc::rlimit {
        rlim_cur: 0,
        rlim_max: 0,
    };
    // SAFETY: getrlimit writes the struct it is given.
    let ok = unsafe { libc::getrlimit(libc::RLIMIT_AS, &mut limit) } == 0;
    (ok && limit.rlim_cur != libc::RLIM_INFINITY).then_some(limit.rlim_cur as f64)
}

#[cfg(not(unix))]
fn physical() -> Option<f64> {
    None
}

#[cfg(not(unix))]
fn address_space_limit() -> Option<f64> {
    None
}

/// The cgroup's memory limit (cgroup v2 `memory.max`, or v1
/// `memory.limit_in_bytes`), if one is set.
fn cgroup_limit() -> Option<f64> {
    let read = |path: &str| std::fs::read_to_string(path).ok();
    let own = read("/proc/self/cgroup")
        .and_then(|t| {
            t.lines()
                .find_map(|l| l.strip_prefix("0::").map(str::to_string))
        })
        .unwrap_or_default();
    [
        format!("/sys/fs/cgroup{own}/memory.max"),
        "/sys/fs/cgroup/memory.max".to_string(),
        "/sys/fs/cgroup/memory/memory.limit_in_bytes".to_string(),
    ]
    .iter()
    .filter_map(|p| read(p)?.trim().parse::<f64>().ok())
    // cgroup v1 writes a huge number for "no limit".
    .find(|&b| b > 0.0 && b < 1e18)
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Sizes read as written; anything else names the variable.
    #[test]
    fn sizes_parse_with_binary_suffixes() {
        assert_eq!(parse_size("1000"), Ok(1000.0));
        assert_eq!(parse_size("16G"), Ok(16.0 * GIB));
        assert_eq!(parse_size("512MiB"), Ok(512.0 * 1024.0 * 1024.0));
        assert_eq!(parse_size(" 1.5 TB"), Ok(1.5 * 1024.0 * GIB));
        let e = parse_size("lots").unwrap_err();
        assert_eq!(e.path, LIMIT_VARIABLE);
        assert!(e.message.contains("got \"lots\""), "{e}");
        assert!(parse_size("-1G").is_err());
        assert!(parse_size("nan").is_err());
        assert_eq!(parse_size("16777216T"), Ok(MAX_LIMIT));
        assert_eq!(
            parse_size("99999999999999T").unwrap_err().message,
            "must be at most 2^64 bytes (16777216T), got \"99999999999999T\""
        );
    }

    /// Sizes are shown in decimal units with one decimal.
    #[test]
    fn sizes_show_in_decimal_units() {
        assert_eq!(show(512.0), "512 bytes");
        assert_eq!(show(1.26e9), "1.3 GB");
        assert_eq!(show(3.0e20), "300000.0 PB");
        assert_eq!(show(3.0e40), "3.0e25 PB");
    }

    /// The available memory is found on this machine (Linux: physical
    /// memory at least), and the default limit is a share of it.
    #[test]
    fn the_default_limit_is_a_share_of_the_available_memory() {
        assert!(physical().is_some_and(|b| b > 1e8));
        assert!(available() > 1e8);
    }
}
