//! A quota where there is none: the bound on a run's writable folders
//! that no tmpfs holds.
//!
//! In a box, a scene's working folder is a tmpfs of `--disk` MiB and
//! [`crate::scratch`]'s inodes. Where no tmpfs can be mounted (without a
//! box, as in Gradescope's containers), and for a build's folder, which a
//! box binds from the grader's disk, the file system has no quota for the
//! run's user (and as an ordinary user's grader, that user is the
//! grader's own). So the grader measures those folders while the program
//! runs ([`Quota::due`]), again after a pause as long as the last walk
//! took and 50 ms more (a walk of an honest run's folder takes
//! microseconds; of one holding tens of thousands of files, at most half
//! a core), and the run ([`crate::run`]) kills the program's whole
//! process tree as soon as they hold more bytes (blocks allocated) or
//! more entries than a tmpfs would: the report then says the run's disk
//! space was full, as it does for a tmpfs. A run may pass the bound by
//! what it writes between two walks; `--max-file-size` still bounds each
//! file, and what the run leaves is removed after it.
//!
//! The walk ([`usage`]) follows no link and holds two descriptors at most
//! (a folder, and on the way up its parent, reached through `..` and
//! checked by device and inode, as [`crate::folder::remove_tree`] does),
//! so 30,000 nested folders cost no stack and no descriptor per level;
//! it stays on the folder's file system, counts a file with several names
//! once, counts too the files on that file system that the run's
//! processes hold open after removing them (`/proc/PID/fd`), and stops as
//! soon as the bound is passed, so one walk reads at most the bound's
//! number of entries. An ordinary user's program may take its folders'
//! rights from their owner (`chmod 000`): the grader, that owner, gives
//! them back before it lists one. A folder it still cannot list, or one
//! moved while it was walked, leaves that walk unfinished; walks that
//! keep being left unfinished count as over the bound, so no program can
//! hide its files by keeping the grader from seeing them.

use std::collections::HashSet;
use std::ffi::{CStr, CString, OsStr};
use std::fs::Permissions;
use std::io;
use std::os::fd::{AsRawFd, OwnedFd};
use std::os::unix::ffi::OsStrExt;
use std::os::unix::fs::{MetadataExt, PermissionsExt};
use std::path::{Path, PathBuf};
use std::time::{Duration, Instant};

use crate::copy::{open_at, stat_at};
use crate::procs::descendants;

/// The shortest pause between two walks.
const PAUSE: Duration = Duration::from_millis(50);

/// Walks in a row left unfinished before the folders count as over the
/// bound.
const UNFINISHED: u32 = 8;

/// What the folders may hold, or what is left of it.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(crate) struct Bound {
    pub bytes: u64,
    pub inodes: u64,
}

/// How a walk ended.
#[derive(Debug, PartialEq, Eq)]
pub(crate) enum Usage {
    /// Within the bound: what is left of it.
    Within(Bound),
    /// Over the bound.
    Over,
    /// A folder could not be listed, or was moved while it was walked.
    Unfinished,
}

/// The folders one run may write that no tmpfs bounds, and when to walk
/// them next.
#[derive(Debug)]
pub(crate) struct Quota {
    folders: Vec<PathBuf>,
    bound: Bound,
    next: Instant,
    unfinished: u32,
    /// The run's first process, once it runs: the files its tree holds
    /// open count too.
    leader: Option<libc::pid_t>,
}

impl Quota {
    /// The quota of `folders`, together held to `bound`; `None` when there
    /// is no folder to watch.
    pub(crate) fn new(folders: Vec<PathBuf>, bound: Bound) -> Option<Quota> {
        (!folders.is_empty()).then(|| Quota {
            folders,
            bound,
            next: Instant::now(),
            unfinished: 0,
            leader: None,
        })
    }

    /// Count, from now on, the files that the process tree of `leader`
    /// (the run's first process) holds open and no folder names any more.
    pub(crate) fn watch(&mut self, leader: libc::pid_t) {
        self.leader = Some(leader);
    }

    /// The folders' usage, with what the run's processes hold open
    /// while it runs.
    fn usage(&self) -> Usage {
        let holders = self.leader.map(descendants).unwrap_or_default();
        usage(&self.folders, self.bound, &holders)
    }

    /// Whether the folders hold more than the bound now, before the
    /// program starts or once it has ended (a walk left unfinished counts
    /// as within it).
    pub(crate) fn over(&self) -> bool {
        usage(&self.folders, self.bound, &[]) == Usage::Over
    }

    /// While the program runs: walk the folders when a walk is due, and
    /// say whether they are over the bound, or their walks keep being left
    /// unfinished.
    pub(crate) fn due(&mut self) -> bool {
        let now = Instant::now();
        if now < self.next {
            return false;
        }
        let found = self.usage();
        self.next = Instant::now() + (Instant::now() - now) + PAUSE;
        match found {
            Usage::Within(_) => {
                self.unfinished = 0;
                false
            }
            Usage::Over => true,
            Usage::Unfinished => {
                self.unfinished += 1;
                self.unfinished >= UNFINISHED
            }
        }
    }
}

/// The entries and bytes under `folders` (each folder counted too), and
/// of the files on their file systems that the processes `holders` hold
/// open and no folder names any more, against `bound`.
pub(crate) fn usage(folders: &[PathBuf], bound: Bound, holders: &[libc::pid_t]) -> Usage {
    let mut walk = Walk {
        left: bound,
        seen: HashSet::new(),
        devices: Vec::new(),
    };
    for folder in folders {
        match walk.folder(folder) {
            Ok(true) => {}
            Ok(false) => return Usage::Over,
            Err(_) => return Usage::Unfinished,
        }
    }
    if !walk.held_open(holders) {
        return Usage::Over;
    }
    Usage::Within(walk.left)
}

/// One walk: what is left of the bound, the files with several names (or
/// none) already counted, and the file systems of the folders walked.
struct Walk {
    left: Bound,
    seen: HashSet<(u64, u64)>,
    devices: Vec<u64>,
}

/// A folder being walked: its device and inode (to know it again on the
/// way up), and the folders in it not walked yet.
struct Level {
    id: (u64, u64),
    folders: Vec<CString>,
}

impl Walk {
    /// Count `top` and everything under it; `Ok(false)` once the bound is
    /// passed.
    fn folder(&mut self, top: &Path) -> io::Result<bool> {
        let mut current = enter(libc::AT_FDCWD, top.as_os_str())?;
        let stat = stat_of(&current)?;
        let device = stat.st_dev;
        self.devices.push(device);
        if !self.count(&stat) {
            return Ok(false);
        }
        let mut levels = vec![Level {
            id: (stat.st_dev, stat.st_ino),
            folders: Vec::new(),
        }];
        let Some(folders) = self.list(&current, device)? else {
            return Ok(false);
        };
        levels[0].folders = folders;
        loop {
            let level = levels.last_mut().expect("a level while walking");
            if let Some(name) = level.folders.pop() {
                let inner = match enter(current.as_raw_fd(), OsStr::from_bytes(name.as_bytes())) {
                    Ok(inner) => inner,
                    // Removed since it was listed.
                    Err(error) if error.raw_os_error() == Some(libc::ENOENT) => continue,
                    Err(error) => return Err(error),
                };
                let stat = stat_of(&inner)?;
                let Some(folders) = self.list(&inner, device)? else {
                    return Ok(false);
                };
                current = inner;
                levels.push(Level {
                    id: (stat.st_dev, stat.st_ino),
                    folders,
                });
                continue;
            }
            levels.pop();
            let Some(up) = levels.last() else {
                return Ok(true);
            };
            let parent = open_at(current.as_raw_fd(), OsStr::new(".."), libc::O_DIRECTORY)?;
            let stat = stat_of(&parent)?;
            if (stat.st_dev, stat.st_ino) != up.id {
                return Err(io::Error::other("a folder was moved while it was walked"));
            }
            current = parent;
        }
    }

    /// Count one entry; `false` once the bound is passed.
    fn count(&mut self, stat: &libc::stat) -> bool {
        let folder = stat.st_mode & libc::S_IFMT == libc::S_IFDIR;
        if !folder && stat.st_nlink > 1 && !self.seen.insert((stat.st_dev, stat.st_ino)) {
            return true;
        }
        self.charge(stat.st_blocks as u64)
    }

    /// Charge one inode of `blocks` blocks of 512 bytes; `false` once the
    /// bound is passed.
    fn charge(&mut self, blocks: u64) -> bool {
        match (
            self.left.inodes.checked_sub(1),
            self.left.bytes.checked_sub(blocks.saturating_mul(512)),
        ) {
            (Some(inodes), Some(bytes)) => {
                self.left = Bound { bytes, inodes };
                true
            }
            _ => false,
        }
    }

    /// Count the regular files on the walked file systems that `holders`
    /// hold open and no folder names (deleted, no link left): what a
    /// program writes through a descriptor after removing the file;
    /// `false` once the bound is passed.
    fn held_open(&mut self, holders: &[libc::pid_t]) -> bool {
        for pid in holders {
            let Ok(descriptors) = std::fs::read_dir(format!("/proc/{pid}/fd")) else {
                continue;
            };
            for descriptor in descriptors.flatten() {
                // The descriptor's link, followed: the open file itself.
                let Ok(meta) = std::fs::metadata(descriptor.path()) else {
                    continue;
                };
                let unnamed = meta.is_file() && meta.nlink() == 0;
                if unnamed
                    && self.devices.contains(&meta.dev())
                    && self.seen.insert((meta.dev(), meta.ino()))
                    && !self.charge(meta.blocks())
                {
                    return false;
                }
            }
        }
        true
    }

    /// Count every entry of the open folder `dir`, and return the names
    /// of the folders in it on `device`; `None` once the bound is passed.
    fn list(&mut self, dir: &OwnedFd, device: u64) -> io::Result<Option<Vec<CString>>> {
        let mut folders = Vec::new();
        for name in names(dir)? {
            let stat = match stat_at(dir, &name) {
                Ok(stat) => stat,
                Err(error) if error.raw_os_error() == Some(libc::ENOENT) => continue,
                Err(error) => return Err(error),
            };
            if !self.count(&stat) {
                return Ok(None);
            }
            if stat.st_mode & libc::S_IFMT == libc::S_IFDIR && stat.st_dev == device {
                folders.push(name);
            }
        }
        Ok(Some(folders))
    }
}

/// Open the folder `name` in `dir` (`AT_FDCWD`: the working folder) for
/// listing, not following a link ([`listable`]).
fn enter(dir: libc::c_int, name: &OsStr) -> io::Result<OwnedFd> {
    listable(open_at(dir, name, libc::O_PATH | libc::O_DIRECTORY)?)
}

/// The folder held at `place` (`O_PATH`), opened for listing; when its
/// owner may not list or search it, and the grader is that owner, given
/// those rights back first (root needs no right).
fn listable(place: OwnedFd) -> io::Result<OwnedFd> {
    let stat = stat_of(&place)?;
    let me = crate::effective_uid();
    if me != 0 && stat.st_uid == me && stat.st_mode & 0o500 != 0o500 {
        let through = format!("/proc/self/fd/{}", place.as_raw_fd());
        let mode = stat.st_mode & 0o7777 | 0o700;
        std::fs::set_permissions(through, Permissions::from_mode(mode))?;
    }
    open_at(place.as_raw_fd(), OsStr::new("."), libc::O_DIRECTORY)
}

/// The names in the open folder `dir` but `.` and `..`.
fn names(dir: &OwnedFd) -> io::Result<Vec<CString>> {
    // A descriptor of its own, so the listing starts at the beginning.
    let listing = open_at(dir.as_raw_fd(), OsStr::new("."), libc::O_DIRECTORY)?;
    // SAFETY: `fdopendir` takes ownership of the fresh descriptor.
    let stream = unsafe { libc::fdopendir(listing.as_raw_fd()) };
    if stream.is_null() {
        return Err(io::Error::last_os_error());
    }
    std::mem::forget(listing);
    let mut names = Vec::new();
    loop {
        // SAFETY: `stream` is an open directory stream.
        let entry = unsafe { libc::readdir(stream) };
        if entry.is_null() {
            break;
        }
        // SAFETY: `d_name` of an entry `readdir` returned is a C string.
        let name = unsafe { CStr::from_ptr((*entry).d_name.as_ptr()) };
        if !matches!(name.to_bytes(), b"." | b"..") {
            names.push(name.to_owned());
        }
    }
    // SAFETY: closing the stream `fdopendir` made (and its descriptor).
    unsafe { libc::closedir(stream) };
    Ok(names)
}

/// `fstat` of an open file.
fn stat_of(fd: &OwnedFd) -> io::Result<libc::stat> {
    // SAFETY: `stat` is plain data, filled by the call.
    let mut stat: libc::stat = unsafe { std::mem::zeroed() };
    // SAFETY: a valid descriptor and out pointer.
    if unsafe { libc::fstat(fd.as_raw_fd(), &mut stat) } != 0 {
        return Err(io::Error::last_os_error());
    }
    Ok(stat)
}

#[cfg(test)]
mod tests {
    use super::*;

    fn bound(bytes: u64, inodes: u64) -> Bound {
        Bound { bytes, inodes }
    }

    #[test]
    fn entries_and_bytes_are_counted_once_without_following_a_link() {
        let dir = tempfile::tempdir().unwrap();
        let outside = dir.path().join("outside");
        std::fs::create_dir(&outside).unwrap();
        std::fs::write(outside.join("big"), vec![1u8; 1 << 20]).unwrap();
        let top = dir.path().join("top");
        std::fs::create_dir_all(top.join("a/b")).unwrap();
        std::fs::write(top.join("a/b/file"), vec![1u8; 64 << 10]).unwrap();
        std::fs::hard_link(top.join("a/b/file"), top.join("again")).unwrap();
        std::os::unix::fs::symlink(&outside, top.join("link")).unwrap();
        let Usage::Within(left) = usage(std::slice::from_ref(&top), bound(1 << 30, 100), &[])
        else {
            panic!("over the bound")
        };
        // top, a, b, file (with its second name), link.
        assert_eq!(100 - left.inodes, 5);
        let used = (1 << 30) - left.bytes;
        assert!((64 << 10..1 << 20).contains(&used), "{used}");
        assert_eq!(
            usage(std::slice::from_ref(&top), bound(1 << 30, 4), &[]),
            Usage::Over
        );
        assert_eq!(usage(&[top], bound(32 << 10, 100), &[]), Usage::Over);
    }

    /// As an ordinary user's grader, which is the owner of what its
    /// program makes: a folder the program closed to listing (`chmod
    /// 300`) is opened again and counted, not left unseen.
    #[test]
    fn a_folder_its_owner_closed_is_opened_again_and_counted() {
        if crate::effective_uid() != 0 {
            // Run as root, the test plays an ordinary user (`nobody`).
            use std::io::Write;
            let _ = writeln!(
                std::io::stderr(),
                "SKIPPED the user's walk: it needs root to play a user"
            );
            return;
        }
        let dir = tempfile::tempdir().unwrap();
        std::fs::set_permissions(dir.path(), Permissions::from_mode(0o755)).unwrap();
        let top = dir.path().join("top");
        let hidden = top.join("hidden");
        std::fs::create_dir_all(&hidden).unwrap();
        for name in ["a", "b", "c"] {
            std::fs::write(hidden.join(name), vec![1u8; 8192]).unwrap();
        }
        let nobody = crate::confinement::NOBODY;
        for path in [&top, &hidden] {
            for entry in std::fs::read_dir(path).unwrap() {
                std::os::unix::fs::lchown(entry.unwrap().path(), Some(nobody), Some(nobody))
                    .unwrap();
            }
        }
        std::os::unix::fs::lchown(&top, Some(nobody), Some(nobody)).unwrap();
        std::fs::set_permissions(&hidden, Permissions::from_mode(0o300)).unwrap();
        // SAFETY: the child only switches uid, walks and leaves with `_exit`.
        let child = unsafe { libc::fork() };
        if child == 0 {
            // SAFETY: plain system calls.
            let switched = unsafe { libc::setgid(nobody) == 0 && libc::setuid(nobody) == 0 };
            // Itself, `hidden` and three files of 8 KiB.
            let counted = switched
                && matches!(
                    usage(std::slice::from_ref(&top), bound(1 << 30, 100), &[]),
                    Usage::Within(left) if left.inodes == 95 && (1 << 30) - left.bytes >= 3 * 8192
                );
            // SAFETY: leaving the child.
            unsafe { libc::_exit(i32::from(!counted)) };
        }
        let mut status = 0;
        // SAFETY: waiting for our own child.
        assert_eq!(unsafe { libc::waitpid(child, &mut status, 0) }, child);
        assert_eq!(status, 0, "the closed folder was not counted as its owner");
        let mode = std::fs::metadata(&hidden).unwrap().permissions().mode();
        assert_eq!(
            mode & 0o777,
            0o700,
            "its owner's rights were not given back"
        );
    }

    /// A file removed while a process holds it open and writes to it is
    /// named by no folder, and still takes the disk: it counts, for the
    /// processes that hold it.
    #[test]
    fn a_removed_file_held_open_counts() {
        let dir = tempfile::tempdir().unwrap();
        let top = dir.path().join("top");
        std::fs::create_dir(&top).unwrap();
        let mut held = std::fs::File::create(top.join("removed")).unwrap();
        std::fs::remove_file(top.join("removed")).unwrap();
        std::io::Write::write_all(&mut held, &vec![1u8; 1 << 20]).unwrap();
        held.sync_all().unwrap();
        let folders = std::slice::from_ref(&top);
        let small = bound(512 << 10, 100);
        assert!(matches!(usage(folders, small, &[]), Usage::Within(_)));
        let me = std::process::id() as libc::pid_t;
        assert_eq!(usage(folders, small, &[me]), Usage::Over);
        drop(held);
        assert!(matches!(usage(folders, small, &[me]), Usage::Within(_)));
    }

    #[test]
    fn deep_and_closed_folders_are_measured_with_a_small_stack() {
        let dir = tempfile::tempdir().unwrap();
        let top = dir.path().join("top");
        std::fs::create_dir(&top).unwrap();
        let mut current = open_at(libc::AT_FDCWD, top.as_os_str(), libc::O_DIRECTORY).unwrap();
        for _ in 0..3_000 {
            // SAFETY: a valid descriptor and C string.
            assert_eq!(
                unsafe { libc::mkdirat(current.as_raw_fd(), c"d".as_ptr(), 0o755) },
                0
            );
            current = open_at(current.as_raw_fd(), OsStr::new("d"), libc::O_DIRECTORY).unwrap();
        }
        drop(current);
        let closed = top.join("closed");
        std::fs::create_dir(&closed).unwrap();
        std::fs::write(closed.join("file"), "x").unwrap();
        std::fs::set_permissions(&closed, Permissions::from_mode(0o000)).unwrap();
        let measured = top.clone();
        let found = std::thread::Builder::new()
            .stack_size(64 << 10)
            .spawn(move || usage(&[measured], bound(1 << 40, 10_000), &[]))
            .unwrap()
            .join()
            .unwrap();
        let Usage::Within(left) = found else {
            panic!("{found:?}")
        };
        // top, 3,000 nested folders, closed and its file.
        assert_eq!(10_000 - left.inodes, 3_003);
        assert_eq!(
            usage(std::slice::from_ref(&top), bound(1 << 40, 3_002), &[]),
            Usage::Over
        );
        crate::folder::remove_tree(&top).unwrap();
    }
}
