//! A student who fills the disk, in a box and without one: the run's
//! writable space is bounded in bytes and in files whatever the grader
//! can mount.
//!
//! In a box a scene's working folder is a tmpfs of `--disk` MiB; without
//! one (`--unprotected`, as in Gradescope's containers, made here by a
//! seccomp filter that refuses namespaces) the grader watches the
//! working folder, its private temporary folder inside it, and kills the
//! run when they hold more (crates/box/src/quota.rs). Each kind of run a
//! grader may be (root, an ordinary user; boxed or not) grades one class:
//! a student who fills the disk with many small files (in a folder it
//! closes to listing, which the grader must reopen to count), one who
//! makes more files than the bound in its temporary folder, one who
//! writes through the descriptor of a file it removed, and an honest one;
//! and one student whose build fills its folder, which lies on the
//! grader's disk in a box too.

use std::ffi::OsStr;
use std::os::unix::fs::PermissionsExt;
use std::path::{Path, PathBuf};
use std::process::{Output, Stdio};

use serde_json::Value;

use crate::support;
use crate::support::grading::{grader, open_folder, student_binary, Kind};
use crate::support::namespaces::without_namespaces;

/// Writes 64 KiB files, far past the disk space, into a folder its owner
/// may not list (`chmod 300`), then renders.
const SMALL_FILES: &str = "\
mkdir hidden; chmod 300 hidden\n\
for i in $(seq 4096); do head -c 65536 /dev/zero > hidden/fill$i 2>/dev/null || break; done\n\
exec ./renderer render \"$1\" \"$2\"\n";

/// Makes empty files in its temporary folder (the working folder in a
/// box, where `TMPDIR` is not set) past the bound on files, then renders.
const MANY_FILES: &str = "\
cd \"${TMPDIR:-.}\"; for i in $(seq 65536); do : 2>/dev/null > f$i || break; done; cd - >/dev/null\n\
exec ./renderer render \"$1\" \"$2\"\n";

/// Writes far past the disk space into a file it has removed, holding
/// the disk for a while through the descriptor, then renders.
const REMOVED_FILE: &str = "\
exec 3>held; rm held; head -c 67108864 /dev/zero >&3 2>/dev/null; sleep 5\n\
exec ./renderer render \"$1\" \"$2\"\n";

const HONEST: &str = "exec ./renderer render \"$1\" \"$2\"\n";

/// Every kind of run this machine can try: (as root, without a box).
fn kinds() -> Vec<(bool, bool)> {
    let mut kinds = Vec::new();
    if support::is_root() {
        kinds.extend([(true, false), (true, true)]);
        if !support::tool_available(
            "setpriv",
            "the user-run disk attacks",
            "apt-get install util-linux",
        ) {
            return kinds;
        }
    } else {
        assert!(!support::under_ci(), "CI runs as root");
        support::skipped("the root-run disk attacks: the tests do not run as root");
    }
    kinds.extend([(false, false), (false, true)]);
    kinds
}

/// The disk bound each run gets: each student's folder (its copy of the
/// renderer, whose size the build profile sets) fits it with 8 MiB to
/// spare; and the reason a run past it is given.
fn disk_bound() -> (String, String) {
    let renderer = std::fs::metadata(student_binary()).unwrap().len();
    let disk = ((renderer >> 20) + 1 + 8).to_string();
    let full = format!("the run's disk space ({disk} MiB) was full");
    (disk, full)
}

/// A temporary folder in `d` that every account may write, as /tmp is.
fn shared_tmp(d: &Path) -> PathBuf {
    let tmp = d.join("tmp");
    std::fs::create_dir(&tmp).unwrap();
    std::fs::set_permissions(&tmp, std::fs::Permissions::from_mode(0o1777)).unwrap();
    tmp
}

/// `grade` of `what` (`--student FOLDER` or `--class FOLDER`) on `d`'s
/// suite, as root or as an ordinary user, boxed or `--unprotected` (made
/// to find no namespace), with `disk` MiB and `tmp` as its `TMPDIR`;
/// the report goes to `report`.
fn grade(
    d: &Path,
    (root, unprotected): (bool, bool),
    disk: &str,
    tmp: &Path,
    what: [&OsStr; 2],
    report: &Path,
) -> Output {
    let mut command = grader(if root { Kind::Root } else { Kind::User });
    command
        .args(["grade", "--disk", disk, "--timeout", "60"])
        .args(what)
        .arg("-o")
        .arg(report)
        .arg("--cache")
        .arg(d.join(format!("cache-{root}")))
        .arg(d.join("suite"))
        .env("HOME", d)
        .env("TMPDIR", tmp)
        .stdin(Stdio::null());
    if unprotected {
        command.arg("--unprotected");
        without_namespaces(&mut command);
    }
    command.output().unwrap()
}

/// The class: each student's folder holds `tracer.sh` and a copy of the
/// renderer; the suite one small scene.
fn class(d: &Path) {
    std::fs::create_dir_all(d.join("suite")).unwrap();
    std::fs::write(
        d.join("suite/ball.txt"),
        "camera 16\nsphere\n  dimension 1\n  center 0 0 -5\n  color .9 .6 .3\n",
    )
    .unwrap();
    for (name, script) in [
        ("a-small-files", SMALL_FILES),
        ("b-many-files", MANY_FILES),
        ("c-removed-file", REMOVED_FILE),
        ("d-honest", HONEST),
    ] {
        let folder = d.join("class").join(name);
        std::fs::create_dir_all(&folder).unwrap();
        std::fs::write(folder.join("tracer.txt"), "bash tracer.sh {scene} {out}\n").unwrap();
        std::fs::write(folder.join("tracer.sh"), script).unwrap();
        std::fs::copy(student_binary(), folder.join("renderer")).unwrap();
        for path in [folder, d.join("class")] {
            std::fs::set_permissions(&path, std::fs::Permissions::from_mode(0o755)).unwrap();
        }
    }
}

/// A build that fills its folder past the disk space: in a box too its
/// folder lies on the grader's disk, so the grader's quota holds it in
/// every kind of run; the build is stopped, its reason says the disk was
/// full, and nothing of it is left.
#[test]
fn a_build_that_fills_its_folder_is_stopped_and_told_in_every_kind_of_run() {
    let dir = open_folder("grade-disk-build-");
    let d = dir.path();
    class(d);
    let student = d.join("class/d-honest");
    std::fs::write(student.join("build.txt"), "bash build.sh\n").unwrap();
    std::fs::write(
        student.join("build.sh"),
        "for i in $(seq 4096); do head -c 65536 /dev/zero > fill$i || exit 1; done\n",
    )
    .unwrap();
    let (disk, full) = disk_bound();
    let tmp = shared_tmp(d);
    for (root, unprotected) in kinds() {
        let run = format!("root {root}, unprotected {unprotected}");
        let report = d.join(format!("report-{root}-{unprotected}"));
        let what = [OsStr::new("--student"), student.as_os_str()];
        let output = grade(d, (root, unprotected), &disk, &tmp, what, &report);
        let stderr = String::from_utf8_lossy(&output.stderr);
        let summary: Value = serde_json::from_slice(
            &std::fs::read(report.join("summary.json"))
                .unwrap_or_else(|_| panic!("{run}: no summary: {stderr}")),
        )
        .unwrap();
        let build = &summary["build"];
        assert_eq!(build["ok"], false, "{run}: {build}");
        let reason = build["reason"].as_str().unwrap_or_default();
        assert!(reason.contains(&full), "{run}: {build}");
        assert_ne!(build["reason"], "wall-clock time limit", "{run}: {build}");
        let left: Vec<_> = std::fs::read_dir(&tmp).unwrap().flatten().collect();
        assert!(left.is_empty(), "{run}: left in TMPDIR: {left:?}");
    }
}

/// The scene of `student` in the class report `report`.
fn scene(report: &Path, student: &str) -> Value {
    let summary: Value =
        serde_json::from_slice(&std::fs::read(report.join(student).join("summary.json")).unwrap())
            .unwrap();
    summary["scenes"][0].clone()
}

/// Each student who fills the disk is stopped before the timeout (without
/// a box, killed by the watch; in a box, its writes fail) and told the
/// run's disk space was full; the honest student after them matches; the
/// class is graded to the end and nothing of a run is left in `TMPDIR`.
#[test]
fn a_run_that_fills_its_disk_space_is_stopped_and_told_in_every_kind_of_run() {
    let dir = open_folder("grade-disk-");
    let d = dir.path();
    class(d);
    let (disk, full) = disk_bound();
    let tmp = shared_tmp(d);
    let class = d.join("class");
    for (root, unprotected) in kinds() {
        let run = format!("root {root}, unprotected {unprotected}");
        let report = d.join(format!("report-{root}-{unprotected}"));
        let what = [OsStr::new("--class"), class.as_os_str()];
        let output = grade(d, (root, unprotected), &disk, &tmp, what, &report);
        let stderr = String::from_utf8_lossy(&output.stderr);
        assert_eq!(output.status.code(), Some(1), "{run}: {stderr}");
        for student in ["a-small-files", "b-many-files", "c-removed-file"] {
            let scene = scene(&report, student);
            let reason = scene["reason"].as_str().unwrap_or_default();
            assert!(reason.contains(&full), "{run}, {student}: {scene}");
            assert_ne!(scene["status"], "match", "{run}, {student}: {scene}");
            assert_ne!(scene["status"], "timeout", "{run}, {student}: {scene}");
        }
        let honest = scene(&report, "d-honest");
        assert_eq!(honest["status"], "match", "{run}: {honest}");
        assert!(honest["reason"].is_null(), "{run}: {honest}");
        let csv = std::fs::read_to_string(report.join("class.csv")).unwrap();
        assert_eq!(csv.lines().count(), 5, "{run}: {csv}");
        let left: Vec<_> = std::fs::read_dir(&tmp).unwrap().flatten().collect();
        assert!(left.is_empty(), "{run}: left in TMPDIR: {left:?}");
    }
}
