//! The command line's arguments (clap): the doc comments are the `--help`
//! texts.

use clap::{Parser, Subcommand};
use std::path::PathBuf;

/// Rotational dynamics of rigid rotors in quaternion form.
#[derive(Parser, Debug)]
#[command(name = "quatrot", version, about)]
pub(super) struct Cli {
    /// Memory a run may take for what its input sizes (lattices, pair
    /// lists, histories), e.g. 16G or 512M; default half the memory
    /// available, or QUATROT_MEMORY_LIMIT.
    #[arg(long, global = true)]
    pub(super) memory_limit: Option<String>,
    #[command(subcommand)]
    pub(super) command: Command,
}

#[derive(Subcommand, Debug)]
pub(super) enum Command {
    /// Run a scene (a built-in name or a TOML file).
    Run {
        /// Built-in scene name (see `quatrot scenes`) or path to a .toml file.
        scene: String,
        /// Output directory (default: quatrot_out/<scene name>).
        // The doc comment is the --help text, shown as written.
        #[allow(rustdoc::invalid_html_tags)]
        #[arg(long)]
        out: Option<PathBuf>,
        /// Replace the scene's time step.
        #[arg(long, allow_negative_numbers = true)]
        dt: Option<f64>,
        /// Replace the scene's number of steps.
        #[arg(long, allow_negative_numbers = true)]
        steps: Option<i64>,
        /// Replace the scene's integrator (with default options): gear_a,
        /// gear_b, no_squish, dlm, richardson.
        #[arg(long)]
        integrator: Option<String>,
        /// Drop the scene's thermostat: run at constant energy from its
        /// start (gear_b and richardson take no thermostat).
        #[arg(long)]
        no_thermostat: bool,
        /// Continue from a checkpoint file written by an earlier run.
        #[arg(long)]
        restart: Option<PathBuf>,
        /// Threads of the run (1 to 1024); default the scene's run.threads,
        /// else RAYON_NUM_THREADS if set, else one per 500 rotors or 250 sites
        /// of moving bodies, at least 1, at most the cores. Results are
        /// bitwise reproducible for a given count.
        #[arg(long, allow_negative_numbers = true)]
        threads: Option<i64>,
    },
    /// List the built-in scenes, one per line.
    Scenes,
    /// Validate a scene (and build its potential) without running it.
    Check {
        /// Built-in scene name or path to a .toml file.
        scene: String,
    },
    /// Run a grid of scenes as Dask tasks: `python -m quatrot.sweep` with
    /// these arguments (interpreter: $QUATROT_PYTHON, default python3; see
    /// `quatrot sweep --help`).
    #[command(disable_help_flag = true)]
    Sweep {
        /// Passed to `python -m quatrot.sweep` as they are.
        #[arg(trailing_var_arg = true, allow_hyphen_values = true)]
        args: Vec<String>,
    },
}
