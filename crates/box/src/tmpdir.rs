//! The private temporary folder of a run without a box.
//!
//! In a box, `/tmp`, `/var/tmp` and `/dev/shm` are tmpfs folders of the
//! box's own ([`crate::jail`]). Without one (`--unprotected`, as in
//! Gradescope's container), the fence refuses the machine's `/tmp`
//! ([`crate::fence`]), and a compiler (`cc`, `c++`, `make`'s children),
//! Java or Python writing its temporary files there would fail. So such
//! a run gets a folder of its own inside its working folder, which it may
//! write, named in the environment by every setting the usual runtimes
//! read: `TMPDIR` (the C library, GCC, Python's `tempfile`, Node) and
//! `JAVA_TOOL_OPTIONS`' `java.io.tmpdir` (Java and `javac`; with the JVM's
//! performance data, which is written to `/tmp` whatever the setting,
//! turned off). The child makes the folder ([`make`]) once it is the run's
//! user, so the folder is the run's; it goes with the working folder.

use std::ffi::{CString, OsString};
use std::io;
use std::os::unix::ffi::OsStrExt;
use std::path::{Path, PathBuf};

/// The folder's name inside the run's working folder.
pub const NAME: &str = ".tmp";

/// The private temporary folder of a run that starts in `dir`.
pub fn folder(dir: &Path) -> PathBuf {
    dir.join(NAME)
}

/// The environment that names `folder` as the temporary folder.
pub fn environment(folder: &Path) -> Vec<(&'static str, OsString)> {
    let mut java = OsString::from("-Djava.io.tmpdir=");
    java.push(folder);
    java.push(" -XX:-UsePerfData");
    vec![("TMPDIR", folder.into()), ("JAVA_TOOL_OPTIONS", java)]
}

/// `folder` as the child's [`make`] takes it.
pub fn path(folder: &Path) -> io::Result<CString> {
    CString::new(folder.as_os_str().as_bytes()).map_err(io::Error::other)
}

/// Make the folder (mode 0700), or find it made (a student's build left
/// one in the folder its runs copy).
///
/// # Safety
/// Async-signal-safe: called between fork and exec, as the run's user.
pub unsafe fn make(path: &CString) -> io::Result<()> {
    // SAFETY: a NUL-terminated path.
    unsafe {
        if libc::mkdir(path.as_ptr(), 0o700) == -1 && *libc::__errno_location() != libc::EEXIST {
            return Err(io::Error::last_os_error());
        }
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn every_runtime_is_told_the_folder() {
        let env = environment(Path::new("/w/.tmp"));
        assert_eq!(env[0], ("TMPDIR", OsString::from("/w/.tmp")));
        assert_eq!(
            env[1],
            (
                "JAVA_TOOL_OPTIONS",
                OsString::from("-Djava.io.tmpdir=/w/.tmp -XX:-UsePerfData")
            )
        );
    }
}
