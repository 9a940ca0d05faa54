//! Gradescope's autograder (`make gradescope`, scripts/gradescope.sh) in a
//! real container engine configured as Gradescope's Docker is: podman with
//! runc, Docker's default seccomp profile (Debian's
//! golang-github-docker-docker-dev) and Docker's default capabilities, no
//! network, the host's root as an overlay. There no namespace can be made,
//! so `grade` runs each program without a box.
//!
//! The bundle is built on a suite of two scenes; inside one container,
//! as Gradescope does, it is unzipped into /autograder/source, `setup.sh`
//! runs once, then `run_autograder` once per submission: a C, a C++
//! (built by `make`), a Java and a Python student of tests/students/ (and
//! the Python one without shadows, who scores part of the points), an
//! attacker (tests/students/container/attacker, which tries to write
//! results.json, read the references and the suite, change the grader's
//! files and stop it, then renders honestly), a submission without
//! `tracer.txt`, and last a bundle whose binary is gone. Each student
//! scores in results.json what `grade --student` gives it outside the
//! container; the attacker scores what the honest Python student does,
//! every attack it printed is `refused`, the bundle's files are unchanged;
//! and results.json exists, a score of 0 with the reason, when grading
//! cannot run. No submission renders a reference (the bundle's cache
//! serves). A second bundle, with the course's constants
//! (`REFERENCE_OPTIONS`), grades the Python student as `grade
//! --reference-options` does outside, from its cache too; a third, with
//! the course's own tracer (`REFERENCE_TRACER`), grades the Python student
//! without shadows as `grade --reference-tracer` does outside. Podman, runc, unzip and the profile are Debian packages
//! that .ci/run installs; without them the test fails under CI.

use std::path::{Path, PathBuf};
use std::process::Command;
use std::time::Instant;

use serde_json::Value;

use crate::support::{self, bin};

/// Docker's default seccomp profile, as Debian installs it.
const PROFILE: &str =
    "/usr/share/gocode/src/github.com/docker/docker/profiles/seccomp/default.json";

/// Docker's default capabilities (podman's own defaults are fewer).
const DOCKER_CAPABILITIES: &str = "CHOWN,DAC_OVERRIDE,FSETID,FOWNER,MKNOD,NET_RAW,SETGID,SETUID,\
SETFCAP,SETPCAP,NET_BIND_SERVICE,SYS_CHROOT,KILL,AUDIT_WRITE";

/// The submissions graded, in order: the attacker first, so the honest
/// students after it show it changed nothing.
const STUDENTS: &[&str] = &[
    "attacker",
    "c",
    "cpp",
    "java",
    "python",
    "no_shadows",
    "no_tracer",
];

/// What every submission runs in the container, after `setup.sh`.
const SCRIPT: &str = r#"
set -eu
mkdir -p /autograder/source /autograder/submission /autograder/results
unzip -q /bundle/autograder.zip -d /autograder/source
bash /autograder/source/setup.sh
sums() { (cd /autograder && find source run_autograder -type f | sort | xargs sha256sum); }
sums > /out/before
for student in STUDENTS; do
    rm -rf /autograder/submission /autograder/results
    mkdir -p /autograder/submission
    cp -R "/students/$student/." /autograder/submission/
    /autograder/run_autograder > "/out/$student.log" 2>&1
    # The attacker's daemon would write after its grading.
    [ "$student" != attacker ] || sleep 5
    cp /autograder/results/results.json "/out/$student.json"
    if [ -f /autograder/report/summary.json ]; then
        cp /autograder/report/summary.json "/out/$student.summary.json"
    fi
done
sums > /out/after
rm -rf /autograder/submission /autograder/results
cp -R /students/python/. /autograder/submission/
mv /autograder/source/raytracer /autograder/source/raytracer.gone
/autograder/run_autograder > /out/no_grader.log 2>&1
cp /autograder/results/results.json /out/no_grader.json
"#;

/// One Python submission graded by a bundle with the course's options.
const OPTIONS_SCRIPT: &str = r#"
set -eu
mkdir -p /autograder/source /autograder/submission
unzip -q /bundle/autograder.zip -d /autograder/source
bash /autograder/source/setup.sh
cp -R /students/python/. /autograder/submission/
/autograder/run_autograder > /out/options.log 2>&1
cp /autograder/results/results.json /out/options.json
cp /autograder/report/summary.json /out/options.summary.json
"#;

/// Say what the test measured where `cargo test` shows it (libtest
/// captures `eprintln!` of a passing test, not a write to the handle).
fn note(what: &str) {
    use std::io::Write;
    let _ = writeln!(std::io::stderr(), "gradescope: {what}");
}

fn json(path: &Path) -> Value {
    let text = std::fs::read_to_string(path)
        .unwrap_or_else(|e| panic!("cannot read {}: {e}", path.display()));
    serde_json::from_str(&text).unwrap_or_else(|e| panic!("{}: {e}: {text}", path.display()))
}

fn copy(from: &Path, to: &Path) {
    let status = Command::new("cp")
        .arg("-R")
        .arg(from)
        .arg(to)
        .status()
        .expect("run cp");
    assert!(status.success(), "cp {} {}", from.display(), to.display());
}

/// Whether everything the test drives is here; under CI it must be.
fn engine_available() -> bool {
    const INSTALL: &str = "apt-get install podman runc unzip zip golang-github-docker-docker-dev";
    const TEST: &str = "tests/gradescope.rs";
    if !support::tool_available("podman", TEST, INSTALL)
        || !support::tool_available("runc", TEST, INSTALL)
        || !support::tool_available("zip", TEST, INSTALL)
    {
        return false;
    }
    if !Path::new(PROFILE).is_file() {
        assert!(!support::under_ci(), "{TEST}: no {PROFILE} ({INSTALL})");
        support::skipped(&format!("{TEST}: no {PROFILE} ({INSTALL})"));
        return false;
    }
    if !support::is_root() {
        assert!(!support::under_ci(), "{TEST}: podman runs as root here");
        support::skipped(&format!("{TEST}: podman runs as root here"));
        return false;
    }
    true
}

/// The students: tests/students/'s C, Java and Python correct tracers,
/// the C++ one and the attacker of tests/students/container/ (with the
/// Python tracer it renders with), and a folder without `tracer.txt`.
fn students(dir: &Path) -> PathBuf {
    let classes = Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/students");
    let students = dir.join("students");
    std::fs::create_dir_all(&students).unwrap();
    for (name, from) in [
        ("c", "tune/correct_centres"),
        ("cpp", "container/cpp"),
        ("java", "judge/correct_centres"),
        ("python", "judge/correct_centres_py"),
        ("no_shadows", "judge/no_shadows"),
        ("attacker", "container/attacker"),
    ] {
        copy(&classes.join(from), &students.join(name));
    }
    std::fs::copy(
        classes.join("judge/correct_centres_py/tracer.py"),
        students.join("attacker/tracer.py"),
    )
    .unwrap();
    support::write(&students, "no_tracer/README", "tracer.txt was forgotten\n");
    students
}

/// The course's own command for its reference tracer.
const INSTRUCTOR: &str = "./tracer {scene} {out}";

/// Where the references come from besides our renderer's defaults.
enum Reference<'a> {
    /// The course's constants (`--reference-options`).
    Options(&'a Path),
    /// The course's tracer, [`INSTRUCTOR`] run from this folder.
    Tracer(&'a Path),
}

/// `scripts/gradescope.sh`'s bundle in `out` of `suite`, with the course's
/// `reference` when given, checked to hold what Gradescope runs at its root.
fn make_bundle(out: &Path, suite: &Path, reference: Option<&Reference>) -> PathBuf {
    let mut make =
        Command::new(Path::new(env!("CARGO_MANIFEST_DIR")).join("scripts/gradescope.sh"));
    make.arg(out).env("SUITE", suite).env("RAYTRACER", bin());
    match reference {
        Some(Reference::Options(options)) => {
            make.env("REFERENCE_OPTIONS", options);
        }
        Some(Reference::Tracer(folder)) => {
            make.env("REFERENCE_TRACER", INSTRUCTOR)
                .env("REFERENCE_TRACER_DIR", folder);
        }
        None => {}
    }
    let made = make.output().expect("run scripts/gradescope.sh");
    assert!(
        made.status.success(),
        "{}",
        String::from_utf8_lossy(&made.stderr)
    );
    let listing = Command::new("unzip")
        .arg("-Z1")
        .arg(out.join("autograder.zip"))
        .output()
        .expect("run unzip");
    let listing = String::from_utf8_lossy(&listing.stdout);
    let mut roots = vec![
        "setup.sh",
        "run_autograder",
        "raytracer",
        "suite/",
        "cache/",
    ];
    match reference {
        Some(Reference::Options(_)) => roots.push("reference.json"),
        Some(Reference::Tracer(_)) => roots.extend(["reference.txt", "reference/"]),
        None => {}
    }
    for root in roots {
        assert!(
            listing.lines().any(|l| l == root),
            "{root} not at the zip's root: {listing}"
        );
    }
    out.to_path_buf()
}

/// The score `grade --student` gives `student` here, as run_autograder
/// grades (`--memory 8192`, the course's `reference`).
fn grade_outside(dir: &Path, student: &Path, suite: &Path, reference: Option<&Reference>) -> f64 {
    let report = dir.join("outside").join(student.file_name().unwrap());
    let mut command = support::command(&["grade", "--student"]);
    command
        .arg(student)
        .arg(suite)
        .arg("--cache")
        .arg(dir.join("cache"))
        .args(["--memory", "8192", "-o"])
        .arg(&report);
    match reference {
        Some(Reference::Options(options)) => {
            command.arg("--reference-options").arg(options);
        }
        Some(Reference::Tracer(folder)) => {
            command
                .args(["--reference-tracer", INSTRUCTOR])
                .current_dir(folder);
        }
        None => {}
    }
    let output = command.output().expect("run raytracer");
    assert!(
        output.status.code().is_some_and(|c| c <= 1),
        "{}: {}",
        student.display(),
        String::from_utf8_lossy(&output.stderr)
    );
    let score = json(&report.join("results.json"))["score"]
        .as_f64()
        .unwrap();
    let build = &json(&report.join("summary.json"))["build"];
    assert!(
        score > 0.0,
        "{} scores nothing outside: {build}",
        student.display()
    );
    std::fs::remove_dir_all(&report).unwrap();
    score
}

/// Run `script` with bash in a container as Gradescope's (Docker's
/// default seccomp profile and capabilities, no network), the bundle in
/// /bundle, the students in /students and `out` in /out.
fn in_container(bundle: &Path, students: &Path, out: &Path, script: &str) -> std::process::Output {
    let volume = |from: &Path, to: &str| format!("{}:{to}", from.display());
    Command::new("timeout")
        .args(["900", "podman", "run", "--rm", "--runtime", "runc"])
        .args(["--cgroup-manager=cgroupfs", "--network", "none"])
        .args(["--security-opt", &format!("seccomp={PROFILE}")])
        .args(["--cap-drop", "all", "--cap-add", DOCKER_CAPABILITIES])
        .args([
            "--ulimit",
            "nofile=4096:4096",
            "--ulimit",
            "nproc=4096:4096",
        ])
        // The host's graders lease uids in the host's /run: a range
        // they do not use, or one's lease would kill the other's runs.
        .args(["-e", "GRADE_UIDS=65200-65209"])
        .args(["-v", &volume(bundle, "/bundle:ro")])
        .args(["-v", &volume(students, "/students:ro")])
        .args(["-v", &volume(out, "/out")])
        .args(["--rootfs", "/:O", "bash", "-c", script])
        .output()
        .expect("run podman")
}

#[test]
fn gradescope_bundle_grades_in_dockers_default_container() {
    if !engine_available() {
        return;
    }
    let dir = tempfile::tempdir().unwrap();
    let dir = dir.path();
    // Two scenes of the built-in suite, with the texture one needs.
    let full = dir.join("full");
    assert!(
        support::run(&["grade", "--export-suite", full.to_str().unwrap()])
            .status
            .success()
    );
    let suite = dir.join("suite");
    std::fs::create_dir(&suite).unwrap();
    for file in ["sample.txt", "wood_tex.ppm", "colours.txt"] {
        std::fs::copy(full.join(file), suite.join(file)).unwrap();
    }
    let students = students(dir);

    let bundle = make_bundle(&dir.join("bundle"), &suite, None);
    let outside: Vec<f64> = STUDENTS[..6]
        .iter()
        .map(|student| grade_outside(dir, &students.join(student), &suite, None))
        .collect();

    let out = dir.join("out");
    std::fs::create_dir(&out).unwrap();
    let started = Instant::now();
    let ran = in_container(
        &bundle,
        &students,
        &out,
        &SCRIPT.replace("STUDENTS", &STUDENTS.join(" ")),
    );
    let seconds = started.elapsed().as_secs_f64();
    assert!(
        ran.status.success(),
        "the container failed: {}\n{}",
        String::from_utf8_lossy(&ran.stdout),
        String::from_utf8_lossy(&ran.stderr)
    );
    note(&format!("the container ran for {seconds:.0} s"));

    let log = |student: &str| std::fs::read_to_string(out.join(format!("{student}.log")));
    for (student, score) in STUDENTS[..6].iter().zip(&outside) {
        let results = json(&out.join(format!("{student}.json")));
        let inside = results["score"].as_f64().unwrap();
        let summary = json(&out.join(format!("{student}.summary.json")));
        let mechanisms = &summary["sandbox"]["mechanisms"];
        note(&format!(
            "{student}: {inside} inside, {score} outside, {mechanisms}"
        ));
        assert!(
            (inside - score).abs() < 1e-9,
            "{student}: {inside} inside, {score} outside: {results}\n{:?}\nbuild: {}",
            log(student),
            summary["build"]
        );
        assert_eq!(summary["sandbox"]["boxed"], false, "{student}: {summary}");
        for mechanism in ["uid", "landlock", "seccomp", "rlimits", "no_new_privs"] {
            assert!(
                mechanisms
                    .as_array()
                    .unwrap()
                    .iter()
                    .any(|m| m == mechanism),
                "{student}: {mechanisms}"
            );
        }
    }

    // The attacker gains nothing and scores as the honest Python student.
    assert_eq!(
        outside[0], outside[4],
        "the attacker renders as python does"
    );
    let attacker = std::fs::read_to_string(out.join("attacker.json")).unwrap();
    assert!(!attacker.contains("gained:"), "{attacker}");
    for attack in [
        "write results.json",
        "replace results.json",
        "remove the results folder",
        "read the references",
        "list the references",
        "read the suite",
        "read the suite through the grader's root",
        "change run_autograder",
        "replace the grader",
        "change the bundle's run_autograder",
        "stop the grader",
        "write /tmp",
    ] {
        assert!(
            attacker.contains(&format!("refused: {attack}")),
            "{attack}: {attacker}"
        );
    }
    assert_eq!(
        std::fs::read_to_string(out.join("before")).unwrap(),
        std::fs::read_to_string(out.join("after")).unwrap(),
        "the grader's files changed"
    );

    // Grading that cannot run still gives a result of 0 with the reason.
    for (case, reason) in [
        ("no_tracer", "tracer.txt"),
        ("no_grader", "raytracer grade exited 127"),
    ] {
        let results = json(&out.join(format!("{case}.json")));
        assert_eq!(results["score"], 0.0, "{case}: {results}");
        let output = results["output"].as_str().unwrap();
        assert!(output.contains("grading could not run"), "{case}: {output}");
        assert!(output.contains(reason), "{case}: {output}");
    }

    // The course's constants: the bundle's references are rendered with
    // them, and run_autograder grades with them, from the cache alone.
    for student in STUDENTS[..6].iter() {
        let log = log(student).unwrap();
        assert!(
            !log.contains("rendered"),
            "{student} rendered a reference: {log}"
        );
    }
    let options = support::write(dir, "course.json", r#"{"ambient": 0.3}"#);
    let options = Path::new(&options);
    let options = Reference::Options(options);
    let bundle = make_bundle(&dir.join("bundle_options"), &suite, Some(&options));
    let expected = grade_outside(dir, &students.join("python"), &suite, Some(&options));
    let ran = in_container(&bundle, &students, &out, OPTIONS_SCRIPT);
    assert!(
        ran.status.success(),
        "{}",
        String::from_utf8_lossy(&ran.stderr)
    );
    let results = json(&out.join("options.json"));
    note(&format!(
        "python with the course's constants: {} inside, {expected} outside",
        results["score"]
    ));
    assert_eq!(results["score"].as_f64(), Some(expected), "{results}");
    let log = std::fs::read_to_string(out.join("options.log")).unwrap();
    assert!(!log.contains("rendered"), "a reference was rendered: {log}");
    let rmse = |summary: &str| {
        let summary = json(&out.join(summary));
        let mut scenes: Vec<(String, String)> = summary["scenes"]
            .as_array()
            .unwrap()
            .iter()
            .map(|s| (s["scene"].to_string(), s["rmse"].to_string()))
            .collect();
        scenes.sort();
        scenes
    };
    assert_ne!(
        rmse("python.summary.json"),
        rmse("options.summary.json"),
        "the course's constants changed nothing"
    );

    // The course's own tracer (the C student's, built here): the bundle
    // caches its images, and run_autograder grades against them as
    // `grade --reference-tracer` does outside, rendering nothing.
    let instructor = dir.join("instructor");
    std::fs::create_dir(&instructor).unwrap();
    let classes = Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/students");
    let built = Command::new("cc")
        .args(["-O2", "-o"])
        .arg(instructor.join("tracer"))
        .arg(classes.join("tune/correct_centres/tracer.c"))
        .arg("-lm")
        .status()
        .expect("run cc");
    assert!(built.success());
    let tracer = Reference::Tracer(&instructor);
    let bundle = make_bundle(&dir.join("bundle_tracer"), &suite, Some(&tracer));
    let expected = grade_outside(dir, &students.join("no_shadows"), &suite, Some(&tracer));
    let script = OPTIONS_SCRIPT
        .replace("/students/python/", "/students/no_shadows/")
        .replace("options.", "instructor.");
    let ran = in_container(&bundle, &students, &out, &script);
    assert!(
        ran.status.success(),
        "{}",
        String::from_utf8_lossy(&ran.stderr)
    );
    let results = json(&out.join("instructor.json"));
    note(&format!(
        "no_shadows against the course's tracer: {} inside, {expected} outside",
        results["score"]
    ));
    assert_eq!(results["score"].as_f64(), Some(expected), "{results}");
    let log = std::fs::read_to_string(out.join("instructor.log")).unwrap();
    assert!(!log.contains("rendered"), "a reference was rendered: {log}");
}
