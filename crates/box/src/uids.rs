//! The uids a root grader runs students as, leased so that no two
//! students share one, within a run or across `grade` processes running
//! at once on the machine (a Slurm node grading many students), after
//! isolate's box ids.
//!
//! Each uid of the range (`--uids`, 60000 to 64999 unless given: like
//! isolate's boxes, ids that should belong to no one on the machine) has a
//! lock file in a folder only root may enter ([`FOLDER`], refused when it
//! is a link or someone else's, its mode corrected when it is root's). A
//! [`Lease`] is an open lock file held with `flock`: the lowest uid of
//! the range whose lock no one holds and which names no user or group in
//! the password and group databases (a range may cross an account a
//! package made, as Debian's `slurm` is 64030). The kernel
//! releases a lock when the last descriptor of it closes, so a grader
//! killed with SIGKILL frees its uids, and no grader can keep one it no
//! longer runs. A grader keeps every lease of its run until it exits, so
//! the students of one class have a uid each too. A uid no grader holds
//! runs nothing of ours: taking it first kills every process left
//! running as it (a killed grader's student's daemon, outside a box).

use std::fs::File;
use std::io;
use std::ops::RangeInclusive;
use std::os::fd::AsRawFd;
use std::os::unix::fs::{DirBuilderExt, MetadataExt, OpenOptionsExt, PermissionsExt};
use std::path::Path;

/// The folder of the lock files, root's and closed to everyone else.
pub const FOLDER: &str = "/run/raytracer-grade/uids";

/// A uid held for this grader until it is dropped (or the grader dies).
#[derive(Debug)]
pub struct Lease {
    uid: u32,
    _lock: File,
}

impl Lease {
    /// The lowest uid of `range` that no grader holds and no account has.
    pub fn take(range: &RangeInclusive<u32>) -> io::Result<Lease> {
        let folder = Path::new(FOLDER);
        for dir in [folder.parent().unwrap_or(folder), folder] {
            root_only(dir)?;
        }
        for uid in range.clone().filter(|&uid| !has_account(uid)) {
            let lock = std::fs::OpenOptions::new()
                .read(true)
                .write(true)
                .create(true)
                .mode(0o600)
                .custom_flags(libc::O_NOFOLLOW)
                .open(folder.join(uid.to_string()))?;
            // SAFETY: `flock` on a descriptor we own.
            if unsafe { libc::flock(lock.as_raw_fd(), libc::LOCK_EX | libc::LOCK_NB) } == 0 {
                kill_every_process_of(uid)?;
                return Ok(Lease { uid, _lock: lock });
            }
            let error = io::Error::last_os_error();
            if error.raw_os_error() != Some(libc::EWOULDBLOCK) {
                return Err(error);
            }
        }
        Err(io::Error::other(format!(
            "every uid from {} to {} is in use or names an account (`--uids` takes another range)",
            range.start(),
            range.end()
        )))
    }

    pub fn uid(&self) -> u32 {
        self.uid
    }
}

/// Whether `id` names a user in the password database or a group in the
/// group database (through NSS, so directory services count too): such
/// an id is someone's, and a student run as it could reach their files.
fn has_account(id: u32) -> bool {
    let mut buffer = vec![0 as libc::c_char; 16 * 1024];
    // SAFETY: `getpwuid_r` and `getgrgid_r` write into the records and
    // the buffer we pass, whose lengths we give.
    unsafe {
        let mut user: libc::passwd = std::mem::zeroed();
        let mut found: *mut libc::passwd = std::ptr::null_mut();
        libc::getpwuid_r(id, &mut user, buffer.as_mut_ptr(), buffer.len(), &mut found);
        if !found.is_null() {
            return true;
        }
        let mut group: libc::group = std::mem::zeroed();
        let mut found: *mut libc::group = std::ptr::null_mut();
        libc::getgrgid_r(
            id,
            &mut group,
            buffer.as_mut_ptr(),
            buffer.len(),
            &mut found,
        );
        !found.is_null()
    }
}

/// Kill every process running as `uid`, and empty its user and user
/// session keyrings (`@u`, `@us`): what a grader killed without a box may
/// have left running, and what any run left in the kernel, under a uid no
/// grader holds now. A child
/// takes the uid alone and signals every process it may (`kill(-1)`),
/// as isolate cleans a box.
fn kill_every_process_of(uid: u32) -> io::Result<()> {
    // SAFETY: the child makes only async-signal-safe system calls.
    unsafe {
        let child = libc::fork();
        if child == -1 {
            return Err(io::Error::last_os_error());
        }
        if child == 0 {
            if libc::setresuid(uid, uid, uid) == 0 {
                libc::kill(-1, libc::SIGKILL);
                // The uid's own keyrings outlive its processes: emptied,
                // so no key one student left reaches the next.
                const KEYCTL_CLEAR: libc::c_long = 7;
                for keyring in [-4 as libc::c_long, -5] {
                    libc::syscall(libc::SYS_keyctl, KEYCTL_CLEAR, keyring);
                }
                libc::_exit(0);
            }
            libc::_exit(1);
        }
        let mut status = 0;
        while libc::waitpid(child, &mut status, 0) == -1 {
            if *libc::__errno_location() != libc::EINTR {
                return Err(io::Error::last_os_error());
            }
        }
        if !libc::WIFEXITED(status) || libc::WEXITSTATUS(status) != 0 {
            return Err(io::Error::other(format!(
                "cannot end the processes left running as uid {uid}"
            )));
        }
    }
    Ok(())
}

/// Make `dir` a folder of root's that only root may enter, or refuse it.
fn root_only(dir: &Path) -> io::Result<()> {
    match std::fs::DirBuilder::new().mode(0o700).create(dir) {
        Err(error) if error.kind() != io::ErrorKind::AlreadyExists => return Err(error),
        _ => {}
    }
    let meta = dir.symlink_metadata()?;
    if !meta.is_dir() || meta.uid() != 0 {
        return Err(io::Error::other(format!(
            "`{}` is not a folder of root's",
            dir.display()
        )));
    }
    if meta.mode() & 0o077 != 0 {
        std::fs::set_permissions(dir, std::fs::Permissions::from_mode(0o700))?;
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::{has_account, Lease};

    #[test]
    fn root_has_an_account_and_an_unused_id_has_none() {
        assert!(has_account(0));
        assert!(!has_account(4_000_000_000));
    }

    /// A range that holds an account's id (as 60000 to 64999 holds
    /// Debian's `slurm`, 64030) leases around it, and one that holds only
    /// accounts' ids leases nothing (root alone may lease).
    #[test]
    fn a_range_crossing_an_account_leases_around_it() {
        if crate::effective_uid() != 0 {
            let ci = std::env::var("CI").unwrap_or_default();
            assert!(
                matches!(ci.trim(), "" | "0") || ci.eq_ignore_ascii_case("false"),
                "CI runs as root, and must lease"
            );
            use std::io::Write;
            let _ = writeln!(std::io::stderr(), "SKIPPED leasing uids: root alone may");
            return;
        }
        let error = Lease::take(&(0..=0)).unwrap_err();
        assert!(error.to_string().contains("names an account"), "{error}");
        let nobody = crate::confinement::NOBODY;
        assert!(has_account(nobody));
        let lease = Lease::take(&(nobody..=nobody + 64)).unwrap();
        assert_ne!(lease.uid(), nobody);
        assert!(!has_account(lease.uid()));
    }
}
