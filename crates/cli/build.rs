//! Links the `cardan` command as a position-dependent executable on Linux (GNU toolchains).
//!
//! A position-independent executable is relocated by the loader at every start: the 21 MB
//! command has about 25,000 relocations over 450 kB of `.data.rel.ro` (vtables, string tables),
//! which the loader writes (and the kernel copies page by page) before `main`. Linked with
//! `-no-pie` the linker resolves them once: `cardan --version` takes 1.1 ms of processor time
//! instead of 2.1 ms (139 page faults instead of 257), and a small ASMT file's whole
//! `cardan run` 5.8 ms instead of 8.0 ms (AMD EPYC, 2026-12-08). The price is address-space
//! randomization of the executable's own code (libraries, stack and heap keep it), acceptable
//! for a command-line calculator that reads model files. The library crates and the Python
//! extension are unaffected (the flag applies to this package's binaries only).

fn main() {
    let os = std::env::var("CARGO_CFG_TARGET_OS").unwrap_or_default();
    let env = std::env::var("CARGO_CFG_TARGET_ENV").unwrap_or_default();
    if os == "linux" && env == "gnu" {
        println!("cargo:rustc-link-arg-bins=-no-pie");
    }
    println!("cargo:rerun-if-changed=build.rs");
}
