//! The `quatrot` command-line interface (see [`quatrot::cli`]).

fn main() {
    std::process::exit(quatrot::cli::main());
}
