//! The Slurm recipes of docs/distributed.md ("Slurm job array") and
//! docs/grading.md ("A Slurm job array"), run as written with `sbatch` on
//! a one-node cluster that `scripts/slurm-cluster.sh` starts for each test
//! and stops when it ends, passed or failed ([`Cluster`]'s `Drop`).
//!
//! The tiles: an array of 4 tiles and the stitch that depends on it give
//! the whole render, byte for byte; and when one task is cancelled while it
//! runs, the stitch names the missing tile and the command that renders
//! it, and the doc's block that renders one tile again completes the
//! frame. The class (`grade_class`'s three students): an array over the
//! student folders and the `afterany` merge give the `class.csv` of a
//! `--class` run; a student whose task fails is named by the merge, and the
//! doc's block that grades one student again completes the class; and a
//! task requeued while it runs still gives `--class`'s `class.csv`.
//!
//! Each block sets its numbers on its first lines, as parameters the doc
//! documents (32 tiles of 8 cores, which a 2-CPU node cannot run, the tile
//! or the student to do again); the tests set those (4 tiles of 1 core)
//! and change nothing else, and run the block that does one tile again
//! after the submission's `N` and `CPUS` lines, as in the shell the doc
//! speaks of. The tests take the cluster one at a time. Slurm and MUNGE
//! are Debian packages (`slurm-wlm`, `munge`) that .ci/run installs, and
//! the cluster needs root: without either the tests
//! fail under CI (`support::under_ci`) and say they were skipped otherwise.

use std::path::{Path, PathBuf};
use std::process::{Command, Output};
use std::sync::Mutex;
use std::time::{Duration, Instant};

use serde_json::Value;

use crate::grade_class::class_folder;
use crate::support;

/// How long the jobs of one recipe may take before the test fails (they
/// take seconds; the suite's other tests share the cores).
const JOBS_TIMEOUT: Duration = Duration::from_secs(90);

/// The cluster, one test at a time: each test starts its own, and two at
/// once would share the 2 CPUs that each claims.
static ONE_AT_A_TIME: Mutex<()> = Mutex::new(());

/// 500 rows between two facing mirrors, lit by 240 dim lights: about a
/// second a tile of 4 on one core, so that a task can be cancelled while
/// it runs.
fn scene() -> String {
    let mut scene = String::from(
        "camera 500\n\
         sphere dimension 1 center 0 .3 -4 reflectivity .5 color .4 .5 .6\n\
         plane dimension 40 40 center 0 0 -7 normal 0 0 1 headup 0 1 0 reflectivity .9 color .3 .3 .3\n\
         plane dimension 40 40 center 0 0 1 normal 0 0 -1 headup 0 1 0 reflectivity .9 color .3 .3 .3\n\
         plane dimension 6 6 center 0 -1 -4 normal 0 1 0 headup 0 0 1 texture wood_tex.ppm\n",
    );
    for i in 0..240 {
        let spread = |step: u32| f64::from((i * step) % 240) / 240.0;
        scene.push_str(&format!(
            "light location {:.3} {:.3} {:.3} color .008 .008 .008\n",
            -3.0 + 6.0 * spread(37),
            1.0 + 3.0 * spread(53),
            -5.0 + 5.0 * spread(71)
        ));
    }
    scene
}
const TEXTURE: &str = "P3 2 2 255\n255 0 0  0 255 0\n0 0 255  250 250 250\n";

/// Whether `program` is a file in a folder of `PATH`. The Slurm commands
/// answer no `--version` without a configuration.
fn on_path(program: &str) -> bool {
    std::env::var_os("PATH")
        .is_some_and(|path| std::env::split_paths(&path).any(|dir| dir.join(program).is_file()))
}

/// Whether the cluster can start here: Slurm, MUNGE and root. When it
/// cannot, `test` fails under CI and says it was skipped otherwise.
fn slurm_available(test: &str) -> bool {
    let install = "apt-get install slurm-wlm munge";
    for program in ["munged", "slurmd"] {
        if !support::tool_available(program, test, install) {
            return false;
        }
    }
    for program in [
        "mungekey",
        "slurmctld",
        "sbatch",
        "squeue",
        "scancel",
        "scontrol",
        "sinfo",
    ] {
        if !on_path(program) {
            assert!(
                !support::under_ci(),
                "`{program}` is not installed, and CI must run {test}: .ci/run installs it ({install})"
            );
            support::skipped(&format!("{test}: `{program}` is not installed ({install})"));
            return false;
        }
    }
    let root = support::is_root();
    if !root {
        assert!(
            !support::under_ci(),
            "{test} needs root to start its Slurm cluster (CI runs as root)"
        );
        support::skipped(&format!("{test}: the Slurm cluster needs root"));
    }
    root
}

/// A one-node Slurm cluster with its state in a temporary folder, stopped
/// (its jobs cancelled, its daemons ended by pid) when dropped.
struct Cluster {
    state: tempfile::TempDir,
}

impl Cluster {
    fn script() -> PathBuf {
        Path::new(env!("CARGO_MANIFEST_DIR")).join("scripts/slurm-cluster.sh")
    }

    /// Start the cluster and wait until its node is idle.
    fn start() -> Cluster {
        let cluster = Cluster {
            state: tempfile::Builder::new()
                .prefix("slurm-")
                .tempdir()
                .expect("temp dir"),
        };
        let output = Command::new("bash")
            .arg(Cluster::script())
            .arg("start")
            .arg(cluster.state.path())
            .output()
            .expect("run scripts/slurm-cluster.sh");
        assert!(
            output.status.success(),
            "the Slurm cluster did not start:\n{}{}",
            String::from_utf8_lossy(&output.stdout),
            String::from_utf8_lossy(&output.stderr)
        );
        cluster
    }

    fn conf(&self) -> PathBuf {
        self.state.path().join("slurm.conf")
    }

    /// A Slurm command aimed at this cluster.
    fn command(&self, program: &str, args: &[&str]) -> Command {
        let mut command = Command::new(program);
        command.args(args).env("SLURM_CONF", self.conf());
        command
    }

    /// Run a Slurm command; its stdout. Panics when it fails.
    fn run(&self, program: &str, args: &[&str]) -> String {
        let output = self.command(program, args).output().expect(program);
        assert!(
            output.status.success(),
            "{program} {args:?}: {}",
            String::from_utf8_lossy(&output.stderr)
        );
        String::from_utf8_lossy(&output.stdout).into_owned()
    }

    /// Run a recipe from the docs in `dir`, with the cluster's SLURM_CONF
    /// (the jobs it submits inherit it, and the binary's folder on PATH).
    fn recipe(&self, dir: &Path, script: &str) -> Output {
        let output = support::recipe_command(dir, script)
            .env("SLURM_CONF", self.conf())
            .output()
            .expect("run bash");
        assert!(
            output.status.success(),
            "the recipe failed:\n{script}\n{}{}",
            String::from_utf8_lossy(&output.stdout),
            String::from_utf8_lossy(&output.stderr)
        );
        output
    }

    /// Each array task or job that has not ended, as `ID STATE NAME`
    /// (`12_3 RUNNING frame-tiles`).
    fn queue(&self) -> String {
        self.run("squeue", &["--noheader", "--array", "--format=%i %T %j"])
    }

    /// Wait until no job is pending or running.
    fn wait_for_jobs(&self) {
        let start = Instant::now();
        loop {
            let queue = self.queue();
            if queue.trim().is_empty() {
                return;
            }
            if start.elapsed() > JOBS_TIMEOUT {
                panic!(
                    "the jobs did not end in {JOBS_TIMEOUT:?}:\n{queue}\n{}",
                    self.logs()
                );
            }
            std::thread::sleep(Duration::from_millis(100));
        }
    }

    /// The first array task of the job named `name` to be running.
    fn running_task(&self, name: &str) -> String {
        let start = Instant::now();
        loop {
            let queue = self.queue();
            let running = queue.lines().find_map(|line| {
                let mut fields = line.split_whitespace();
                let (id, state, job) = (fields.next()?, fields.next()?, fields.next()?);
                (job == name && state == "RUNNING" && id.contains('_')).then(|| id.to_string())
            });
            if let Some(id) = running {
                return id;
            }
            assert!(
                queue.contains(name) && start.elapsed() < JOBS_TIMEOUT,
                "no task of {name} runs:\n{queue}\n{}",
                self.logs()
            );
            std::thread::sleep(Duration::from_millis(20));
        }
    }

    /// The value of `field` (`JobState`, `Restarts`) in `scontrol show job
    /// ID`, from its `Field=value` pairs.
    fn job_field(&self, id: &str, field: &str) -> String {
        let shown = self.run("scontrol", &["show", "job", id]);
        shown
            .split_whitespace()
            .find_map(|pair| pair.strip_prefix(&format!("{field}=")))
            .unwrap_or_else(|| panic!("no {field} in job {id}:\n{shown}"))
            .to_string()
    }

    /// Wait until job `id` is in `state` (`PENDING`).
    fn wait_for_state(&self, id: &str, state: &str) {
        let start = Instant::now();
        loop {
            let now = self.job_field(id, "JobState");
            if now == state {
                return;
            }
            assert!(
                start.elapsed() < JOBS_TIMEOUT,
                "job {id} is {now}, not {state}, after {JOBS_TIMEOUT:?}\n{}",
                self.logs()
            );
            std::thread::sleep(Duration::from_millis(20));
        }
    }

    /// The controller's and the node's logs, for a failure.
    fn logs(&self) -> String {
        ["slurmctld.log", "slurmd.log"]
            .iter()
            .map(|name| {
                let text =
                    std::fs::read_to_string(self.state.path().join(name)).unwrap_or_default();
                let tail: Vec<&str> = text.lines().rev().take(30).collect();
                format!(
                    "--- {name}\n{}\n",
                    tail.into_iter().rev().collect::<Vec<_>>().join("\n")
                )
            })
            .collect()
    }
}

impl Drop for Cluster {
    fn drop(&mut self) {
        let stopped = Command::new("bash")
            .arg(Cluster::script())
            .arg("stop")
            .arg(self.state.path())
            .status();
        if !stopped.as_ref().is_ok_and(|s| s.success()) && !std::thread::panicking() {
            panic!("scripts/slurm-cluster.sh stop failed: {stopped:?}");
        }
    }
}

/// `block` with its parameter line `NAME=…` (one of its first lines, before
/// any command) set to `value`, its comment kept.
fn set_parameter(block: &str, name: &str, value: &str) -> String {
    let prefix = format!("{name}=");
    let mut found = false;
    let mut lines = Vec::new();
    let mut at_top = true;
    for line in block.lines() {
        if at_top && line.starts_with(&prefix) {
            let rest = &line[prefix.len()..];
            let comment = rest.find(char::is_whitespace).map_or("", |at| &rest[at..]);
            lines.push(format!("{prefix}{value}{comment}"));
            found = true;
            continue;
        }
        at_top &= line
            .split_once('=')
            .is_some_and(|(n, _)| n.chars().all(|c| c.is_ascii_alphabetic() || c == '_'));
        lines.push(line.to_string());
    }
    assert!(
        found,
        "the block sets no parameter {name} on its first lines:\n{block}"
    );
    lines.join("\n") + "\n"
}

/// The id in the last `Submitted batch job ID` line of a recipe's stdout.
fn last_job(output: &Output) -> String {
    String::from_utf8_lossy(&output.stdout)
        .lines()
        .filter_map(|line| line.strip_prefix("Submitted batch job "))
        .next_back()
        .unwrap_or_else(|| {
            panic!(
                "no job submitted: {}",
                String::from_utf8_lossy(&output.stdout)
            )
        })
        .trim()
        .to_string()
}

fn read(path: &Path) -> String {
    std::fs::read_to_string(path).unwrap_or_else(|e| panic!("{}: {e}", path.display()))
}

/// The three blocks of docs/distributed.md's Slurm recipe: tiles.sbatch,
/// the submission (with N and CPUS set), the tile rendered again.
fn tiles_recipe() -> (String, String, String) {
    let blocks = support::doc_recipes("docs/distributed.md", "## Slurm job array");
    let [sbatch, submit, again]: [String; 3] =
        blocks.try_into().unwrap_or_else(|b: Vec<String>| {
            panic!("the Slurm recipe has {} sh blocks, not 3", b.len())
        });
    assert!(sbatch.starts_with("#!/bin/bash\n#SBATCH"), "{sbatch}");
    let submit = set_parameter(&set_parameter(&submit, "N", "4"), "CPUS", "1");
    (sbatch, submit, again)
}

/// A folder with the scene, its texture and tiles.sbatch, and the whole
/// render (whole.png, whole.json) beside them.
fn tiles_folder(sbatch: &str) -> tempfile::TempDir {
    let dir = tempfile::tempdir().expect("temp dir");
    let d = dir.path();
    std::fs::write(d.join("scene.txt"), scene()).unwrap();
    std::fs::write(d.join("wood_tex.ppm"), TEXTURE).unwrap();
    std::fs::write(d.join("tiles.sbatch"), sbatch).unwrap();
    let whole = support::run(&[
        "render",
        d.join("scene.txt").to_str().unwrap(),
        d.join("whole.png").to_str().unwrap(),
        "--quiet",
        "--stats-json",
        d.join("whole.json").to_str().unwrap(),
    ]);
    assert!(
        whole.status.success(),
        "{}",
        String::from_utf8_lossy(&whole.stderr)
    );
    dir
}

/// frame.png is whole.png, pixel for pixel, and frame.json's counters
/// sum to the whole render's.
fn assert_frame_is_whole(d: &Path) {
    let decode = |name: &str| image::open(d.join(name)).expect(name).to_rgb8().into_raw();
    assert!(
        decode("frame.png") == decode("whole.png"),
        "frame.png is not the whole render"
    );
    let json = |name: &str| -> Value { serde_json::from_str(&read(&d.join(name))).expect(name) };
    let (frame, whole) = (json("frame.json"), json("whole.json"));
    assert_eq!(frame["tiles"], 4);
    for counter in [
        "primary_rays",
        "shadow_rays",
        "reflection_rays",
        "texture_lookups",
    ] {
        assert_eq!(frame[counter], whole[counter], "{counter}");
    }
}

#[test]
fn the_tiles_array_stitches_the_whole_render() {
    if !slurm_available("docs/distributed.md's Slurm recipe") {
        return;
    }
    let (sbatch, submit, _) = tiles_recipe();
    let dir = tiles_folder(&sbatch);
    let d = dir.path();
    let _one = ONE_AT_A_TIME.lock().unwrap_or_else(|e| e.into_inner());
    let cluster = Cluster::start();
    let output = cluster.recipe(d, &submit);
    let stitch = last_job(&output);
    cluster.wait_for_jobs();
    assert_eq!(
        cluster.job_field(&stitch, "JobState"),
        "COMPLETED",
        "{}",
        read(&d.join(format!("logs/stitch-{stitch}.out")))
    );
    assert_frame_is_whole(d);
}

#[test]
fn a_cancelled_tile_is_named_by_the_stitch_and_rendered_again() {
    if !slurm_available("docs/distributed.md's Slurm recipe") {
        return;
    }
    let (sbatch, submit, again) = tiles_recipe();
    let dir = tiles_folder(&sbatch);
    let d = dir.path();
    let _one = ONE_AT_A_TIME.lock().unwrap_or_else(|e| e.into_inner());
    let cluster = Cluster::start();
    let output = cluster.recipe(d, &submit);
    let stitch = last_job(&output);

    // The first task seen running is cancelled while it renders (a tile
    // takes about a second).
    let task = cluster.running_task("frame-tiles");
    std::thread::sleep(Duration::from_millis(300));
    cluster.run("scancel", &[&task]);
    let k = task.split('_').nth(1).expect("an array task");
    cluster.wait_for_jobs();
    assert_eq!(cluster.job_field(&task, "JobState"), "CANCELLED");
    // The other tiles, and no file of the cancelled one, not even a
    // temporary.
    let mut expected: Vec<String> = (1..=4)
        .filter(|&i| i.to_string() != k)
        .flat_map(|i| [format!("tile-{i}.json"), format!("tile-{i}.png")])
        .collect();
    expected.sort();
    assert_eq!(support::listing(&d.join("tiles")), expected);

    assert_eq!(cluster.job_field(&stitch, "JobState"), "FAILED");
    let log = read(&d.join(format!("logs/stitch-{stitch}.out")));
    assert!(log.contains(&format!("tile {k}/4 is missing")), "{log}");
    assert!(
        log.contains(&format!("raytracer render SCENE PART.png --tile {k}/4")),
        "{log}"
    );
    assert!(!d.join("frame.png").exists());

    // The doc's block, in the shell of the submission (N and CPUS set).
    assert!(again.starts_with("K="), "{again}");
    let again = format!("N=4\nCPUS=1\n{}", set_parameter(&again, "K", k));
    let output = cluster.recipe(d, &again);
    let stitch = last_job(&output);
    cluster.wait_for_jobs();
    assert_eq!(
        cluster.job_field(&stitch, "JobState"),
        "COMPLETED",
        "{}",
        read(&d.join(format!("logs/stitch-{stitch}.out")))
    );
    assert_frame_is_whole(d);
}

/// The three blocks of docs/grading.md's Slurm recipe: grade-student.sh,
/// the submission, a student graded again.
fn class_recipe() -> (String, String, String) {
    let blocks = support::doc_recipes("docs/grading.md", "### A Slurm job array");
    let [script, submit, again]: [String; 3] =
        blocks.try_into().unwrap_or_else(|b: Vec<String>| {
            panic!("the Slurm recipe has {} sh blocks, not 3", b.len())
        });
    assert!(script.starts_with("#!/bin/bash\n#SBATCH"), "{script}");
    (script, submit, again)
}

/// `grade --class` on the class in `d`, into `d/class`; its class.csv.
fn class_csv(d: &Path) -> String {
    let output = support::command(&[
        "grade", "--class", "students", "-o", "class", "--cache", "cache", "suite",
    ])
    .current_dir(d)
    .output()
    .unwrap();
    assert!(
        matches!(output.status.code(), Some(0 | 1)),
        "{}",
        String::from_utf8_lossy(&output.stderr)
    );
    read(&d.join("class/class.csv"))
}

#[test]
fn the_class_array_merges_into_the_class_csv() {
    if !slurm_available("docs/grading.md's Slurm recipe") {
        return;
    }
    let (script, submit, _) = class_recipe();
    let dir = class_folder();
    let d = dir.path();
    std::fs::write(d.join("grade-student.sh"), script).unwrap();
    let _one = ONE_AT_A_TIME.lock().unwrap_or_else(|e| e.into_inner());
    let cluster = Cluster::start();
    let output = cluster.recipe(d, &submit);
    let merge = last_job(&output);
    cluster.wait_for_jobs();
    let log = read(&d.join(format!("slurm-{merge}.out")));
    assert_eq!(cluster.job_field(&merge, "JobState"), "COMPLETED", "{log}");
    let merged = read(&d.join("reports/class.csv"));
    assert_eq!(merged.lines().count(), 4, "{merged}");
    assert_eq!(merged, class_csv(d));
}

#[test]
fn a_failed_student_is_named_by_the_merge_and_graded_again() {
    if !slurm_available("docs/grading.md's Slurm recipe") {
        return;
    }
    let (script, submit, again) = class_recipe();
    let dir = class_folder();
    let d = dir.path();
    std::fs::write(d.join("grade-student.sh"), script).unwrap();
    // dave has no tracer.txt yet: `grade --student` exits 2.
    let dave = d.join("students/dave");
    std::fs::create_dir(&dave).unwrap();
    std::fs::set_permissions(&dave, std::os::unix::fs::PermissionsExt::from_mode(0o777)).unwrap();
    let _one = ONE_AT_A_TIME.lock().unwrap_or_else(|e| e.into_inner());
    let cluster = Cluster::start();
    let output = cluster.recipe(d, &submit);
    let merge = last_job(&output);
    cluster.wait_for_jobs();
    let log = read(&d.join(format!("slurm-{merge}.out")));
    assert_eq!(cluster.job_field(&merge, "JobState"), "FAILED", "{log}");
    assert!(log.contains("dave/summary.json`: no such file"), "{log}");
    assert!(!d.join("reports/class.csv").exists());

    // dave's tracer is alice's; the doc's block grades dave alone and merges.
    for file in ["build.txt", "build.sh", "tracer.txt"] {
        std::fs::copy(d.join("students/alice").join(file), dave.join(file)).unwrap();
    }
    assert!(again.starts_with("student="), "{again}");
    let output = cluster.recipe(d, &set_parameter(&again, "student", "dave"));
    let merge = last_job(&output);
    cluster.wait_for_jobs();
    let log = read(&d.join(format!("slurm-{merge}.out")));
    assert_eq!(cluster.job_field(&merge, "JobState"), "COMPLETED", "{log}");
    let merged = read(&d.join("reports/class.csv"));
    assert_eq!(merged.lines().count(), 5, "{merged}");
    assert_eq!(merged, class_csv(d));
}

#[test]
fn a_requeued_student_task_still_completes_the_class() {
    if !slurm_available("docs/grading.md's Slurm recipe") {
        return;
    }
    let (script, submit, _) = class_recipe();
    let dir = class_folder();
    let d = dir.path();
    std::fs::write(d.join("grade-student.sh"), script).unwrap();
    // alice's build takes 2 s, so that her task, the first, runs long
    // enough to be requeued while it runs (a task takes 2 CPUs of 2: one
    // runs at a time).
    let build = d.join("students/alice/build.sh");
    std::fs::write(&build, format!("sleep 2\n{}", read(&build))).unwrap();
    let _one = ONE_AT_A_TIME.lock().unwrap_or_else(|e| e.into_inner());
    let cluster = Cluster::start();
    let output = cluster.recipe(d, &submit);
    let merge = last_job(&output);

    // The first task seen running is requeued, as for a node that failed.
    let task = cluster.running_task("grade-student.sh");
    assert!(task.ends_with("_1"), "{task}");
    cluster.run("scontrol", &["requeue", &task]);
    // Slurm holds a requeued job for about ten seconds (its `BeginTime`).
    // What is tested is that the task runs again and completes the class,
    // not when: the hold is lifted once the task is pending again.
    cluster.wait_for_state(&task, "PENDING");
    cluster.run(
        "scontrol",
        &["update", &format!("JobId={task}"), "StartTime=now"],
    );
    cluster.wait_for_jobs();
    assert_eq!(cluster.job_field(&task, "Restarts"), "1");
    assert_eq!(cluster.job_field(&task, "JobState"), "COMPLETED");
    let log = read(&d.join(format!("slurm-{merge}.out")));
    assert_eq!(cluster.job_field(&merge, "JobState"), "COMPLETED", "{log}");
    let merged = read(&d.join("reports/class.csv"));
    assert_eq!(merged.lines().count(), 4, "{merged}");
    assert_eq!(merged, class_csv(d));
}
