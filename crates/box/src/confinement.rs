//! What confines a run: its limits, what of the grader's file system a
//! box shares with it, and the mechanisms decided once per grading
//! ([`Confinement`]; [`crate::probe`] finds which this machine allows).

use std::path::PathBuf;
use std::time::Duration;

/// The limits one run is held to.
#[derive(Clone, Copy, Debug)]
pub struct Limits {
    pub timeout: Duration,
    pub cpu_seconds: u64,
    pub address_space: u64,
    pub file_size: u64,
    pub processes: u64,
    /// Bytes of stdout, and of stderr, kept.
    pub output: usize,
    /// Bytes of the tmpfs a box gives a run as its working folder
    /// ([`Share::scratch`]).
    pub disk: u64,
}

/// The uid and gid a root grader runs programs as.
pub const NOBODY: u32 = 65_534;

/// What of the grader's file system a box holds: folders bound
/// read-write (a build's folder) and files bound read-only (a `--tracer`
/// program named by its path), each at its own path; the run's
/// working folder, which a box gives as a tmpfs ([`Scratch`]); and the
/// folder given as `HOME`.
#[derive(Clone, Debug, Default)]
pub struct Share {
    pub read_write: Vec<PathBuf>,
    pub read_only: Vec<PathBuf>,
    /// One of `read_write` that a box gives as a tmpfs of its own
    /// (`crate::scratch`); without a box it is shared as the others.
    pub scratch: Option<Scratch>,
    /// One of `read_write` given as `HOME`; the working folder when none.
    pub home: Option<PathBuf>,
}

/// A working folder a box gives the run as a tmpfs of [`Limits::disk`]
/// bytes and a bounded number of inodes, filled from `folder`; of what
/// the program leaves there only `keep` (a path relative to `folder`:
/// its image) comes back into `folder`.
#[derive(Clone, Debug)]
pub struct Scratch {
    pub folder: PathBuf,
    pub keep: PathBuf,
}

/// How the child is confined, decided once per grading.
#[derive(Clone, Copy, Debug)]
pub struct Confinement {
    pub limits: Limits,
    /// Unshare the network namespace (the kernel allows it).
    pub isolate_network: bool,
    /// Switch to this uid and gid (the grader is root).
    pub user: Option<u32>,
    /// Run in a box ([`super::jail`]): PID, mount, IPC, UTS and network
    /// namespaces and a root of our making; inside a user namespace of
    /// its own when the grader is not root.
    pub boxed: bool,
    /// Hold each run in control groups of its own (cgroup v1 `memory` and
    /// `pids`; as root, or in a box under a delegated group,
    /// [`crate::cgroup::ControlGroup`]): `--memory` for the whole run, `--max-processes`
    /// for the run's processes alone.
    pub cgroup: bool,
    /// Without a box: Landlock ([`super::fence`]) where the kernel has it.
    pub landlock: bool,
    /// Without a box: the seccomp filter ([`super::fence`]).
    pub seccomp: bool,
}

impl Confinement {
    /// The confinement of one tracer graded: the uid of `lease` (root's
    /// grader leases one per student, [`crate::uids::Lease`]).
    pub fn with_user(self, lease: Option<&crate::uids::Lease>) -> Confinement {
        Confinement {
            user: lease.map(crate::uids::Lease::uid).or(self.user),
            ..self
        }
    }

    /// The names of the mechanisms that confine each run.
    pub fn mechanisms(&self) -> Vec<String> {
        let mut names = Vec::new();
        if self.boxed {
            names.extend(["pid_namespace", "mount_namespace", "ipc_namespace"]);
            if !self.root() {
                names.push("user_namespace");
            }
        }
        if self.isolate_network {
            names.push("network_namespace");
        }
        if self.root() {
            names.push("uid");
        }
        if self.cgroup {
            names.push("cgroup");
        }
        if self.landlock {
            names.push("landlock");
        }
        if self.seccomp {
            names.push("seccomp");
        }
        names.extend(["rlimits", "no_new_privs"]);
        names.into_iter().map(String::from).collect()
    }

    /// Whether the grader runs as root (and so switches uids).
    pub fn root(&self) -> bool {
        self.user.is_some()
    }
}
