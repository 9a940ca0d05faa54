//! The folders a run works in: made closed to everyone but the grader,
//! and given to the run's user from the inside out.

use std::fs::Permissions;
use std::os::unix::fs::PermissionsExt;
use std::path::Path;

use tempfile::TempDir;

/// A fresh temporary folder that only the grader may enter (mode 0700).
pub fn private_folder() -> std::io::Result<TempDir> {
    tempfile::Builder::new()
        .prefix("raytracer-grade-")
        .permissions(Permissions::from_mode(0o700))
        .tempdir()
}

/// Give `dir`, and everything under it, to user and group `id`: the
/// entries first, while `dir` is still the grader's own and closed to
/// everyone else, and `dir` itself last. No link is followed: an entry is
/// given as what it is, and a folder is walked only when it is one.
pub fn give(dir: &Path, id: u32) -> std::io::Result<()> {
    give_entries(dir, id)?;
    std::os::unix::fs::lchown(dir, Some(id), Some(id))
}

/// Give everything under the folder `dir` to `id`, deepest first.
fn give_entries(dir: &Path, id: u32) -> std::io::Result<()> {
    for entry in std::fs::read_dir(dir)? {
        let entry = entry?;
        let path = entry.path();
        if entry.file_type()?.is_dir() {
            give_entries(&path, id)?;
        }
        std::os::unix::fs::lchown(&path, Some(id), Some(id))?;
    }
    Ok(())
}
