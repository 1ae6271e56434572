//! `cargo xtask soak [MINUTES]`: the soak test on Monado (as root).

use crate::process::{cargo, run_checked, workspace_root};
use crate::{monado, Failure, Result};

/// `cargo xtask soak [MINUTES]`: the soak test on Monado for MINUTES (default 20).
pub fn cmd_soak(rest: &[String]) -> Result<()> {
    let minutes = match rest {
        [] => 20.0,
        [m] => match m.parse::<f64>() {
            Ok(v) if v > 0.0 && v <= 24.0 * 60.0 => v,
            _ => {
                return Err(Failure::Usage(format!(
                    "soak: {m:?} is not a number of minutes in (0, 1440]"
                )))
            }
        },
        _ => {
            return Err(Failure::Usage(
                "soak takes at most one argument, MINUTES".into(),
            ))
        }
    };
    let env = monado::prepare_step()?;
    let mut cmd = cargo();
    cmd.args(["test", "--test", "soak", "--", "--ignored", "--nocapture"])
        .envs(env)
        .env("VR_OCEAN_SOAK_MINUTES", minutes.to_string())
        .current_dir(workspace_root());
    run_checked(&mut cmd)
}
