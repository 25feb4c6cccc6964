//! The `embusen` command line. Native only: in the browser the app is the
//! interface, but `cargo test --target wasm32-unknown-unknown` still builds
//! every binary, so on wasm this is an empty program.

#[cfg(all(not(target_arch = "wasm32"), feature = "board"))]
mod calibrate;
#[cfg(not(target_arch = "wasm32"))]
mod cli;
#[cfg(not(target_arch = "wasm32"))]
mod eval_track;
#[cfg(not(target_arch = "wasm32"))]
mod takes;
#[cfg(not(target_arch = "wasm32"))]
mod track;

#[cfg(not(target_arch = "wasm32"))]
fn main() -> std::process::ExitCode {
    cli::main()
}

#[cfg(target_arch = "wasm32")]
fn main() {}
