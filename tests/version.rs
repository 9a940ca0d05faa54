//! `raytracer --version` names the build: the commit it was built from and
//! whether the sources differed from it, or `unknown commit` outside a git
//! checkout (a tarball). The binary's build script is included here to run
//! its [`describe`](build_script::describe) on checkouts of the test's own.

use std::path::Path;
use std::process::Command;

use crate::support::{self, run};

#[path = "../build.rs"]
mod build_script;

fn git(dir: &Path, args: &[&str]) -> String {
    let output = Command::new("git")
        .args(["-c", "user.name=test", "-c", "user.email=test@example.com"])
        .args(args)
        .current_dir(dir)
        .output()
        .expect("run git");
    assert!(output.status.success(), "git {args:?}: {output:?}");
    String::from_utf8_lossy(&output.stdout).trim().to_string()
}

#[test]
fn the_version_names_the_commit_of_this_checkout() {
    let output = run(&["--version"]);
    assert_eq!(output.status.code(), Some(0));
    let version = String::from_utf8(output.stdout).expect("UTF-8");
    let repo = Path::new(env!("CARGO_MANIFEST_DIR"));
    let build = build_script::describe(repo);
    assert_eq!(
        version,
        format!(
            "raytracer {} ({})\n",
            env!("CARGO_PKG_VERSION"),
            build.text()
        )
    );
    // In a checkout, the commit is HEAD's, as git itself says.
    if let Some(commit) = &build.commit {
        assert_eq!(*commit, git(repo, &["rev-parse", "--short=7", "HEAD"]));
        assert!(version.contains(&format!("(commit {commit}")), "{version}");
    } else {
        support::skipped("the_version_names_the_commit_of_this_checkout: not a git checkout");
    }
}

#[test]
fn describe_says_unknown_outside_a_checkout_and_marks_changed_sources() {
    if !support::tool_available(
        "git",
        "describe_says_unknown_outside_a_checkout_and_marks_changed_sources",
        "apt-get install git",
    ) {
        return;
    }
    // A tarball: no checkout.
    let tarball = tempfile::tempdir().unwrap();
    support::write(tarball.path(), "src/main.rs", "fn main() {}\n");
    let build = build_script::describe(tarball.path());
    assert_eq!(build.text(), "unknown commit");
    assert!(build.git_files.is_empty());

    // A checkout of its own.
    let dir = tempfile::tempdir().unwrap();
    support::write(dir.path(), "src/main.rs", "fn main() {}\n");
    support::write(dir.path(), "notes.txt", "notes\n");
    git(dir.path(), &["init", "-q", "-b", "main"]);
    git(dir.path(), &["add", "."]);
    git(dir.path(), &["commit", "-q", "-m", "first"]);
    let head = git(dir.path(), &["rev-parse", "--short=7", "HEAD"]);
    let build = build_script::describe(dir.path());
    assert_eq!(build.text(), format!("commit {head}"));
    assert!(
        build.git_files.iter().any(|f| f.ends_with("HEAD")),
        "{:?}",
        build.git_files
    );

    // A change outside what the binary is built from leaves it unmarked;
    // a change to the sources, or a new source file, marks it.
    support::write(dir.path(), "notes.txt", "more notes\n");
    assert_eq!(
        build_script::describe(dir.path()).text(),
        format!("commit {head}")
    );
    support::write(dir.path(), "src/main.rs", "fn main() { }\n");
    assert_eq!(
        build_script::describe(dir.path()).text(),
        format!("commit {head}, modified")
    );
    git(dir.path(), &["checkout", "-q", "--", "src/main.rs"]);
    support::write(dir.path(), "crates/new.rs", "\n");
    assert_eq!(
        build_script::describe(dir.path()).text(),
        format!("commit {head}, modified")
    );

    // A folder inside a checkout that is not its top (a tarball unpacked
    // in someone's repository) is not that repository's commit.
    let inner = dir.path().join("vendor/raytracer");
    support::write(&inner, "src/main.rs", "fn main() {}\n");
    assert_eq!(build_script::describe(&inner).text(), "unknown commit");
}
