//! The integrators and the thermostats meet only through
//! `src/thermostat_hook` (below both) and `src/dynamics.rs` (above both):
//! no file of either folder imports the other, and the hook imports
//! neither (issue 35's one-way rule; the README's architecture section).
//! Facts issue 35 gave one owner keep it: the Ewald accuracy is range-checked
//! only where an [`quatrot::potential::Accuracy`] is made, and the scene's
//! field paths travel outside the messages.

use std::path::Path;

/// Every `.rs` file under `src/<folder>`, with its text.
fn sources(folder: &str) -> Vec<(String, String)> {
    let root = Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("src")
        .join(folder);
    let mut out = Vec::new();
    let mut pending = vec![root];
    while let Some(dir) = pending.pop() {
        for entry in std::fs::read_dir(&dir).expect("a source folder") {
            let path = entry.expect("an entry").path();
            if path.is_dir() {
                pending.push(path);
            } else if path.extension().is_some_and(|e| e == "rs") {
                let text = std::fs::read_to_string(&path).expect("a source file");
                out.push((path.display().to_string(), text));
            }
        }
    }
    assert!(!out.is_empty(), "no sources under src/{folder}");
    out
}

/// The files of `folder` that mention any of `forbidden` (a path between the
/// two folders is refused in code and in doc links alike, as
/// `grep -rn crate::thermostats src/integrators` would show it).
fn offenders(folder: &str, forbidden: &[&str]) -> Vec<String> {
    sources(folder)
        .into_iter()
        .filter_map(|(path, text)| {
            let found: Vec<&str> = forbidden
                .iter()
                .copied()
                .filter(|f| text.contains(f))
                .collect();
            (!found.is_empty()).then(|| format!("{path}: {found:?}"))
        })
        .collect()
}

/// Each folder with what it must not name: the integrators and the
/// thermostats not each other, nor the pairing above them; the hook none of
/// the three.
#[test]
fn the_layers_import_one_way() {
    let rules: [(&str, &[&str]); 3] = [
        (
            "integrators",
            &["crate::thermostats", "use crate::dynamics"],
        ),
        (
            "thermostats",
            &["crate::integrators", "use crate::dynamics"],
        ),
        (
            "thermostat_hook",
            &[
                "use crate::integrators",
                "use crate::thermostats",
                "use crate::dynamics",
            ],
        ),
    ];
    for (folder, forbidden) in rules {
        let found = offenders(folder, forbidden);
        assert!(found.is_empty(), "{found:#?}");
    }
}

/// The code of a source file: without its test module and its comments.
fn production_code(text: &str) -> String {
    let code = text.split("#[cfg(test)]").next().unwrap_or(text);
    code.lines()
        .filter(|line| !line.trim_start().starts_with("//"))
        .collect::<Vec<_>>()
        .join("\n")
}

/// The files of `src/` whose code ([`production_code`]) holds `needle`,
/// once per occurrence.
fn occurrences(needle: &str) -> Vec<String> {
    sources("")
        .into_iter()
        .flat_map(|(path, text)| {
            let count = production_code(&text).matches(needle).count();
            std::iter::repeat_n(path, count)
        })
        .collect()
}

/// The Ewald accuracy is checked once per run: only `Accuracy::new` makes
/// one (its field is private) and holds the range check, and it is called
/// where a sum's options are read, once for each kind of run: rotors'
/// `Boundary::periodic` (the scene and the bindings alike; the potential
/// trusts the type) and the direct Ewald sum of moving bodies
/// (`mesh_ewald::for_waves`, which bodies' `method = "direct"` reaches
/// without a `Boundary`).
#[test]
fn the_accuracy_is_checked_in_one_place() {
    for needle in ["must be in (0, 1)", "pub struct Accuracy(f64);"] {
        let found = occurrences(needle);
        assert_eq!(found.len(), 1, "{needle}: {found:#?}");
        assert!(
            found[0].ends_with("periodic_sum.rs"),
            "{needle}: {found:#?}"
        );
    }
    let readers = occurrences("Accuracy::new");
    assert_eq!(readers.len(), 2, "Accuracy::new: {readers:#?}");
    assert!(
        readers.iter().any(|p| p.ends_with("periodic_sum.rs"))
            && readers.iter().any(|p| p.ends_with("mesh_ewald/waves.rs")),
        "Accuracy::new: {readers:#?}"
    );
}

/// Field paths are typed in the scene layer: no marker character puts a path
/// inside an error message to be parsed back out (the `PATH_MARK` NUL of
/// the tagged tables, read back by `split_inner_path`).
#[test]
fn scene_paths_travel_outside_messages() {
    let markers = ["\\u{0}", "\\0", "PATH_MARK", "split_inner_path"];
    let found: Vec<String> = sources("scene")
        .into_iter()
        .filter(|(_, text)| markers.iter().any(|m| text.contains(m)) || text.contains('\0'))
        .map(|(path, _)| path)
        .collect();
    assert!(found.is_empty(), "{found:#?}");
}
