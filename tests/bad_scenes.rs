//! Every file in `tests/bad_scenes/` is a scene that must be rejected with the
//! exact message stated on its `# error: ` line.

use quatrot::scene::{load, Overrides};
use std::path::Path;

const MARKER: &str = "# error: ";
/// The corpus holds at least this many bad scenes (a folder emptied or
/// misread would otherwise pass).
const MIN_BAD_SCENES: usize = 30;

#[test]
fn every_bad_scene_fails_with_its_stated_message() {
    let dir = Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/bad_scenes");
    let mut paths: Vec<_> = std::fs::read_dir(&dir)
        .expect("tests/bad_scenes exists")
        .map(|e| e.expect("readable entry").path())
        .filter(|p| p.extension().is_some_and(|x| x == "toml"))
        .collect();
    paths.sort();
    assert!(
        paths.len() >= MIN_BAD_SCENES,
        "only {} bad scenes",
        paths.len()
    );
    let mut failures = Vec::new();
    for path in &paths {
        let text = std::fs::read_to_string(path).expect("readable file");
        let expected = text
            .lines()
            .find_map(|l| l.strip_prefix(MARKER))
            .unwrap_or_else(|| panic!("{}: no `{MARKER}` line", path.display()));
        match load(path.to_str().expect("utf-8 path"), &Overrides::default()) {
            Ok(_) => failures.push(format!("{}: accepted", path.display())),
            Err(e) if e.to_string() == expected => {}
            Err(e) => failures.push(format!(
                "{}:\n  expected: {expected}\n  got:      {e}",
                path.file_name().unwrap_or_default().to_string_lossy()
            )),
        }
    }
    assert!(failures.is_empty(), "\n{}", failures.join("\n"));
}
