//! The `vr-ocean` command line: the ocean window (the default, falling back to headless without a
//! display), headless rendering, the headset through OpenXR (`xr`), simulate, export, bench and
//! lod-svg. Thin: parse ([`cli`]), run, print an error as one line and exit non-zero.

mod cli;

use std::process::ExitCode;

fn main() -> ExitCode {
    env_logger::Builder::from_env(env_logger::Env::default().default_filter_or("info")).init();
    match cli::run(cli::parse()) {
        Ok(()) => ExitCode::SUCCESS,
        Err(e) => {
            eprintln!("error: {e}");
            ExitCode::FAILURE
        }
    }
}
