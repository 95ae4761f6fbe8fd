//! Project tasks, run as `cargo xtask <task>`.
fn main() {
    eprintln!("usage: cargo xtask oracle [--check]");
    std::process::exit(2);
}
