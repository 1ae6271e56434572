//! Physics step cost for 64 floating bodies (filled in with `src/physics`).

fn main() {}
