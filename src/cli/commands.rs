//! The commands: `run` (with a progress bar on a terminal), `scenes`,
//! `check` and `sweep` (a launcher of the Python sweep), each turning every user error into a message and an exit code.

use super::args::{Cli, Command};
use super::progress::ProgressBarObserver;
use super::{sweep, EXIT_ERROR};
use crate::parallel::{fixed_threads, MAX_THREADS};
use crate::run::{execute, prepare, Outputs, Placement, Progress, RunResult};
use crate::scene::{load, parse_toml, Overrides, Scene, BUILTINS};
use crate::simulation::{Control, Stop};
use clap::Parser;
use std::ffi::OsString;
use std::io::{IsTerminal, Write};
use std::num::NonZeroUsize;
use std::path::PathBuf;
use std::sync::Arc;

/// Exit code of a run that blew up (its outputs are written and valid).
const EXIT_BLOW_UP: i32 = 3;
/// Exit code of a run stopped by SIGINT or SIGTERM (its outputs are
/// written, flushed and valid up to the step it stopped at; 128 + SIGINT,
/// as shells report an interrupted command).
const EXIT_INTERRUPTED: i32 = 130;
/// Runs shorter than this many steps get no progress bar.
const PROGRESS_MIN_STEPS: u64 = 1000;
/// Progress bar updates per run.
const PROGRESS_UPDATES: u64 = 200;

/// Runs the command line and returns the process exit code.
pub fn main() -> i32 {
    main_from(std::env::args_os())
}

/// Runs the command line `args` (the program name first), as [`main`]
/// does the process's (`python -m quatrot` passes Python's `sys.argv`).
pub fn main_from<I, T>(args: I) -> i32
where
    I: IntoIterator<Item = T>,
    T: Into<OsString> + Clone,
{
    let cli = match Cli::try_parse_from(args) {
        Ok(cli) => cli,
        Err(e) => {
            // Usage errors, --help and --version, as clap prints them.
            let _ = e.print();
            return e.exit_code();
        }
    };
    if let Some(limit) = &cli.memory_limit {
        if let Err(e) = crate::memory::set_limit(limit, "--memory-limit") {
            return fail(&e);
        }
    }
    match cli.command {
        Command::Scenes => after_output(list_scenes(), 0),
        Command::Check { scene } => match load(&scene, &Overrides::default()) {
            Ok((_, scene)) => match prepare(&scene, false) {
                Ok(_) => after_output(say(&format!("ok: {}", describe(&scene))), 0),
                Err(e) => fail(&e),
            },
            Err(e) => fail(&e),
        },
        Command::Run {
            scene,
            out,
            dt,
            steps,
            integrator,
            no_thermostat,
            restart,
            threads,
        } => {
            let overrides = Overrides {
                dt,
                steps,
                integrator,
                no_thermostat,
            };
            match threads.map(thread_count).transpose() {
                Ok(threads) => run(&scene, &overrides, out, restart, threads),
                Err(e) => fail(&e),
            }
        }
        Command::Sweep { args } => match sweep::launch(&args) {
            Ok(code) => code,
            Err(e) => fail(&e),
        },
    }
}

fn fail(e: &dyn std::fmt::Display) -> i32 {
    tell(&format!("error: {e}"));
    EXIT_ERROR
}

/// Writes `line` to standard error; a standard error that cannot be
/// written to (closed, full) is not reported anywhere.
fn tell(line: &str) {
    let _ = writeln!(std::io::stderr().lock(), "{line}");
}

/// Writes `line` to standard output.
fn say(line: &str) -> std::io::Result<()> {
    let mut out = std::io::stdout().lock();
    writeln!(out, "{line}").and_then(|()| out.flush())
}

/// The exit code after the output of a command that would exit with
/// `code`: a reader that went away (a closed pipe, as `| head`) ends the
/// output quietly with that code; any other failure to write (a full disk)
/// is an error.
fn after_output(written: std::io::Result<()>, code: i32) -> i32 {
    match written {
        Err(e) if e.kind() != std::io::ErrorKind::BrokenPipe => {
            fail(&format!("cannot write to standard output: {e}"))
        }
        _ => code,
    }
}

fn list_scenes() -> std::io::Result<()> {
    let width = BUILTINS.iter().map(|b| b.name.len()).max().unwrap_or(0);
    for b in BUILTINS {
        let description = parse_toml(b.toml)
            .ok()
            .and_then(|raw| raw.description)
            .unwrap_or_default();
        say(&format!("{:width$}  {description}", b.name))?;
    }
    Ok(())
}

fn describe(scene: &Scene) -> String {
    let seed = scene.seed.map_or(String::new(), |s| format!(", seed {s}"));
    let population = match &scene.bodies {
        Some(b) => format!("{} bodies", b.bodies.len()),
        None => format!("{} rotors", scene.rotors.len()),
    };
    let time_unit = scene
        .units
        .names()
        .map_or(String::new(), |n| format!(" {}", n.time));
    format!(
        "{}: {population}, {}, dt {}{time_unit}, {} steps{seed}",
        scene.name,
        scene.integrator.name(),
        crate::checks::num(scene.dt),
        scene.steps
    )
}

/// The `--threads` value: 1 to [`MAX_THREADS`].
fn thread_count(threads: i64) -> Result<NonZeroUsize, String> {
    fixed_threads(threads)
        .ok_or_else(|| format!("--threads: must be between 1 and {MAX_THREADS}, got {threads}"))
}

fn run(
    name: &str,
    overrides: &Overrides,
    out: Option<PathBuf>,
    restart: Option<PathBuf>,
    threads: Option<NonZeroUsize>,
) -> i32 {
    let (raw, scene) = match load(name, overrides) {
        Ok(loaded) => loaded,
        Err(e) => return fail(&e),
    };
    let definition = raw.definition();
    let dir = out.unwrap_or_else(|| PathBuf::from("quatrot_out").join(&scene.name));
    let control = Arc::new(Control::new());
    stop_on_signals(&control);
    let outputs = Outputs {
        dir: Some(dir.clone()),
        keep: false,
        control: Some(control),
        threads,
    };
    let show_progress = std::io::stderr().is_terminal() && scene.steps >= PROGRESS_MIN_STEPS;
    let mut bar = show_progress.then(|| ProgressBarObserver::new(scene.steps));
    let progress = bar.as_mut().map(|b| Progress {
        every: (scene.steps / PROGRESS_UPDATES).max(1),
        observer: b,
    });
    match execute(&scene, definition, &outputs, restart.as_deref(), progress) {
        Ok(result) => {
            let code = match result.stop {
                Stop::Completed => 0,
                Stop::BlewUp { .. } => EXIT_BLOW_UP,
                Stop::Interrupted { .. } => EXIT_INTERRUPTED,
            };
            after_output(say(&one_line(&scene, &result)), code)
        }
        Err(e) => fail(&e),
    }
}

/// SIGINT and SIGTERM ask the run to stop at the end of the current step
/// (it then flushes and closes its outputs); a second one exits at once.
fn stop_on_signals(control: &Arc<Control>) {
    let control = Arc::clone(control);
    let installed = ctrlc::set_handler(move || {
        if control.stop_requested() {
            tell("quatrot: interrupted again: exiting without flushing the outputs");
            std::process::exit(EXIT_INTERRUPTED);
        }
        tell(&format!(
            "quatrot: stopping at the end of step {} (interrupt again to exit at once)",
            control.step() + 1
        ));
        control.request_stop();
    });
    if let Err(e) = installed {
        tell(&format!("quatrot: warning: cannot catch interrupts ({e}); an interrupt ends the run without flushing its outputs"));
    }
}

/// Where the outputs went, in words.
fn placement(result: &RunResult) -> String {
    match &result.written {
        None => "No output files".to_string(),
        Some((dir, Placement::New)) => format!("Outputs in {}", dir.display()),
        Some((dir, Placement::Append(_))) => {
            format!(
                "Outputs appended to the earlier run's files in {}",
                dir.display()
            )
        }
        Some((dir, Placement::NewFolder { reason, .. })) => format!(
            "Outputs in the new folder {} (the earlier files were kept: {reason})",
            dir.display()
        ),
    }
}

/// The one-line summary printed at the end of a run.
fn one_line(scene: &Scene, result: &RunResult) -> String {
    let s = &result.summary;
    let steps = s.last_step - s.start_step;
    let rate = steps as f64 / s.wall_seconds.max(f64::MIN_POSITIVE);
    let energy = match (&s.final_energies, &s.drift) {
        (Some(e), Some(d)) => format!(
            ", energy error {:.3e}, drift {:.3e} per unit time",
            e.error, d.relative_per_time
        ),
        (Some(e), None) => format!(", energy error {:.3e}", e.error),
        _ => String::new(),
    };
    let status = s
        .message
        .as_ref()
        .map_or(String::new(), |m| format!(" STOPPED: {m}."));
    let population = match &s.bodies {
        Some(b) => format!("{} bodies", b.count),
        None => format!("{} rotors", s.rotors),
    };
    format!(
        "{}: {steps} steps of {} ({population}) in {:.3} s ({rate:.0} steps/s){energy}.{status} {}.",
        scene.name,
        s.integrator,
        s.wall_seconds,
        placement(result)
    )
}
