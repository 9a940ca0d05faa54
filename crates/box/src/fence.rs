//! The fence around a program run without a box (`--unprotected`, where
//! the kernel or container refuses namespaces): Landlock and a seccomp
//! filter, both of which an unprivileged process may install on itself.
//!
//! Landlock ([`Fence::new`], prepared before the fork): the program may
//! read and run what lies under the system folders the box would bind
//! (`/usr`, `/bin`, `/sbin`, `/lib*`, `/etc`), read `/proc`, use the
//! devices the box has, read and write its working folder, and read and
//! run the files its command names; everything else of the file system
//! (the grader's files, the reference cache, the reports, home folders,
//! `/tmp`) is refused, whatever its mode. TCP `connect` and `bind` are
//! refused, as are an abstract UNIX socket and a signal to any process
//! outside the program's own (Landlock's scopes): the grader cannot be
//! stopped or killed. The whole ruleset is a hard requirement: a kernel
//! without Landlock ABI 6 gets no Landlock at all, and the report says
//! so. The seccomp filter refuses `socket` (any family, so no UNIX socket
//! file either, which Landlock does not govern), `io_uring_setup`
//! (which could open sockets without `socket`) and the keyring calls
//! (`add_key`, `request_key`, `keyctl`: a user's grader's keys are its
//! uid's), with `EACCES`; on x86-64
//! the same calls through the x32 numbers too. `socketpair` stays: it
//! reaches nothing outside. A second filter refuses, with `EPERM`, a mode
//! with the set-user-ID or set-group-ID bit (`chmod`, `fchmod`,
//! `fchmodat`, `fchmodat2`, and a file made by `open`, `openat`, `creat`,
//! `mknod` or `mknodat`), and a third `openat2` (whose mode a filter
//! cannot read) with `ENOSYS`, as a kernel without it would: no mount can
//! make the run's folder `nosuid` without a box, so the program cannot
//! make a file that runs as its uid for another account (which could not
//! reach it anyway, [`crate::folder`]). [`Fence::enter`] installs them in
//! the forked child after it has become the run's user.

use std::collections::BTreeMap;
use std::io;
use std::os::fd::{AsRawFd, OwnedFd};
use std::path::Path;

use landlock::{
    path_beneath_rules, Access, AccessFs, AccessNet, CompatLevel, Compatible, Ruleset, RulesetAttr,
    RulesetCreatedAttr, Scope, ABI,
};
use seccompiler::{
    BpfProgram, SeccompAction, SeccompCmpArgLen, SeccompCmpOp, SeccompCondition, SeccompFilter,
    SeccompRule,
};

use crate::child::sh_runs_after;
use crate::confinement::Share;
use crate::jail::{DEVICES, SYSTEM};

/// The Landlock ABI whose rights the fence handles: 6 adds the scopes.
const LANDLOCK_ABI: ABI = ABI::V6;

/// The system calls refused.
const REFUSED: &[libc::c_long] = &[
    libc::SYS_socket,
    libc::SYS_io_uring_setup,
    // The kernel's keyrings: without a box the run's uid may be the
    // grader's own (a user's grader), whose keys it must not reach.
    libc::SYS_add_key,
    libc::SYS_request_key,
    libc::SYS_keyctl,
];

/// The system calls that give a file a mode, with the index of the mode
/// among their arguments: refused when it has a set-user-ID or
/// set-group-ID bit.
const MODES: &[(libc::c_long, u8)] = &[
    #[cfg(target_arch = "x86_64")]
    (libc::SYS_chmod, 1),
    (libc::SYS_fchmod, 1),
    (libc::SYS_fchmodat, 2),
    (libc::SYS_fchmodat2, 2),
    #[cfg(target_arch = "x86_64")]
    (libc::SYS_open, 2),
    (libc::SYS_openat, 3),
    #[cfg(target_arch = "x86_64")]
    (libc::SYS_creat, 1),
    #[cfg(target_arch = "x86_64")]
    (libc::SYS_mknod, 1),
    (libc::SYS_mknodat, 2),
];

/// One run's fence, prepared before the fork.
#[derive(Debug)]
pub struct Fence {
    /// The Landlock ruleset, when the kernel has Landlock.
    landlock: Option<OwnedFd>,
    /// The seccomp filters, when the kernel has seccomp.
    seccomp: Option<Vec<BpfProgram>>,
}

/// What of the fence this kernel allows: Landlock, seccomp. Each is
/// tried alone on `sh -c :`.
pub fn available() -> (bool, bool) {
    let works = |fence: Fence| {
        // SAFETY: `Fence::enter` makes only async-signal-safe calls.
        unsafe {
            sh_runs_after(move || {
                libc::prctl(libc::PR_SET_NO_NEW_PRIVS, 1, 0, 0, 0);
                fence.enter()
            })
        }
    };
    let landlock = ruleset(&Share::default()).is_some_and(|ruleset| {
        works(Fence {
            landlock: Some(ruleset),
            seccomp: None,
        })
    });
    let seccomp = filter().is_some_and(|filter| {
        works(Fence {
            landlock: None,
            seccomp: Some(filter),
        })
    });
    (landlock, seccomp)
}

impl Fence {
    /// The fence of a run sharing `share` (its working folder read-write,
    /// its command's files read-only), with what of it is wanted; an
    /// error when a part wanted cannot be made, so no run goes without
    /// what the report says confines it.
    pub fn new(share: &Share, landlock: bool, seccomp: bool) -> io::Result<Fence> {
        let missing = |what: &str| io::Error::other(format!("cannot make the {what}"));
        Ok(Fence {
            landlock: landlock
                .then(|| ruleset(share).ok_or_else(|| missing("Landlock ruleset")))
                .transpose()?,
            seccomp: seccomp
                .then(|| filter().ok_or_else(|| missing("seccomp filter")))
                .transpose()?,
        })
    }

    /// Install the fence on this process.
    ///
    /// # Safety
    /// Async-signal-safe: called between fork and exec, after the switch
    /// to the run's user and `PR_SET_NO_NEW_PRIVS`.
    pub unsafe fn enter(&self) -> io::Result<()> {
        if let Some(ruleset) = &self.landlock {
            // SAFETY: a ruleset descriptor and no flags.
            let result = unsafe {
                libc::syscall(
                    libc::SYS_landlock_restrict_self,
                    ruleset.as_raw_fd(),
                    0 as libc::c_uint,
                )
            };
            if result != 0 {
                return Err(io::Error::last_os_error());
            }
        }
        for program in self.seccomp.iter().flatten() {
            seccompiler::apply_filter(program).map_err(|error| match error {
                seccompiler::Error::Prctl(error) | seccompiler::Error::Seccomp(error) => error,
                _ => io::Error::from_raw_os_error(libc::EINVAL),
            })?;
        }
        Ok(())
    }
}

/// The Landlock ruleset of the module doc, or `None` where the kernel
/// lacks any of it.
fn ruleset(share: &Share) -> Option<OwnedFd> {
    let read = AccessFs::from_read(LANDLOCK_ABI);
    let all = AccessFs::from_all(LANDLOCK_ABI);
    let read_write_file = AccessFs::from_file(LANDLOCK_ABI) & !AccessFs::Execute;
    // The box's system folders and devices ([`crate::jail`]).
    let system = SYSTEM.iter().map(Path::new);
    let devices = DEVICES.iter().map(|device| Path::new("/dev").join(device));
    let created = (|| -> Result<_, landlock::RulesetError> {
        Ruleset::default()
            .set_compatibility(CompatLevel::HardRequirement)
            .handle_access(all)?
            .handle_access(AccessNet::from_all(LANDLOCK_ABI))?
            .scope(Scope::from_all(LANDLOCK_ABI))?
            .create()?
            .add_rules(path_beneath_rules(system, read))?
            .add_rules(path_beneath_rules(
                [Path::new("/proc")],
                AccessFs::ReadFile | AccessFs::ReadDir,
            ))?
            .add_rules(path_beneath_rules(devices, read_write_file))?
            .add_rules(path_beneath_rules(&share.read_only, read))?
            .add_rules(path_beneath_rules(&share.read_write, all))
    })()
    .ok()?;
    created.into()
}

/// The seccomp filters of the module doc, or `None` on an architecture
/// seccompiler does not know.
fn filter() -> Option<Vec<BpfProgram>> {
    let arch: seccompiler::TargetArch = std::env::consts::ARCH.try_into().ok()?;
    // Each call, and on x86-64 its x32 number too.
    let numbers = |call: libc::c_long| {
        #[cfg(target_arch = "x86_64")]
        return [call, call | 0x4000_0000];
        #[cfg(not(target_arch = "x86_64"))]
        return [call];
    };
    let compile = |rules: BTreeMap<libc::c_long, Vec<SeccompRule>>, errno: i32| {
        let filter = SeccompFilter::new(
            rules,
            SeccompAction::Allow,
            SeccompAction::Errno(errno as u32),
            arch,
        )
        .ok()?;
        BpfProgram::try_from(filter).ok()
    };
    let refused = REFUSED
        .iter()
        .flat_map(|&call| numbers(call))
        .map(|call| (call, Vec::new()))
        .collect();
    let mut modes = BTreeMap::new();
    for &(call, argument) in MODES {
        let rules = [libc::S_ISUID, libc::S_ISGID]
            .into_iter()
            .map(|bit| {
                let condition = SeccompCondition::new(
                    argument,
                    SeccompCmpArgLen::Dword,
                    SeccompCmpOp::MaskedEq(u64::from(bit)),
                    u64::from(bit),
                )
                .ok()?;
                SeccompRule::new(vec![condition]).ok()
            })
            .collect::<Option<Vec<_>>>()?;
        for number in numbers(call) {
            modes.insert(number, rules.clone());
        }
    }
    let openat2 = numbers(libc::SYS_openat2)
        .into_iter()
        .map(|call| (call, Vec::new()))
        .collect();
    Some(vec![
        compile(refused, libc::EACCES)?,
        compile(modes, libc::EPERM)?,
        compile(openat2, libc::ENOSYS)?,
    ])
}
