//! Which confinement this machine allows, tried once per grading before
//! any student runs: a box ([`crate::jail::available`]), else a network
//! namespace and the fence ([`crate::fence::available`]); control groups
//! where they can be made ([`crate::cgroup`]).

use std::io;
use std::os::unix::process::CommandExt;
use std::process::{Command, Stdio};

use crate::cgroup::ControlGroup;
use crate::child::network_namespaces;
use crate::confinement::{Confinement, Limits, NOBODY};

impl Confinement {
    /// The confinement for this process: a box when one can be had, else
    /// a network namespace when one can be had; `nobody` when root until
    /// [`Confinement::with_user`] gives each student its own uid.
    pub fn new(limits: Limits) -> Confinement {
        let root = crate::effective_uid() == 0;
        let boxed = crate::jail::available(root);
        let (landlock, seccomp) = if boxed {
            (false, false)
        } else {
            crate::fence::available()
        };
        Confinement {
            limits,
            isolate_network: boxed || network_isolation(root),
            user: root.then_some(NOBODY),
            boxed,
            cgroup: (root || boxed) && ControlGroup::available(),
            landlock,
            seccomp,
        }
    }
}

/// Whether a child can be given a network namespace of its own: start one
/// (this program, printing its version) that unshares it.
fn network_isolation(root: bool) -> bool {
    let Ok(exe) = std::env::current_exe() else {
        return false;
    };
    let mut probe = Command::new(exe);
    probe
        .arg("--version")
        .stdin(Stdio::null())
        .stdout(Stdio::null())
        .stderr(Stdio::null());
    let flags = network_namespaces(root);
    // SAFETY: `unshare` is a plain system call.
    unsafe {
        probe.pre_exec(move || {
            if libc::unshare(flags) == -1 {
                Err(io::Error::last_os_error())
            } else {
                Ok(())
            }
        });
    }
    probe.status().is_ok_and(|s| s.success())
}
