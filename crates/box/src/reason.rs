//! Why a run could not start, in words for a report: lowercase, naming
//! the program and what to do, the same whoever the grader runs as.

use std::ffi::OsStr;
use std::io;

/// `error` as a lowercase phrase.
pub(crate) fn reason(error: &io::Error) -> String {
    let text = error.to_string();
    let mut chars = text.chars();
    match chars.next() {
        Some(first) => first.to_lowercase().chain(chars).collect(),
        None => text,
    }
}

/// Why `program` could not start: a missing program is `ENOENT` to one
/// user and `EACCES` to another (the search met a folder of `PATH` that
/// user may not enter), and a file without `chmod +x` is `EACCES` too,
/// so both read as one reason that names the program and the three
/// causes.
pub(crate) fn start_failure(program: &OsStr, error: &io::Error) -> String {
    match error.kind() {
        io::ErrorKind::NotFound | io::ErrorKind::PermissionDenied => format!(
            "no program `{}` it may run (it is missing, not executable: `chmod +x`, or in a folder its user may not enter)",
            program.to_string_lossy()
        ),
        _ => reason(error),
    }
}
