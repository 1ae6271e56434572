//! The command lines of `apk`, `install` and `launch`.

use std::path::PathBuf;

use crate::{Failure, Result};

/// Options of `cargo xtask apk`.
#[derive(Debug, Default, PartialEq)]
pub struct ApkOpts {
    /// Release profile.
    pub release: bool,
    /// The NDK-less verification build (CI).
    pub verify_without_ndk: bool,
    /// The loader AAR or .so.
    pub openxr_loader: Option<PathBuf>,
}

/// Parses `apk` options.
pub fn parse_apk_args(args: &[String]) -> Result<ApkOpts> {
    let mut opts = ApkOpts::default();
    let mut iter = args.iter();
    while let Some(arg) = iter.next() {
        match arg.as_str() {
            "--release" => opts.release = true,
            "--verify-without-ndk" => opts.verify_without_ndk = true,
            "--openxr-loader" => match iter.next() {
                Some(p) if !p.starts_with("--") => opts.openxr_loader = Some(PathBuf::from(p)),
                _ => return Err(Failure::Usage("--openxr-loader needs a PATH".into())),
            },
            other => {
                if let Some(p) = other.strip_prefix("--openxr-loader=") {
                    opts.openxr_loader = Some(PathBuf::from(p));
                } else {
                    return Err(Failure::Usage(format!("apk: unknown option `{other}`")));
                }
            }
        }
    }
    Ok(opts)
}

/// Parses `install`/`launch` options (`--release` only).
pub fn parse_release_flag(cmd: &str, args: &[String]) -> Result<bool> {
    let mut release = false;
    for arg in args {
        match arg.as_str() {
            "--release" => release = true,
            other => return Err(Failure::Usage(format!("{cmd}: unknown option `{other}`"))),
        }
    }
    Ok(release)
}

#[cfg(test)]
mod tests {
    use super::*;

    fn strings(args: &[&str]) -> Vec<String> {
        args.iter().map(|s| s.to_string()).collect()
    }

    #[test]
    fn apk_flags() {
        assert_eq!(parse_apk_args(&[]), Ok(ApkOpts::default()));
        assert_eq!(
            parse_apk_args(&strings(&[
                "--release",
                "--verify-without-ndk",
                "--openxr-loader",
                "x.aar"
            ])),
            Ok(ApkOpts {
                release: true,
                verify_without_ndk: true,
                openxr_loader: Some("x.aar".into())
            })
        );
        assert_eq!(
            parse_apk_args(&strings(&["--openxr-loader=y.so"]))
                .unwrap()
                .openxr_loader,
            Some(PathBuf::from("y.so"))
        );
        for bad in [
            &["--openxr-loader"][..],
            &["--openxr-loader", "--release"],
            &["--x"],
        ] {
            assert!(matches!(
                parse_apk_args(&strings(bad)),
                Err(Failure::Usage(_))
            ));
        }
        assert_eq!(
            parse_release_flag("install", &strings(&["--release"])),
            Ok(true)
        );
        assert!(parse_release_flag("launch", &strings(&["-x"])).is_err());
    }
}
