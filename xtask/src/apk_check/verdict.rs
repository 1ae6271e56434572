//! apk-check's verdict: the expectations that passed and those that failed.

use crate::process::say;

/// Collects failed expectations; the step fails if any.
#[derive(Default)]
pub struct Verdict {
    /// What failed (the step fails if anything is here).
    pub problems: Vec<String>,
    /// How many expectations passed.
    pub passed: usize,
}

impl Verdict {
    /// Notes one expectation: passed when `ok`.
    pub fn expect(&mut self, ok: bool, what: &str) {
        if ok {
            self.passed += 1;
            say(&format!("ok: {what}"));
        } else {
            say(&format!("FAILED: {what}"));
            self.problems.push(what.to_string());
        }
    }

    /// Notes a check that passes when it found no `problems` (each is reported).
    pub fn all(&mut self, what: &str, problems: Vec<String>) {
        let ok = problems.is_empty();
        for p in problems {
            say(&format!("  problem: {p}"));
            self.problems.push(format!("{what}: {p}"));
        }
        if ok {
            self.passed += 1;
            say(&format!("ok: {what}"));
        }
    }
}
