//! [`Monado`]'s methods: `monado-service` started in the root and waited for, a client run next
//! to it, the service killed as a crash would, or finished with how it ended.

use std::fs::{self, File};
use std::os::unix::fs::FileTypeExt;
use std::path::Path;
use std::process::{Child, Command, Stdio};
use std::sync::Mutex;
use std::thread;
use std::time::{Duration, Instant};

use super::process::{show, tail, wait_timeout};
use super::root::{chroot_command, prepare_runtime_dir, SOCKET};
use super::{
    run_client, runtime_dir_in_root, ClientRun, Monado, ServiceExit, EXIT_TIMEOUT, START_TIMEOUT,
};

/// The service's log (stdout and stderr) in its runtime directory.
const SERVICE_LOG: &str = "monado-service.log";

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

fn is_socket(path: &Path) -> bool {
    fs::symlink_metadata(path).is_ok_and(|m| m.file_type().is_socket())
}
