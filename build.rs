//! The build of `raytracer` names itself: `raytracer --version` says which
//! commit it was built from and whether the sources differed from it
//! (`raytracer 0.1.0 (commit 2a79027, modified)`), so a bug report names
//! the build. It asks `git` when the package is a git checkout of its own
//! and says `unknown commit` otherwise (a tarball, or no `git`). Only the
//! thin binary has this script, so a commit rebuilds `main` alone, not the
//! crates below it. tests/version.rs runs [`describe`] on folders of its own.

use std::path::{Path, PathBuf};
use std::process::Command;

/// The paths whose change the commit or the modified mark follow: what the
/// binary is built from.
pub const SOURCES: [&str; 5] = ["src", "crates", "Cargo.toml", "Cargo.lock", "build.rs"];

#[allow(dead_code)] // tests/version.rs includes this file for `describe`
fn main() {
    let dir = PathBuf::from(std::env::var_os("CARGO_MANIFEST_DIR").expect("cargo sets it"));
    let build = describe(&dir);
    println!(
        "cargo:rustc-env=RAYTRACER_VERSION={} ({})",
        std::env::var("CARGO_PKG_VERSION").expect("cargo sets it"),
        build.text()
    );
    for source in SOURCES {
        println!("cargo:rerun-if-changed={source}");
    }
    // Git's own files that change with a commit, a checkout or a staged
    // change (absent in a tarball, where the sources above suffice).
    for path in build.git_files {
        println!("cargo:rerun-if-changed={}", path.display());
    }
}

/// What `git` says of the checkout at `dir`.
pub struct Build {
    /// HEAD's short hash, or `None` when `dir` is not the top of a git
    /// checkout or `git` cannot run.
    pub commit: Option<String>,
    /// Whether [`SOURCES`] differ from HEAD (staged, unstaged or new files).
    pub modified: bool,
    /// The files of git's that a new commit, checkout or index changes.
    pub git_files: Vec<PathBuf>,
}

impl Build {
    /// `commit 2a79027`, `commit 2a79027, modified` or `unknown commit`.
    pub fn text(&self) -> String {
        match (&self.commit, self.modified) {
            (Some(commit), false) => format!("commit {commit}"),
            (Some(commit), true) => format!("commit {commit}, modified"),
            (None, _) => "unknown commit".to_string(),
        }
    }
}

/// Ask `git`, in `dir`, which commit it is and whether [`SOURCES`] differ.
pub fn describe(dir: &Path) -> Build {
    let unknown = Build {
        commit: None,
        modified: false,
        git_files: Vec::new(),
    };
    let git = |args: &[&str]| -> Option<String> {
        let output = Command::new("git")
            .arg("--no-optional-locks")
            .args(args)
            .current_dir(dir)
            .output()
            .ok()?;
        output
            .status
            .success()
            .then(|| String::from_utf8_lossy(&output.stdout).trim().to_string())
    };
    // Only a checkout whose top is this package: a tarball unpacked inside
    // some other repository is not that repository's commit.
    let Some(top) = git(&["rev-parse", "--show-toplevel"]) else {
        return unknown;
    };
    let same = |a: &Path, b: &Path| match (a.canonicalize(), b.canonicalize()) {
        (Ok(a), Ok(b)) => a == b,
        _ => false,
    };
    if !same(Path::new(&top), dir) {
        return unknown;
    }
    let Some(commit) = git(&["rev-parse", "--short=7", "HEAD"]) else {
        return unknown;
    };
    let mut status = vec!["status", "--porcelain", "--"];
    status.extend(SOURCES);
    let modified = git(&status).is_none_or(|changes| !changes.is_empty());
    let mut git_files = Vec::new();
    if let Some(git_dir) = git(&["rev-parse", "--absolute-git-dir"]) {
        let git_dir = PathBuf::from(git_dir);
        git_files.push(git_dir.join("HEAD"));
        git_files.push(git_dir.join("index"));
    }
    if let Some(common) = git(&["rev-parse", "--git-common-dir"]) {
        let common = dir.join(common);
        git_files.push(common.join("packed-refs"));
        if let Some(branch) = git(&["symbolic-ref", "-q", "HEAD"]) {
            git_files.push(common.join(branch));
        }
    }
    git_files.retain(|path| path.exists());
    Build {
        commit: Some(commit),
        modified,
        git_files,
    }
}
