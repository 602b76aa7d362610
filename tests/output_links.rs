//! No output is created or written through a symbolic link planted in the
//! output folder (issue 37: `topology.pdb` and `trajectory.gsd` were written
//! through one). A link is planted at every name a run writes, pointing at a
//! file outside the folder; the run either refuses it, naming the file, or
//! replaces the link itself (files written by rename), and the file outside
//! keeps its bytes.

use std::process::Command;

/// A run that writes every kind of output: a series, a trajectory in the
/// format `format`, checkpoints and the summary.
fn scene(format: &str) -> String {
    format!(
        r#"
version = 1
[rotors]
kind = "sites"
sites = [{{ position = [0.0, 0.0, 0.0] }}, {{ position = [1.5, 0.0, 0.0] }}]
default = {{ inertia = 1.0, dipole = [0.0, 0.0, 1.0] }}
[interactions]
boundary = {{ kind = "open" }}
[initial]
kind = "random"
seed = 3
temperature = 1.0
[integrator]
kind = "dlm"
[run]
dt = 0.01
steps = 10
[record]
checkpoint_every = 5
[[record.series]]
name = "energies"
every = 5
quantities = ["total_energy"]
[record.trajectory]
every = 5
format = "{format}"
"#
    )
}

/// Every name a run writes in its folder, with the trajectory format that
/// writes it.
const OUTPUTS: [(&str, &str); 11] = [
    ("energies.csv", "dcd"),
    ("topology.pdb", "dcd"),
    ("trajectory.dcd", "dcd"),
    ("trajectory.gsd", "gsd"),
    ("checkpoint.json", "dcd"),
    ("checkpoint.json.partial", "dcd"),
    ("summary.json", "dcd"),
    ("summary.json.partial", "dcd"),
    ("summary.json", "gsd"),
    ("energies.csv", "gsd"),
    (".quatrot.lock", "dcd"),
];

#[cfg(unix)]
#[test]
fn no_output_is_written_through_a_link_in_the_folder() {
    for (name, format) in OUTPUTS {
        let work = tempfile::tempdir().expect("temporary folder");
        let victim = work.path().join("victim.txt");
        std::fs::write(&victim, "a user's file").expect("victim written");
        let out = work.path().join("out");
        std::fs::create_dir(&out).expect("output folder");
        std::os::unix::fs::symlink(&victim, out.join(name)).expect("link planted");
        let file = work.path().join("scene.toml");
        std::fs::write(&file, scene(format)).expect("scene written");
        let output = Command::new(env!("CARGO_BIN_EXE_quatrot"))
            .args(["run", file.to_str().expect("utf-8"), "--out"])
            .arg(&out)
            .output()
            .expect("quatrot runs");
        let stderr = String::from_utf8_lossy(&output.stderr);
        assert_eq!(
            std::fs::read_to_string(&victim).expect("victim readable"),
            "a user's file",
            "{name} ({format}): written through the link; stderr: {stderr}"
        );
        let still_a_link = std::fs::symlink_metadata(out.join(name))
            .map(|m| m.file_type().is_symlink())
            .unwrap_or(false);
        if output.status.success() {
            assert!(!still_a_link, "{name} ({format}): the run used the link");
        } else {
            assert_eq!(output.status.code(), Some(2), "{name} ({format}): {stderr}");
            assert!(stderr.contains(name), "{name} ({format}): {stderr}");
            // Said plainly (the links fuzz saw "Too many levels of symbolic links").
            assert!(
                stderr.contains(&format!(
                    "{name}: is a symbolic link; a run writes only inside"
                )),
                "{name} ({format}): {stderr}"
            );
        }
    }
}
