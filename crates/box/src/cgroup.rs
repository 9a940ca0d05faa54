//! The control groups a run is held in (cgroup v1 `memory` and `pids`),
//! where this grader can make them.

use std::io;
use std::path::Path;
use std::time::Duration;

use crate::confinement::Limits;

/// The cgroup v1 hierarchies a run is held in, and the file of each that
/// takes its limit.
const CONTROLLERS: [(&str, &str); 2] = [("memory", "memory.limit_in_bytes"), ("pids", "pids.max")];

/// A run's control groups (cgroup v1 `memory` and `pids`), removed when
/// dropped, once the run's processes are gone. A root grader makes them
/// at the top of each hierarchy. An ordinary user's grader makes them in
/// its own group of each hierarchy (`/proc/self/cgroup`) when that group
/// is delegated to it (its folder writable by the grader's uid): then the
/// run's groups are the grader's uid's, which is also the program's, so
/// they are used only in a box, which holds no `/sys` and lets no user
/// namespace be made in it to mount one ([`super::jail`]).
pub struct ControlGroup {
    folders: Vec<std::path::PathBuf>,
}

impl ControlGroup {
    /// Whether this grader can make control groups: cgroup v1's `memory`
    /// and `pids` hierarchies mounted, and writable where
    /// [`ControlGroup::parent`] says.
    pub(crate) fn available() -> bool {
        let limits = Limits {
            timeout: Duration::from_secs(1),
            cpu_seconds: 1,
            address_space: 1 << 30,
            file_size: 1 << 20,
            processes: 8,
            output: 0,
            disk: 0,
        };
        for (controller, _) in CONTROLLERS {
            if let Some(parent) = ControlGroup::parent(controller) {
                ControlGroup::sweep(&parent);
            }
        }
        ControlGroup::new(&limits).is_some()
    }

    /// Remove the groups in `parent` that graders which died left (one
    /// killed with SIGKILL removes nothing): named for a pid no process
    /// has, unchanged for a minute (so never one a grader of another PID
    /// namespace is making), and empty (the kernel removes no group that
    /// holds a process or a group).
    fn sweep(parent: &Path) {
        let Ok(entries) = std::fs::read_dir(parent) else {
            return;
        };
        for entry in entries.flatten() {
            let name = entry.file_name();
            let Some(pid) = name
                .to_str()
                .and_then(|n| n.strip_prefix("raytracer-grade-"))
                .and_then(|rest| rest.split('-').next())
                .and_then(|pid| pid.parse::<libc::pid_t>().ok())
            else {
                continue;
            };
            // SAFETY: `kill` with signal 0 sends nothing.
            let dead = unsafe { libc::kill(pid, 0) } == -1
                && io::Error::last_os_error().raw_os_error() == Some(libc::ESRCH);
            let old = entry
                .metadata()
                .and_then(|m| m.modified())
                .is_ok_and(|t| t.elapsed().is_ok_and(|age| age > Duration::from_secs(60)));
            if dead && old {
                let _ = std::fs::remove_dir(entry.path());
            }
        }
    }

    /// A run's groups with `limits`' memory and processes, or `None`.
    pub(crate) fn new(limits: &Limits) -> Option<ControlGroup> {
        use std::sync::atomic::{AtomicU64, Ordering};
        static RUNS: AtomicU64 = AtomicU64::new(0);
        let name = format!(
            "raytracer-grade-{}-{}",
            std::process::id(),
            RUNS.fetch_add(1, Ordering::Relaxed)
        );
        let mut group = ControlGroup {
            folders: Vec::new(),
        };
        for (controller, file) in CONTROLLERS {
            let folder = ControlGroup::parent(controller)?.join(&name);
            std::fs::create_dir(&folder).ok()?;
            group.folders.push(folder.clone());
            let value = match controller {
                "memory" => limits.address_space,
                _ => limits.processes,
            };
            std::fs::write(folder.join(file), value.to_string()).ok()?;
        }
        Some(group)
    }

    /// The folder a run's group of `controller`'s hierarchy is made in:
    /// the hierarchy's root as root, else this process's own group.
    fn parent(controller: &str) -> Option<std::path::PathBuf> {
        let hierarchy = Path::new("/sys/fs/cgroup").join(controller);
        if crate::effective_uid() == 0 {
            return Some(hierarchy);
        }
        let groups = std::fs::read_to_string("/proc/self/cgroup").ok()?;
        groups.lines().find_map(|line| {
            let mut fields = line.splitn(3, ':');
            let (_, controllers, path) = (fields.next()?, fields.next()?, fields.next()?);
            controllers
                .split(',')
                .any(|c| c == controller)
                .then(|| hierarchy.join(path.trim_start_matches('/')))
        })
    }

    /// The `cgroup.procs` file of each group.
    pub(crate) fn procs(&self) -> Vec<std::ffi::CString> {
        use std::os::unix::ffi::OsStrExt;
        self.folders
            .iter()
            .filter_map(|f| {
                std::ffi::CString::new(f.join("cgroup.procs").as_os_str().as_bytes()).ok()
            })
            .collect()
    }
}

impl Drop for ControlGroup {
    fn drop(&mut self) {
        for folder in &self.folders {
            // A killed process leaves its group a moment after it is reaped.
            for _ in 0..200 {
                if std::fs::remove_dir(folder).is_ok() || !folder.exists() {
                    break;
                }
                std::thread::sleep(Duration::from_millis(5));
            }
        }
    }
}

/// Move this process into the group whose `cgroup.procs` is `path`.
///
/// # Safety
/// Async-signal-safe: called between fork and exec.
pub(crate) fn join_group(path: &std::ffi::CStr) -> io::Result<()> {
    // SAFETY: a NUL-terminated path; plain system calls.
    unsafe {
        let fd = libc::open(path.as_ptr(), libc::O_WRONLY | libc::O_CLOEXEC);
        if fd == -1 {
            return Err(io::Error::last_os_error());
        }
        let written = libc::write(fd, b"0".as_ptr().cast(), 1);
        libc::close(fd);
        if written != 1 {
            return Err(io::Error::last_os_error());
        }
    }
    Ok(())
}
