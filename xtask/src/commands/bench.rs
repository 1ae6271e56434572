//! `cargo xtask bench [--criterion] [--no-setup] [ARGS]`: the FFT benchmarks against FFTW.

use crate::process::{cargo, run_checked, say, workspace_root};
use crate::setup::{ensure_apt_packages, BENCH_APT_PACKAGES};
use crate::Result;

/// Options of `cargo xtask bench`.
#[derive(Debug, Default, PartialEq)]
pub struct BenchOpts {
    /// `--criterion`: also run `cargo bench --bench fft`.
    criterion: bool,
    /// `--no-setup`: install nothing.
    no_setup: bool,
    /// Passed to `vr-ocean bench`.
    passthrough: Vec<String>,
}

/// Parses `bench` options: its own flags are taken out, the rest (and all after `--`) pass
/// through to `vr-ocean bench`.
pub fn parse_bench_args(args: &[String]) -> Result<BenchOpts> {
    let mut opts = BenchOpts::default();
    let mut iter = args.iter();
    while let Some(arg) = iter.next() {
        match arg.as_str() {
            "--criterion" => opts.criterion = true,
            "--no-setup" => opts.no_setup = true,
            "--" => {
                opts.passthrough.extend(iter.by_ref().cloned());
                break;
            }
            _ => opts.passthrough.push(arg.clone()),
        }
    }
    Ok(opts)
}

/// `cargo xtask bench`: `vr-ocean bench` (release, `fftw` feature), then criterion if asked.
pub fn cmd_bench(opts: &BenchOpts) -> Result<()> {
    let root = workspace_root();
    if opts.no_setup {
        say("set-up skipped (--no-setup)");
    } else {
        ensure_apt_packages(BENCH_APT_PACKAGES)?;
    }
    // Without arguments: the baseline comparison on one thread, then thread scaling without
    // the baselines (their buffers crowd the shared cache and distort the scaling rounds).
    let default_runs: [&[&str]; 2] = [
        &["--threads", "1"],
        &["--threads", "1,2", "--skip-baselines"],
    ];
    // Other arguments are added to both runs; choosing `--threads` yourself makes it one run.
    let runs: Vec<Vec<String>> = if opts.passthrough.iter().any(|a| a.starts_with("--threads")) {
        vec![opts.passthrough.clone()]
    } else {
        default_runs
            .iter()
            .map(|r| {
                r.iter()
                    .map(|a| a.to_string())
                    .chain(opts.passthrough.iter().cloned())
                    .collect()
            })
            .collect()
    };
    for args in runs {
        let mut cmd = cargo();
        cmd.args([
            "run",
            "--release",
            "--features",
            "fftw",
            "--bin",
            "vr-ocean",
            "--",
            "bench",
        ])
        .args(&args)
        .current_dir(&root);
        run_checked(&mut cmd)?;
    }
    if opts.criterion {
        let mut cmd = cargo();
        cmd.args(["bench", "--features", "fftw", "--bench", "fft"])
            .current_dir(&root);
        run_checked(&mut cmd)?;
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    fn strings(args: &[&str]) -> Vec<String> {
        args.iter().map(|s| s.to_string()).collect()
    }

    #[test]
    fn bench_flags_are_stripped_and_rest_passes_through() {
        let opts = parse_bench_args(&strings(&[
            "--criterion",
            "--size",
            "512",
            "--",
            "--no-setup",
        ]))
        .unwrap();
        assert!(opts.criterion);
        assert!(!opts.no_setup);
        assert_eq!(opts.passthrough, strings(&["--size", "512", "--no-setup"]));
    }
}
