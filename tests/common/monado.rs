//! Running OpenXR clients against Monado in the Debian trixie root that `cargo xtask` prepares
//! (`xtask/src/monado.rs`; the facts behind the settings are in
//! `docs/notes/monado-headless-ci.md`).
//!
//! Monado as packaged is IPC only: a [`Monado`] runs `monado-service` (null compositor,
//! simulated HMD with simple controllers) in the root with `chroot`, and [`Monado::client`] runs
//! a program next to it in the same root. Each service gets its own runtime directory
//! `/run/xrt-<name>` (as seen inside the root), where its socket and log live, so services with
//! different names do not meet. The tests using this need root and are `#[ignore]`d; the
//! `openxr (Monado)` step of `cargo xtask test` runs them.
//!
//! Every process here runs with a cleared environment plus `PATH` and `HOME=/root`, so nothing
//! from the host (`VK_*`, `XR_*`, `DISPLAY`, ...) leaks into the root.
//!
//! This file is what the tests call: the root, [`Monado`], [`ClientRun`] and the client
//! functions, the validation layer's environment and report. Behind it: `monado/service.rs`
//! ([`Monado`]'s methods: the service started, killed, finished), `monado/root.rs` (commands and
//! files in the root) and `monado/process.rs` (pipes, waits, command lines).

mod process;
mod root;
mod service;

use std::fmt;
use std::fs;
use std::path::{Path, PathBuf};
use std::process::{Child, ExitStatus, Stdio};
use std::sync::Mutex;
use std::time::{Duration, Instant};

use process::{collect, show, tail, wait_timeout};
pub use root::runtime_dir_in_root;
use root::{chroot_command, install_client, prepare_runtime_dir};

/// The environment variable holding the root's path on the host.
pub const ROOT_ENV: &str = "VR_OCEAN_MONADO_ROOT";

/// Monado's runtime manifest inside the root (the loader finds it without this too, through
/// `/etc/xdg/openxr/1/active_runtime.json`; clients get it explicitly).
pub const RUNTIME_JSON: &str = "/usr/share/openxr/1/openxr_monado.json";

/// How long [`Monado::start`] waits for the service's socket.
pub const START_TIMEOUT: Duration = Duration::from_secs(15);

/// How long [`Monado::finish`] waits for the service to exit by itself (it does once its
/// client has disconnected: `IPC_EXIT_ON_DISCONNECT=1`) before it sends SIGTERM.
pub const EXIT_TIMEOUT: Duration = Duration::from_secs(5);

/// The root's path from `VR_OCEAN_MONADO_ROOT`. Panics, saying how to get one, when it is unset
/// or does not hold `monado-service`.
pub fn root_from_env() -> PathBuf {
    let root = match std::env::var_os(ROOT_ENV) {
        Some(v) if !v.is_empty() => PathBuf::from(v),
        _ => panic!(
            "{ROOT_ENV} is not set. The Monado tests run as root in a Debian trixie chroot and \
             are run by the `openxr (Monado)` step of `cargo xtask test`. By hand:\n  export \
             {ROOT_ENV}=$(cargo xtask monado-root)\n  cargo test --test openxr_monado -- \
             --ignored --nocapture --test-threads=1"
        ),
    };
    assert!(
        root.join("usr/bin/monado-service").is_file(),
        "{ROOT_ENV}={} holds no usr/bin/monado-service; `cargo xtask monado-root` makes the root",
        root.display()
    );
    root
}

/// A running `monado-service`; dropping it kills the service if it still runs. It is `Sync`:
/// a test can run a client on one thread and [`Monado::kill_service`] on another.
pub struct Monado {
    root: PathBuf,
    name: String,
    /// `<root>/run/xrt-<name>` on the host.
    runtime_dir: PathBuf,
    log_path: PathBuf,
    /// `None` once the service has been waited for.
    child: Mutex<Option<Child>>,
    /// Set when [`Monado::kill_service`] reaped it.
    killed: Mutex<Option<ExitStatus>>,
    startup: Duration,
}

/// How the service ended, from [`Monado::finish`].
#[derive(Debug)]
pub struct ServiceExit {
    /// Exit code; `None` when a signal ended it.
    pub status: Option<i32>,
    /// `None` when it exited by itself; otherwise the signal that had to end it (`"SIGTERM"`,
    /// `"SIGKILL"`), also after [`Monado::kill_service`].
    pub stopped_by: Option<&'static str>,
    /// The service's whole log (stdout and stderr).
    pub log: String,
}

/// The result of a client run ([`Monado::client`], [`client_without_service`]). Its `Display`
/// shows the outcome and the ends of both outputs, for assertion messages.
#[derive(Debug)]
pub struct ClientRun {
    /// Exit code; `None` when a signal ended it (also after a timeout).
    pub status: Option<i32>,
    /// The client ran into the timeout and was killed.
    pub timed_out: bool,
    /// Everything it wrote to stdout.
    pub stdout: String,
    /// Everything it wrote to stderr.
    pub stderr: String,
    /// Wall-clock seconds from start to exit.
    pub seconds: f64,
}

impl ClientRun {
    /// Exited with status 0 within the timeout.
    pub fn success(&self) -> bool {
        self.status == Some(0) && !self.timed_out
    }
}

impl fmt::Display for ClientRun {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        writeln!(
            f,
            "client status {:?}{} after {:.1} s",
            self.status,
            if self.timed_out {
                " (timed out, killed)"
            } else {
                ""
            },
            self.seconds
        )?;
        writeln!(f, "--- stdout (end) ---\n{}", tail(&self.stdout, 60))?;
        write!(f, "--- stderr (end) ---\n{}", tail(&self.stderr, 60))
    }
}

/// Like [`Monado::client`], but with no service: `XDG_RUNTIME_DIR` is `/run/xrt-<name>` with no
/// socket in it (a stale one is deleted, so use a `name` that no running service uses). For
/// tests of the "runtime not running" path (`xrCreateInstance` fails with
/// `XR_ERROR_RUNTIME_FAILURE`).
pub fn client_without_service(
    root: &Path,
    name: &str,
    exe: &Path,
    args: &[&str],
    env: &[(&str, &str)],
    timeout: Duration,
) -> ClientRun {
    prepare_runtime_dir(root, name);
    run_client(root, name, exe, args, env, timeout)
}

/// Environment that turns on the OpenXR core validation layer for a client, writing text to
/// `/tmp/xrval-<name>.txt` in the root (read it with [`xr_validation_errors`]). Pass it with
/// [`env_refs`].
pub fn xr_validation_env(name: &str) -> Vec<(String, String)> {
    vec![
        (
            "XR_ENABLE_API_LAYERS".into(),
            "XR_APILAYER_LUNARG_core_validation".into(),
        ),
        ("XR_CORE_VALIDATION_EXPORT_TYPE".into(), "text".into()),
        (
            "XR_CORE_VALIDATION_FILE_NAME".into(),
            format!("/tmp/xrval-{name}.txt"),
        ),
    ]
}

/// Borrows owned `(name, value)` pairs as the `env` argument of the client functions.
pub fn env_refs(env: &[(String, String)]) -> Vec<(&str, &str)> {
    env.iter().map(|(k, v)| (k.as_str(), v.as_str())).collect()
}

/// The problems the core validation layer reported for the client run with
/// [`xr_validation_env`]`(name)`: every message whose severity is not `VALID_DEBUG` or
/// `VALID_INFO` (so errors and warnings), each with its indented detail lines, and any line not
/// in the layer's format. A clean run writes only two lines, like
/// `[2026-11-22 11:04:36][VALID_DEBUG | VUID-CoreValidation-Initialize | xrCreateApiLayerInstance] : ...`
/// and the same with `VUID-CoreValidation-Destroy`. Panics when the file is missing: then the
/// layer never ran (not enabled, or no instance was created).
pub fn xr_validation_errors(root: &Path, name: &str) -> Vec<String> {
    let path = root.join(format!("tmp/xrval-{name}.txt"));
    let text = fs::read_to_string(&path).unwrap_or_else(|e| {
        panic!(
            "no core validation output {} ({e}): was the layer enabled (xr_validation_env) and \
             did the client create an instance?",
            path.display()
        )
    });
    validation_problems(&text)
}

/// Groups the layer's text output into messages (a `[time][VALID_<SEVERITY> | id | command] :
/// text` line and the indented lines after it) and keeps those that are not debug or info.
fn validation_problems(text: &str) -> Vec<String> {
    let mut messages: Vec<String> = Vec::new();
    for line in text.lines() {
        if line.starts_with(char::is_whitespace) && !messages.is_empty() {
            let last = messages.last_mut().expect("not empty");
            last.push('\n');
            last.push_str(line);
        } else if !line.trim().is_empty() {
            messages.push(line.to_owned());
        }
    }
    messages.retain(|m| {
        let severity = m.split_once("[VALID_").map(|(_, rest)| {
            rest.split(|c: char| !c.is_ascii_alphabetic())
                .next()
                .unwrap_or_default()
        });
        !matches!(severity, Some("DEBUG" | "INFO"))
    });
    messages
}

/// [`Monado::client`] by the service's name, without holding the service (a client that
/// outlives the service it started with: the soak's, across a killed and restarted runtime).
#[allow(dead_code)]
pub fn run_client(
    root: &Path,
    name: &str,
    exe: &Path,
    args: &[&str],
    env: &[(&str, &str)],
    timeout: Duration,
) -> ClientRun {
    let inside = install_client(root, exe);
    let xdg = runtime_dir_in_root(name);
    // Each client starts from the default settings and keeps its own (in the root's /tmp).
    let config = format!("/tmp/vr-ocean-config-{name}-{}", std::process::id());
    let mut vars: Vec<(&str, &str)> = vec![
        ("XDG_RUNTIME_DIR", xdg.as_str()),
        ("XDG_CONFIG_HOME", config.as_str()),
        ("XR_RUNTIME_JSON", RUNTIME_JSON),
        ("RUST_LOG", "info"),
    ];
    vars.retain(|(k, _)| !env.iter().any(|(e, _)| e == k));
    vars.extend_from_slice(env);
    if let Some((_, file)) = vars
        .iter()
        .find(|(k, _)| *k == "XR_CORE_VALIDATION_FILE_NAME")
    {
        let stale = root.join(file.trim_start_matches('/'));
        let _ = fs::remove_file(stale);
    }

    let mut cmd = chroot_command(root);
    cmd.envs(vars.iter().copied())
        .arg(&inside)
        .args(args)
        .stdin(Stdio::null())
        .stdout(Stdio::piped())
        .stderr(Stdio::piped());
    eprintln!("monado: client: {}", show(&cmd));
    let start = Instant::now();
    let mut child = cmd
        .spawn()
        .unwrap_or_else(|e| panic!("cannot start `{}`: {e}", show(&cmd)));
    // Readers on threads, so that neither pipe fills up; they append as they read, so a
    // grandchild that keeps a pipe open cannot hold the result back.
    let out = collect(child.stdout.take().expect("piped stdout"));
    let err = collect(child.stderr.take().expect("piped stderr"));
    let (status, timed_out) = match wait_timeout(&mut child, timeout) {
        Some(status) => (status, false),
        None => {
            let _ = child.kill();
            (child.wait().expect("wait on the client"), true)
        }
    };
    let seconds = start.elapsed().as_secs_f64();
    let stdout = out.finish();
    let stderr = err.finish();
    eprintln!(
        "monado: client ended: {status}{} after {seconds:.2} s",
        if timed_out {
            " (timed out, killed)"
        } else {
            ""
        }
    );
    ClientRun {
        status: status.code(),
        timed_out,
        stdout,
        stderr,
        seconds,
    }
}
