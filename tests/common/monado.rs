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

use std::fmt;
use std::fs::{self, File};
use std::io::Read;
use std::os::unix::fs::{FileTypeExt, PermissionsExt};
use std::path::{Path, PathBuf};
use std::process::{Child, Command, ExitStatus, Stdio};
use std::sync::atomic::{AtomicUsize, Ordering};
use std::sync::{Arc, Mutex};
use std::thread;
use std::time::{Duration, Instant};

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

/// The service's socket in its runtime directory.
const SOCKET: &str = "monado_comp_ipc";

/// The service's log (stdout and stderr) in its runtime directory.
const SERVICE_LOG: &str = "monado-service.log";

/// `PATH` inside the root (also used to find `chroot` on the host).
const PATH: &str = "/usr/local/sbin:/usr/local/bin:/usr/sbin:/usr/bin:/sbin:/bin";

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

/// The runtime directory of the service called `name`, as seen inside the root.
pub fn runtime_dir_in_root(name: &str) -> String {
    format!("/run/xrt-{name}")
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

impl Monado {
    /// Starts `monado-service` in `root` with the null compositor, a simulated HMD and simple
    /// controllers on both hands, runtime directory `/run/xrt-<name>` (mode 700) and
    /// `IPC_EXIT_ON_DISCONNECT=1`, and waits up to [`START_TIMEOUT`] for its socket. `name`
    /// (letters, digits, `-`, `_`; at most 40) keeps services and their files apart. Panics with
    /// the end of the service's log when it exits or times out.
    pub fn start(root: &Path, name: &str) -> Monado {
        Self::start_with(root, name, true)
    }

    /// [`Monado::start`], with `IPC_EXIT_ON_DISCONNECT` only when `exit_on_disconnect` (a
    /// service for two clients must outlive the first to leave; [`Monado::finish`] then stops
    /// it with SIGTERM).
    pub fn start_with(root: &Path, name: &str, exit_on_disconnect: bool) -> Monado {
        let runtime_dir = prepare_runtime_dir(root, name);
        let log_path = runtime_dir.join(SERVICE_LOG);
        let log = File::create(&log_path)
            .unwrap_or_else(|e| panic!("cannot create {}: {e}", log_path.display()));
        let log_err = log.try_clone().expect("the log file can be reopened");
        let mut cmd = chroot_command(root);
        cmd.envs([
            ("XRT_COMPOSITOR_NULL", "1"),
            ("SIMULATED_ENABLE", "1"),
            ("SIMULATED_LEFT", "simple"),
            ("SIMULATED_RIGHT", "simple"),
            ("XRT_NO_STDIN", "1"),
        ])
        .envs(exit_on_disconnect.then_some(("IPC_EXIT_ON_DISCONNECT", "1")))
        .env("XDG_RUNTIME_DIR", runtime_dir_in_root(name))
        .arg("monado-service")
        .stdin(Stdio::null())
        .stdout(log)
        .stderr(log_err);
        eprintln!("monado: starting: {}", show(&cmd));
        let start = Instant::now();
        let child = cmd
            .spawn()
            .unwrap_or_else(|e| panic!("cannot start `{}`: {e}", show(&cmd)));
        let mut service = Monado {
            root: root.to_path_buf(),
            name: name.to_owned(),
            runtime_dir,
            log_path,
            child: Mutex::new(Some(child)),
            killed: Mutex::new(None),
            startup: Duration::ZERO,
        };
        let socket = service.runtime_dir.join(SOCKET);
        loop {
            if is_socket(&socket) {
                break;
            }
            let mut slot = service.child.lock().expect("child lock");
            let child = slot.as_mut().expect("running");
            if let Some(status) = child.try_wait().expect("try_wait on monado-service") {
                *slot = None;
                drop(slot);
                panic!(
                    "monado-service `{name}` exited before its socket appeared ({status}); the \
                     end of {}:\n{}",
                    service.log_path.display(),
                    tail(&service.log(), 40)
                );
            }
            if start.elapsed() > START_TIMEOUT {
                let _ = child.kill();
                let _ = child.wait();
                *slot = None;
                drop(slot);
                panic!(
                    "monado-service `{name}`: no socket {} after {START_TIMEOUT:?}; the end of \
                     {}:\n{}",
                    socket.display(),
                    service.log_path.display(),
                    tail(&service.log(), 40)
                );
            }
            drop(slot);
            thread::sleep(Duration::from_millis(20));
        }
        service.startup = start.elapsed();
        eprintln!(
            "monado: service `{name}` up in {:.2} s (log: {})",
            service.startup.as_secs_f64(),
            service.log_path.display()
        );
        service
    }

    /// Seconds from spawning the service to its socket appearing.
    pub fn startup_seconds(&self) -> f64 {
        self.startup.as_secs_f64()
    }

    /// The service's log file on the host.
    pub fn log_path(&self) -> &Path {
        &self.log_path
    }

    /// The service's log so far.
    pub fn log(&self) -> String {
        fs::read_to_string(&self.log_path).unwrap_or_default()
    }

    /// The service's process id (of `monado-service` itself: `chroot` execs it), while it runs.
    pub fn pid(&self) -> Option<u32> {
        self.child
            .lock()
            .expect("child lock")
            .as_ref()
            .map(Child::id)
    }

    /// Runs `exe` (a host path; copied to `<root>/xr/`) with `args` in the root, connected to
    /// this service. The environment is `XDG_RUNTIME_DIR`, `XDG_CONFIG_HOME` (a fresh one: the
    /// default settings), `XR_RUNTIME_JSON`, `RUST_LOG=info` (each unless `env` sets it) and
    /// `env`. stdout and stderr are collected; the client is
    /// killed after `timeout`. When `env` names an `XR_CORE_VALIDATION_FILE_NAME`, a stale file
    /// of that name is deleted first (the layer appends).
    pub fn client(
        &self,
        exe: &Path,
        args: &[&str],
        env: &[(&str, &str)],
        timeout: Duration,
    ) -> ClientRun {
        run_client(&self.root, &self.name, exe, args, env, timeout)
    }

    /// Kills the service with SIGKILL now (and reaps it), as a crash would: its clients see
    /// `XR_ERROR_INSTANCE_LOST`. Takes `&self` so that it can be called while a client runs on
    /// another thread. [`Monado::finish`] then reports `stopped_by: Some("SIGKILL")`.
    pub fn kill_service(&self) {
        if let Some(mut child) = self.child.lock().expect("child lock").take() {
            let _ = child.kill();
            let status = child.wait().expect("wait on monado-service");
            *self.killed.lock().expect("killed lock") = Some(status);
            eprintln!("monado: service `{}` killed (SIGKILL)", self.name);
        }
    }

    /// Waits up to [`EXIT_TIMEOUT`] for the service to exit by itself (it does after its client
    /// disconnected), then sends SIGTERM and waits as long again, then SIGKILL. Returns how it
    /// ended and its log.
    pub fn finish(self) -> ServiceExit {
        let child = self.child.lock().expect("child lock").take();
        let (status, stopped_by) = match child {
            None => {
                let killed = *self.killed.lock().expect("killed lock");
                (killed.expect("killed or running"), Some("SIGKILL"))
            }
            Some(mut child) => {
                if let Some(status) = wait_timeout(&mut child, EXIT_TIMEOUT) {
                    (status, None)
                } else {
                    let _ = Command::new("kill")
                        .args(["-TERM", &child.id().to_string()])
                        .status();
                    if let Some(status) = wait_timeout(&mut child, EXIT_TIMEOUT) {
                        (status, Some("SIGTERM"))
                    } else {
                        let _ = child.kill();
                        (
                            child.wait().expect("wait on monado-service"),
                            Some("SIGKILL"),
                        )
                    }
                }
            }
        };
        eprintln!(
            "monado: service `{}` ended: {status}{}",
            self.name,
            stopped_by.map_or(String::new(), |s| format!(" (after {s})"))
        );
        ServiceExit {
            status: status.code(),
            stopped_by,
            log: self.log(),
        }
    }
}

impl Drop for Monado {
    fn drop(&mut self) {
        let child = match self.child.get_mut() {
            Ok(slot) => slot.take(),
            Err(poisoned) => poisoned.into_inner().take(),
        };
        if let Some(mut child) = child {
            let _ = child.kill();
            let _ = child.wait();
            eprintln!("monado: service `{}` killed on drop", self.name);
        }
        if thread::panicking() {
            eprintln!(
                "monado: the end of {}:\n{}",
                self.log_path.display(),
                tail(&self.log(), 40)
            );
        }
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

// ---------------------------------------------------------------------------------------------

/// `chroot <root>` with a cleared environment plus `PATH` and `HOME`.
fn chroot_command(root: &Path) -> Command {
    let mut cmd = Command::new("chroot");
    cmd.env_clear()
        .env("PATH", PATH)
        .env("HOME", "/root")
        .arg(root);
    cmd
}

/// Creates `<root>/run/xrt-<name>` (mode 700) and deletes a stale socket in it; returns it.
fn prepare_runtime_dir(root: &Path, name: &str) -> PathBuf {
    assert!(
        !name.is_empty()
            && name.len() <= 40
            && name
                .chars()
                .all(|c| c.is_ascii_alphanumeric() || c == '-' || c == '_'),
        "service name {name:?}: use 1 to 40 letters, digits, `-` or `_` (it is part of the \
         socket path, which must fit in 108 bytes)"
    );
    let dir = root.join(runtime_dir_in_root(name).trim_start_matches('/'));
    fs::create_dir_all(&dir).unwrap_or_else(|e| panic!("cannot create {}: {e}", dir.display()));
    fs::set_permissions(&dir, fs::Permissions::from_mode(0o700))
        .unwrap_or_else(|e| panic!("cannot chmod {}: {e}", dir.display()));
    let socket = dir.join(SOCKET);
    if fs::symlink_metadata(&socket).is_ok() {
        fs::remove_file(&socket)
            .unwrap_or_else(|e| panic!("cannot remove {}: {e}", socket.display()));
    }
    dir
}

fn is_socket(path: &Path) -> bool {
    fs::symlink_metadata(path).is_ok_and(|m| m.file_type().is_socket())
}

/// Copies `exe` to `<root>/xr/<file name>` (through a temporary name and a rename, so a copy
/// still running elsewhere keeps its file); returns its path inside the root.
fn install_client(root: &Path, exe: &Path) -> String {
    let file = exe
        .file_name()
        .unwrap_or_else(|| panic!("{} has no file name", exe.display()))
        .to_string_lossy()
        .into_owned();
    let dir = root.join("xr");
    fs::create_dir_all(&dir).unwrap_or_else(|e| panic!("cannot create {}: {e}", dir.display()));
    // Unique per call: clients may be installed from several threads at once.
    static COPIES: AtomicUsize = AtomicUsize::new(0);
    let copy = COPIES.fetch_add(1, Ordering::Relaxed);
    let tmp = dir.join(format!(".{file}.{}.{copy}", std::process::id()));
    fs::copy(exe, &tmp)
        .unwrap_or_else(|e| panic!("cannot copy {} to {}: {e}", exe.display(), tmp.display()));
    fs::rename(&tmp, dir.join(&file)).expect("rename the client into place");
    format!("/xr/{file}")
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

/// A pipe being read into memory on a thread.
struct Collector {
    buf: Arc<Mutex<Vec<u8>>>,
    thread: thread::JoinHandle<()>,
}

fn collect(mut pipe: impl Read + Send + 'static) -> Collector {
    let buf = Arc::new(Mutex::new(Vec::new()));
    let sink = Arc::clone(&buf);
    let thread = thread::spawn(move || {
        let mut chunk = [0u8; 8192];
        while let Ok(n) = pipe.read(&mut chunk) {
            if n == 0 {
                break;
            }
            sink.lock()
                .expect("collector lock")
                .extend_from_slice(&chunk[..n]);
        }
    });
    Collector { buf, thread }
}

impl Collector {
    /// What was read, once the pipe closed or at most 2 s after the process exited.
    fn finish(self) -> String {
        let deadline = Instant::now() + Duration::from_secs(2);
        while !self.thread.is_finished() && Instant::now() < deadline {
            thread::sleep(Duration::from_millis(10));
        }
        let bytes = self.buf.lock().expect("collector lock").clone();
        String::from_utf8_lossy(&bytes).into_owned()
    }
}

/// Waits for `child` up to `timeout`; `None` when it still runs.
fn wait_timeout(child: &mut Child, timeout: Duration) -> Option<ExitStatus> {
    let deadline = Instant::now() + timeout;
    loop {
        if let Some(status) = child.try_wait().expect("try_wait") {
            return Some(status);
        }
        if Instant::now() >= deadline {
            return None;
        }
        thread::sleep(Duration::from_millis(10));
    }
}

/// The command line with its environment, as `env -i K=V ... cmd args` (to rerun by hand).
fn show(cmd: &Command) -> String {
    let mut parts = vec!["env -i".to_owned()];
    for (k, v) in cmd.get_envs() {
        if let Some(v) = v {
            parts.push(format!("{}={}", k.to_string_lossy(), v.to_string_lossy()));
        }
    }
    parts.push(cmd.get_program().to_string_lossy().into_owned());
    parts.extend(cmd.get_args().map(|a| a.to_string_lossy().into_owned()));
    parts.join(" ")
}

fn tail(text: &str, lines: usize) -> String {
    let all: Vec<&str> = text.lines().collect();
    all[all.len().saturating_sub(lines)..].join("\n")
}
