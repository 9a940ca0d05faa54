//! A command run as in a container that refuses namespaces (Docker's
//! default seccomp profile, Gradescope's containers): how the tests make
//! `grade` find no box and grade `--unprotected`.

use std::process::Command;

use seccompiler::{
    SeccompAction, SeccompCmpArgLen, SeccompCmpOp, SeccompCondition, SeccompFilter, SeccompRule,
};

/// Run `command` under a seccomp filter that fails `unshare` and `clone`
/// with any `CLONE_NEW*` flag, and `setns`, with `EPERM` (and `clone3`,
/// whose flags a filter cannot read, with `ENOSYS`, so the C library
/// falls back to `clone`).
pub fn without_namespaces(command: &mut Command) -> &mut Command {
    use std::os::unix::process::CommandExt;
    let arch = std::env::consts::ARCH.try_into().unwrap();
    let compile = |rules, action| -> seccompiler::BpfProgram {
        SeccompFilter::new(rules, SeccompAction::Allow, action, arch)
            .unwrap()
            .try_into()
            .unwrap()
    };
    let flags = [
        libc::CLONE_NEWNS,
        libc::CLONE_NEWUSER,
        libc::CLONE_NEWPID,
        libc::CLONE_NEWNET,
        libc::CLONE_NEWIPC,
        libc::CLONE_NEWUTS,
        libc::CLONE_NEWCGROUP,
    ];
    let any_new = || -> Vec<SeccompRule> {
        flags
            .iter()
            .map(|&flag| {
                let condition = SeccompCondition::new(
                    0,
                    SeccompCmpArgLen::Qword,
                    SeccompCmpOp::MaskedEq(flag as u64),
                    flag as u64,
                )
                .unwrap();
                SeccompRule::new(vec![condition]).unwrap()
            })
            .collect()
    };
    let filters = [
        compile(
            [(libc::SYS_clone3, vec![])].into_iter().collect(),
            SeccompAction::Errno(libc::ENOSYS as u32),
        ),
        compile(
            [
                (libc::SYS_unshare, any_new()),
                (libc::SYS_clone, any_new()),
                (libc::SYS_setns, vec![]),
            ]
            .into_iter()
            .collect(),
            SeccompAction::Errno(libc::EPERM as u32),
        ),
    ];
    // SAFETY: installing a filter compiled before the fork is two system calls.
    unsafe {
        command.pre_exec(move || {
            for filter in &filters {
                seccompiler::apply_filter(filter)
                    .map_err(|_| std::io::Error::from_raw_os_error(libc::EPERM))?;
            }
            Ok(())
        });
    }
    command
}
