//! `cargo xtask test`: the project's single test command: set-up, then every check of
//! [`steps::STEPS`] in order, stopping at the first failure, then a summary table.

mod steps;
mod summary;

use std::time::Instant;

pub use steps::CROSS_TARGET;
use steps::{Run, Step, STEPS};
use summary::{print_summary, Outcome};

use crate::process::{banner, cargo, run_status, say, workspace_root};
use crate::setup::{ensure_apt_packages, ensure_rustup, APT_PACKAGES};
use crate::{fuzz, Failure, Result};

/// Options of `cargo xtask test`.
#[derive(Debug, Default, PartialEq)]
pub struct TestOpts {
    /// `--quick`: skip the slow steps.
    quick: bool,
    /// `--no-setup`: install nothing.
    no_setup: bool,
}

/// Parses `test` options.
pub fn parse_test_args(args: &[String]) -> Result<TestOpts> {
    let mut opts = TestOpts::default();
    for arg in args {
        match arg.as_str() {
            "--quick" => opts.quick = true,
            "--no-setup" => opts.no_setup = true,
            other => return Err(Failure::Usage(format!("test: unknown option `{other}`"))),
        }
    }
    Ok(opts)
}

/// `cargo xtask test`: set-up (unless `--no-setup`), then the steps, then the summary.
pub fn cmd_test(opts: &TestOpts) -> Result<()> {
    let root = workspace_root();
    let mut rows: Vec<(String, Outcome)> = Vec::new();

    if opts.no_setup {
        say("set-up skipped (--no-setup)");
        rows.push(("set-up".into(), Outcome::Skipped("--no-setup")));
    } else {
        let start = Instant::now();
        let setup = ensure_apt_packages(APT_PACKAGES).and_then(|()| ensure_rustup());
        let took = start.elapsed();
        if let Err(err) = setup {
            // Report the cause before the summary so it is not lost below the table.
            let code = match err {
                Failure::Msg(msg) => {
                    eprintln!("xtask: error: {msg}");
                    1
                }
                Failure::Exit(code) => code,
                Failure::Usage(msg) => return Err(Failure::Usage(msg)),
            };
            rows.push(("set-up".into(), Outcome::Failed(took)));
            for step in STEPS {
                rows.push((step.name.into(), Outcome::NotRun));
            }
            print_summary(&rows);
            say("FAILED at step `set-up`");
            return Err(Failure::Exit(code));
        }
        rows.push(("set-up".into(), Outcome::Ok(took)));
    }

    // The failed step and what failed in it.
    let mut failed: Option<(&Step, String)> = None;
    for step in STEPS {
        if failed.is_some() {
            rows.push((step.name.into(), Outcome::NotRun));
            continue;
        }
        if opts.quick && step.slow {
            say(&format!("skipping `{}` (--quick)", step.name));
            rows.push((step.name.into(), Outcome::Skipped("--quick")));
            continue;
        }
        banner(&format!("step `{}`: {}", step.name, step.header));
        let start = Instant::now();
        let outcome = match step.prepare.map_or(Ok(Vec::new()), |prepare| prepare()) {
            Ok(envs) => {
                for (key, value) in &envs {
                    say(&format!("with {key}={value}"));
                }
                match step.run {
                    Run::Cargo(args) => {
                        let mut cmd = cargo();
                        cmd.args(args).envs(envs).current_dir(&root);
                        let ok = run_status(&mut cmd)?.success();
                        ok.then_some(())
                            .ok_or_else(|| format!("cargo {}", args.join(" ")))
                    }
                    Run::Fuzz => fuzz::run_all(&root, fuzz::CI_SECONDS),
                }
            }
            Err(err) => {
                if let Failure::Msg(msg) = err {
                    eprintln!("xtask: error: {msg}");
                }
                Err("its preparation (see the error above)".into())
            }
        };
        let took = start.elapsed();
        match outcome {
            Ok(()) => rows.push((step.name.into(), Outcome::Ok(took))),
            Err(what) => {
                rows.push((step.name.into(), Outcome::Failed(took)));
                failed = Some((step, what));
            }
        }
    }

    print_summary(&rows);
    match failed {
        Some((step, what)) => {
            say(&format!("FAILED at step `{}`: {what}", step.name));
            Err(Failure::Exit(1))
        }
        None => {
            say("all steps passed");
            Ok(())
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn strings(args: &[&str]) -> Vec<String> {
        args.iter().map(|s| s.to_string()).collect()
    }

    #[test]
    fn test_flags() {
        assert_eq!(parse_test_args(&[]), Ok(TestOpts::default()));
        assert_eq!(
            parse_test_args(&strings(&["--quick", "--no-setup"])),
            Ok(TestOpts {
                quick: true,
                no_setup: true
            })
        );
        assert!(matches!(
            parse_test_args(&strings(&["--bogus"])),
            Err(Failure::Usage(_))
        ));
    }
}
