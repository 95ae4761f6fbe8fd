//! The `cardan` binary: a thin wrapper around [`cardan_cli::main_with_args`].

fn main() {
    std::process::exit(cardan_cli::main_with_args(std::env::args_os()));
}
