//! Converts the vendored three.js module into the classic script the report page embeds
//! (`src/classic.rs`), once per build instead of once per `cardan run`.

#[path = "src/classic.rs"]
mod classic;

fn main() {
    let module = "vendor/three-0.160.1/three.module.min.js";
    println!("cargo:rerun-if-changed={module}");
    println!("cargo:rerun-if-changed=src/classic.rs");
    let text = std::fs::read_to_string(module).expect("the vendored three.js module");
    let classic = classic::to_classic(&text)
        .expect("the vendored three.js module is one export statement at the end, no import");
    let out =
        std::path::Path::new(&std::env::var("OUT_DIR").expect("OUT_DIR")).join("three.classic.js");
    std::fs::write(out, classic).expect("write three.classic.js");
}
