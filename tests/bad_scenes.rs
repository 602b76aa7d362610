//! Every file in `tests/bad_scenes/` is a scene that must be rejected with the
//! exact message stated on its `# error: ` line, by loading it or by the
//! checks `run` makes before its first step ([`prepare`], as `quatrot check`
//! does: the sizes of the run, then the potential, built, for what
//! validation cannot check cheaply: coincident sites, the size of the sums,
//! a lattice for the FFT path). Each file is a test case of its own (named
//! after the file), so a failure names the scene. The memory limit is set
//! to [`MEMORY_LIMIT`], as `tests/cli.rs` sets it through the environment,
//! so that messages naming it do not depend on the machine.

use libtest_mimic::{Arguments, Failed, Trial};
use quatrot::run::prepare;
use quatrot::scene::{load, Overrides};
use std::path::{Path, PathBuf};

const MARKER: &str = "# error: ";
/// The memory limit of the corpus.
const MEMORY_LIMIT: &str = "4G";
/// The corpus holds at least this many bad scenes (a folder emptied or
/// misread would otherwise pass).
const MIN_BAD_SCENES: usize = 30;

/// The scene files of the corpus, sorted.
fn corpus() -> Vec<PathBuf> {
    let dir = Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/bad_scenes");
    let mut paths: Vec<_> = std::fs::read_dir(&dir)
        .expect("tests/bad_scenes exists")
        .map(|e| e.expect("readable entry").path())
        .filter(|p| p.extension().is_some_and(|x| x == "toml"))
        .collect();
    paths.sort();
    paths
}

/// The scene at `path` fails to load with its stated message.
fn fails_with_its_stated_message(path: &Path) -> Result<(), Failed> {
    let text = std::fs::read_to_string(path).map_err(|e| format!("unreadable: {e}"))?;
    let expected = text
        .lines()
        .find_map(|l| l.strip_prefix(MARKER))
        .ok_or_else(|| format!("no `{MARKER}` line"))?;
    let path = path.to_str().ok_or("not a UTF-8 path")?;
    let error = match load(path, &Overrides::default()) {
        Ok((_, scene)) => match prepare(&scene, false) {
            Ok(_) => return Err("accepted".into()),
            Err(e) => e.to_string(),
        },
        Err(e) => e.to_string(),
    };
    if error == expected {
        Ok(())
    } else {
        Err(format!("\n  expected: {expected}\n  got:      {error}").into())
    }
}

fn main() {
    quatrot::internals::set_limit(MEMORY_LIMIT, quatrot::internals::LIMIT_VARIABLE)
        .expect("the limit is set first");
    let paths = corpus();
    let count = paths.len();
    let mut trials = vec![Trial::test("corpus_has_enough_bad_scenes", move || {
        if count >= MIN_BAD_SCENES {
            Ok(())
        } else {
            Err(format!("only {count} bad scenes, at least {MIN_BAD_SCENES} expected").into())
        }
    })];
    trials.extend(paths.into_iter().map(|path| {
        let name = path
            .file_stem()
            .map_or_else(String::new, |s| s.to_string_lossy().into_owned());
        Trial::test(name, move || fails_with_its_stated_message(&path))
    }));
    libtest_mimic::run(&Arguments::from_args(), trials).exit();
}
