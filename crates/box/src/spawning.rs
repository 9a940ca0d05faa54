//! The lock between starting a program and writing a file a program may
//! run.

/// Held for writing while a program is started, and for reading while
/// the grader has a file open for writing that a program may run (a
/// student's copied program): a fork made then would inherit the open
/// descriptor, and a program run from that file meanwhile would fail with
/// `text file busy` (`ETXTBSY`) until the fork's child execs.
pub static SPAWNING: std::sync::RwLock<()> = std::sync::RwLock::new(());
