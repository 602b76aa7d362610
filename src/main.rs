//! The `quatrot` command-line interface.

use clap::Parser;

/// Rotational dynamics of rigid rotors in quaternion form.
#[derive(Parser, Debug)]
#[command(name = "quatrot", version, about)]
struct Cli {}

fn main() {
    let _cli = Cli::parse();
}
