//! The box a student's program runs in, after IOI's isolate: limits,
//! what of the grader's file system is shared, and how a run ended.
//!
//! A grader decides once what this machine allows ([`Confinement::new`],
//! [`probe`]): a box of namespaces and a root of our making ([`jail`]),
//! else, with `--unprotected`, a network namespace and a fence of
//! Landlock and seccomp ([`fence`]); control groups where they can be
//! made ([`cgroup`]); as root, a uid of the student's own ([`uids`]).
//! Then each command runs under it ([`run::run`]) from a folder closed to
//! everyone but the grader and given to the run's user ([`folder`]),
//! with its output captured within a bound ([`capture`]), and removed
//! after by a walk no folder can stop ([`folder::remove_tree`]); in a box
//! the working folder is a tmpfs of its own, bounded in bytes and inodes
//! (`scratch.rs`); without a box it has a temporary folder of its own
//! inside it ([`tmpdir`]). The grader copies what a program may write without
//! following a link ([`copy`]) and reads what it wrote the same way
//! ([`output`]). Nothing the process that started the grader left open
//! reaches a program: every descriptor from 3 up is close-on-exec in the
//! child.
//!
//! The crate knows nothing of scenes or images: it runs argument vectors
//! and moves bytes. All of grading's `unsafe` code lives here, each use
//! with its reason: the steps between fork and exec (`child.rs`), the
//! box's children that share its memory until they exec (`sharing.rs`), the
//! system calls std does not wrap (`openat2`, `close_range`, `flock`,
//! `pivot_root`, `mount`, …). The crates above it forbid `unsafe`.

pub mod capture;
pub mod cgroup;
mod child;
pub mod confinement;
pub mod copy;
pub mod fence;
pub mod folder;
pub mod jail;
pub mod output;
pub mod probe;
mod procs;
mod quota;
mod reason;
pub mod run;
mod scratch;
mod sharing;
mod spawning;
pub mod tmpdir;
pub mod uids;

pub use confinement::{Confinement, Limits, Scratch, Share};
pub use run::{Ended, Run};

/// This process's effective uid.
pub fn effective_uid() -> u32 {
    // SAFETY: `geteuid` has no preconditions.
    unsafe { libc::geteuid() }
}
