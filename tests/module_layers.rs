//! The crate's modules form the layers `docs/architecture.md` draws, and no
//! arrow runs back up (issue 35): each top-level module of `src/` names in
//! code (`crate::module`, comments and doc links aside) only modules of
//! earlier lines of the layer block, so there is no circle; every module is
//! on a line, and every line's modules exist.

use std::collections::BTreeMap;
use std::path::{Path, PathBuf};

/// The first `text` block of `docs/architecture.md` after `sentence`.
fn block_after(sentence: &str) -> String {
    let path = concat!(env!("CARGO_MANIFEST_DIR"), "/docs/architecture.md");
    let text = std::fs::read_to_string(path).expect("docs/architecture.md");
    let start = text.find(sentence).expect(sentence);
    text[start..]
        .split("```text")
        .nth(1)
        .and_then(|b| b.split("```").next())
        .expect("a text block")
        .to_string()
}

/// The layer block of `docs/architecture.md`: each module with its line.
fn layers() -> BTreeMap<String, usize> {
    let block = block_after("Each layer uses only the layers above it");
    let mut layers = BTreeMap::new();
    let mut line_number = 0;
    for line in block.lines() {
        // A layer line: two spaces, the modules, two or more spaces, words.
        let Some(rest) = line.strip_prefix("  ") else {
            continue;
        };
        if rest.starts_with(' ') {
            continue; // a description's continuation
        }
        line_number += 1;
        let names = rest.split("  ").next().expect("modules");
        for name in names.split(',') {
            let _ = layers.insert(name.trim().to_string(), line_number);
        }
    }
    layers
}

/// Every `.rs` file of the top-level module `name` (`src/name.rs` and the
/// folder `src/name/`).
fn files(src: &Path, name: &str) -> Vec<PathBuf> {
    let mut out = Vec::new();
    let file = src.join(format!("{name}.rs"));
    if file.is_file() {
        out.push(file);
    }
    let mut pending = vec![src.join(name)];
    while let Some(dir) = pending.pop() {
        let Ok(entries) = std::fs::read_dir(&dir) else {
            continue;
        };
        for entry in entries {
            let path = entry.expect("entry").path();
            if path.is_dir() {
                pending.push(path);
            } else if path.extension().is_some_and(|e| e == "rs") {
                out.push(path);
            }
        }
    }
    out
}

/// The modules `text` names in code as `crate::name` (lines that are not
/// comments, up to a trailing comment).
fn named(text: &str) -> Vec<String> {
    let mut out = Vec::new();
    for line in text.lines() {
        let code = line.trim_start();
        if code.starts_with("//") {
            continue;
        }
        let code = code.split("//").next().unwrap_or("");
        for (k, _) in code.match_indices("crate::") {
            let rest = &code[k + "crate::".len()..];
            let name: String = rest
                .chars()
                .take_while(|c| c.is_ascii_lowercase() || *c == '_')
                .collect();
            if !name.is_empty() {
                out.push(name);
            }
        }
    }
    out
}

#[test]
fn every_module_names_only_layers_above_it() {
    let src = Path::new(env!("CARGO_MANIFEST_DIR")).join("src");
    let layers = layers();
    let mut modules: Vec<String> = std::fs::read_dir(&src)
        .expect("src/")
        .map(|e| e.expect("entry").path())
        .filter_map(|p| {
            let stem = p.file_stem()?.to_str()?.to_string();
            (p.is_dir() || p.extension().is_some_and(|e| e == "rs")).then_some(stem)
        })
        .filter(|m| !["lib", "main", "allocation_meter"].contains(&m.as_str()))
        .collect();
    modules.sort();
    modules.dedup();
    let drawn: Vec<&String> = layers.keys().collect();
    assert_eq!(
        modules.iter().collect::<Vec<_>>(),
        drawn,
        "the modules of src/ and of the layer block"
    );
    let mut upward = Vec::new();
    for module in &modules {
        let own = layers[module];
        for file in files(&src, module) {
            let text = std::fs::read_to_string(&file).expect("source");
            for name in named(&text) {
                match layers.get(&name) {
                    Some(&line) if line >= own && &name != module => {
                        upward.push(format!("{}: {module} names {name}", file.display()));
                    }
                    _ => {}
                }
            }
        }
    }
    upward.sort();
    upward.dedup();
    assert!(
        upward.is_empty(),
        "arrows running up or sideways:\n{}",
        upward.join("\n")
    );
}

/// The scan sees a use, a path in an expression and a doc link apart.
#[test]
fn named_modules_are_read_from_code_only() {
    let text = "use crate::checks::num;\n/// [`crate::run`]\nlet x = crate::stats::line_fit(a); // crate::cli\n";
    assert_eq!(named(text), ["checks", "stats"]);
}

/// The `public` and `internal` lists of `docs/architecture.md`, in order.
fn surface() -> (Vec<String>, Vec<String>) {
    let block = block_after("The crate's public surface is");
    let (mut public, mut internal) = (Vec::new(), Vec::new());
    let mut list = &mut public;
    for line in block.lines() {
        let mut rest = line.trim();
        if let Some(r) = rest.strip_prefix("public") {
            (list, rest) = (&mut public, r);
        } else if let Some(r) = rest.strip_prefix("internal") {
            (list, rest) = (&mut internal, r);
        }
        list.extend(
            rest.split(',')
                .map(str::trim)
                .filter(|n| !n.is_empty())
                .map(String::from),
        );
    }
    (public, internal)
}

/// The modules `src/lib.rs` declares, public (`pub mod`) and not, sorted.
fn declared() -> (Vec<String>, Vec<String>) {
    let text = std::fs::read_to_string(concat!(env!("CARGO_MANIFEST_DIR"), "/src/lib.rs"))
        .expect("src/lib.rs");
    let (mut public, mut internal) = (Vec::new(), Vec::new());
    for line in text.lines().map(str::trim) {
        let Some(name) = line.strip_suffix(';') else {
            continue;
        };
        if let Some(name) = name.strip_prefix("pub mod ") {
            public.push(name.to_string());
        } else if let Some(name) = name
            .strip_prefix("pub(crate) mod ")
            .or_else(|| name.strip_prefix("mod "))
        {
            internal.push(name.to_string());
        }
    }
    public.sort();
    internal.sort();
    (public, internal)
}

/// The public and internal modules of `src/lib.rs` are those
/// `docs/architecture.md` lists (the test-only allocation meter aside), and
/// every public module is on the layer block.
#[test]
fn the_public_modules_are_the_documented_ones() {
    let (mut public, mut internal) = surface();
    public.sort();
    internal.sort();
    let (declared_public, mut declared_internal) = declared();
    declared_internal.retain(|m| m != "allocation_meter");
    assert_eq!(declared_public, public, "public modules");
    assert_eq!(declared_internal, internal, "internal modules");
    let layers = layers();
    for module in public.iter().chain(&internal) {
        assert!(layers.contains_key(module), "{module} is on no layer");
    }
}
