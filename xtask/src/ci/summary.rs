//! The table `cargo xtask test` prints at the end: each step's result and time.

use std::time::Duration;

use crate::process::banner;

/// How a step (or the set-up) ended.
pub enum Outcome {
    /// Passed, in this time.
    Ok(Duration),
    /// Failed after this time.
    Failed(Duration),
    /// Not run, for this reason (a flag).
    Skipped(&'static str),
    /// Not run because an earlier step failed.
    NotRun,
}

/// Prints the summary table of `(step name, outcome)` rows, with the total time.
pub fn print_summary(rows: &[(String, Outcome)]) {
    let width = rows.iter().map(|(n, _)| n.len()).max().unwrap_or(4).max(4);
    let total: Duration = rows
        .iter()
        .map(|(_, o)| match o {
            Outcome::Ok(d) | Outcome::Failed(d) => *d,
            _ => Duration::ZERO,
        })
        .sum();
    banner("summary");
    println!("  {:<width$}  {:<18}  {:>9}", "step", "result", "time");
    for (name, outcome) in rows {
        let (result, time) = match outcome {
            Outcome::Ok(d) => ("ok".to_string(), fmt_duration(*d)),
            Outcome::Failed(d) => ("FAILED".to_string(), fmt_duration(*d)),
            Outcome::Skipped(why) => (format!("skipped ({why})"), "-".into()),
            Outcome::NotRun => ("not run".to_string(), "-".into()),
        };
        println!("  {name:<width$}  {result:<18}  {time:>9}");
    }
    println!(
        "  {:<width$}  {:<18}  {:>9}",
        "total",
        "",
        fmt_duration(total)
    );
}

/// `12.3s` under a minute, `4m05s` from there.
fn fmt_duration(d: Duration) -> String {
    let secs = d.as_secs_f64();
    if secs < 60.0 {
        format!("{secs:.1}s")
    } else {
        format!("{}m{:02}s", d.as_secs() / 60, d.as_secs() % 60)
    }
}
