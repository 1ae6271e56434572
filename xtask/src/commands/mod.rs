//! The small commands, one file each: `run`, `shaders`, `bench` and `soak`. (`test` is
//! [`crate::ci`], `apk`/`install`/`launch` [`crate::apk`], `apk-check` [`crate::apk_check`].)

mod bench;
mod run;
mod shaders;
mod soak;

pub use bench::{cmd_bench, parse_bench_args};
pub use run::cmd_run;
pub use shaders::cmd_shaders;
pub use soak::cmd_soak;
