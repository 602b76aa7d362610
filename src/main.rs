//! The `quatrot` command-line interface (`src/cli`, reached through `quatrot::internals`).

fn main() {
    std::process::exit(quatrot::internals::cli_main());
}
