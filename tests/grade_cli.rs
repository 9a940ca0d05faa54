//! `raytracer grade` with student programs written here: one right, one
//! whose sphere moved, one darker, one of another size, and the hostile
//! ones (a crash, a hang, a CPU spin, no image, garbage, a fork bomb, a
//! huge write, a stdout flood, a network connection). Each reaches its
//! status within its limits and leaves no process behind. Our own tracer
//! on the built-in suite matches every scene, and the report is complete:
//! summary.json valid against docs/grade-summary.schema.json, results.json
//! in Gradescope's format, index.html with one row per scene.

use std::net::TcpListener;
use std::os::unix::fs::PermissionsExt;
use std::path::Path;
use std::time::{Duration, Instant};

use serde_json::Value;

use crate::support::grading::{self, open_folder, student_binary, Kind};
use crate::support::{self, run};

/// A small scene: a sphere on a lit floor, 32 pixels.
const SCENE: &str = "camera 32\n\nsphere\n  dimension 1\n  center 0 0 -5\n  color .9 .6 .3\n\n\
plane\n  dimension 20 40\n  center 0 -1 -10\n  normal 0 1 0\n  headup 0 0 -1\n  color .8 .8 .8\n\n\
light\n  location 6 4 -3\n  color 1 1 1\n";

/// A test's folder ([`grading::Case`]): the one-scene suite and the
/// student's script, graded under tight limits, as the tests run; each
/// grading checks that the run left no process.
struct Case(grading::Case);

impl Case {
    fn new(script: &str) -> Case {
        let case = grading::Case::new("grade-case-", SCENE, script).with_defaults(&[
            ("--timeout", "3"),
            ("--max-file-size", "8"),
            ("--max-output", "4"),
        ]);
        Case(case)
    }

    fn path(&self) -> &Path {
        self.0.path()
    }

    /// Grade the student with `extra` options; the exit code, the one
    /// scene's summary entry and the seconds `grade` took.
    fn grade(&self, extra: &[&str]) -> (i32, Value, f64) {
        self.grade_tracer(&self.0.tracer(), extra)
    }

    /// [`Case::grade`] with the tracer command `tracer` instead of the
    /// student script.
    fn grade_tracer(&self, tracer: &str, extra: &[&str]) -> (i32, Value, f64) {
        let start = Instant::now();
        let (code, scene, _) = self.0.grade(Kind::Tests, Some(tracer), extra, &[]);
        let seconds = start.elapsed().as_secs_f64();
        let summary = self.0.summary(Kind::Tests, "");
        assert_eq!(summary["scenes"].as_array().unwrap().len(), 1);
        assert_no_process_left(self.path());
        (code, scene, seconds)
    }
}

/// No process runs the case's script or in the folder it ran in.
fn assert_no_process_left(dir: &Path) {
    let marker = dir.to_string_lossy().into_owned();
    let workdir = std::fs::read_to_string(dir.join("workdir")).unwrap_or_default();
    let workdir = workdir.trim();
    // The kill is synchronous, but a killed process may take a moment to go.
    let deadline = Instant::now() + Duration::from_secs(2);
    loop {
        let left: Vec<String> = std::fs::read_dir("/proc")
            .unwrap()
            .flatten()
            .filter(|e| e.file_name().to_string_lossy().parse::<u32>().is_ok())
            .filter_map(|e| {
                let stat = std::fs::read_to_string(e.path().join("stat")).ok()?;
                let state = stat[stat.rfind(')')? + 2..].chars().next()?;
                let cmdline = std::fs::read(e.path().join("cmdline")).ok()?;
                let cmdline = String::from_utf8_lossy(&cmdline).replace('\0', " ");
                let cwd = std::fs::read_link(e.path().join("cwd")).unwrap_or_default();
                let cwd = cwd.to_string_lossy();
                let ours =
                    cmdline.contains(&marker) || !workdir.is_empty() && cwd.starts_with(workdir);
                (ours && state != 'Z').then(|| format!("{cmdline} ({state}) in {cwd}"))
            })
            .collect();
        if left.is_empty() {
            return;
        }
        assert!(Instant::now() < deadline, "processes left behind: {left:?}");
        std::thread::sleep(Duration::from_millis(50));
    }
}

fn status(scene: &Value) -> (&str, &str) {
    (
        scene["status"].as_str().unwrap(),
        scene["reason"].as_str().unwrap_or(""),
    )
}

#[test]
fn a_right_tracer_matches() {
    let case = Case::new("exec \"$RAYTRACER\" render \"$1\" \"$2\"");
    let (code, scene, _) = case.grade(&[]);
    assert_eq!(status(&scene), ("match", ""), "{scene}");
    assert_eq!(code, 0);
    assert_eq!(scene["coverage_iou"], 1.0);
    assert_eq!(scene["flip_mean"], 0.0);
    assert_eq!(scene["exit_code"], 0);
    assert_eq!(scene["score"], scene["points"]);
}

#[test]
fn moved_darker_and_resized_images_differ_for_their_reasons() {
    // A moved sphere fails geometry (its other aspects pass); another hue
    // fails shading alone, which weighs what geometry and shadows weigh (a
    // third each); a darker scene of the same hues (every colour halved,
    // as a diffuse and an ambient weight of half ours give) is a reading
    // of the shading constants and matches. (One object darker than the
    // others is not: a tracer has one diffuse weight for the scene.)
    for (edit, reason, score) in [
        ("s/center 0 0 -5/center .5 0 -5/", "geometry", 0.666667),
        ("s/color .9 .6 .3/color .3 .6 .9/", "shading", 0.666667),
        (
            "s/color .9 .6 .3/color .45 .3 .15/; s/color .8 .8 .8/color .4 .4 .4/",
            "",
            1.0,
        ),
        (
            "s/camera 32/camera 40/",
            "size: expected 32 × 32, found 40 × 40 (not decoded: larger than the camera)",
            0.0,
        ),
    ] {
        let case = Case::new(&format!(
            "sed '{edit}' \"$1\" > edited.txt && exec \"$RAYTRACER\" render edited.txt \"$2\""
        ));
        let (code, scene, _) = case.grade(&[]);
        let expected = if reason.is_empty() {
            "match"
        } else {
            "differs"
        };
        assert_eq!(status(&scene), (expected, reason), "{scene}");
        assert_eq!(code, i32::from(!reason.is_empty()));
        assert_eq!(scene["score"], score, "{scene}");
    }
}

#[test]
fn a_crash_is_reported_with_its_signal_and_stderr() {
    let case = Case::new("echo 'about to fail' >&2; kill -SEGV $$");
    let (code, scene, _) = case.grade(&[]);
    assert_eq!(
        status(&scene),
        ("crashed", "signal 11 (SIGSEGV)"),
        "{scene}"
    );
    assert_eq!(code, 1);
    assert_eq!(scene["signal"], 11);
    assert!(scene["stderr"].as_str().unwrap().contains("about to fail"));

    let case = Case::new("exit 3");
    let (_, scene, _) = case.grade(&[]);
    assert_eq!(status(&scene), ("crashed", "exit code 3"), "{scene}");
}

/// A program that is not there, one without `chmod +x`, and a name no
/// folder of `PATH` holds read the same, whoever the grader runs as (the
/// search may meet a folder the program's user may not enter: `EACCES`).
#[test]
fn a_program_that_cannot_start_says_why_in_one_way() {
    let case = Case::new("exit 0");
    let d = case.path();
    std::fs::write(d.join("plain.sh"), "#!/bin/sh\n").unwrap();
    std::fs::set_permissions(d.join("plain.sh"), std::fs::Permissions::from_mode(0o644)).unwrap();
    for program in [
        d.join("missing").display().to_string(),
        d.join("plain.sh").display().to_string(),
        "no-such-tracer-anywhere".to_string(),
    ] {
        let (code, scene, _) = case.grade_tracer(&format!("{program} {{scene}} {{out}}"), &[]);
        assert_eq!(code, 1);
        assert_eq!(
            status(&scene),
            (
                "crashed",
                format!("cannot start: no program `{program}` it may run (it is missing, not executable: `chmod +x`, or in a folder its user may not enter)").as_str()
            ),
            "{scene}"
        );
    }
}

#[test]
fn a_hang_is_killed_at_the_timeout_with_its_children() {
    let case = Case::new("sleep 1000 & sleep 1000");
    let (code, scene, seconds) = case.grade(&[]);
    assert_eq!(
        status(&scene),
        ("timeout", "wall-clock time limit"),
        "{scene}"
    );
    assert_eq!(code, 1);
    let ran = scene["seconds"].as_f64().unwrap();
    assert!((3.0..6.0).contains(&ran), "{ran}");
    assert!(seconds < 10.0, "{seconds}");
}

/// The reason names the CPU limit, not the wall-clock one: the limit on
/// CPU time acted first. How long a second of CPU takes on the wall clock
/// depends on the machine's load (on two loaded cores, over 15 s), so the
/// wall-clock timeout is far above it and no wall time is asserted.
#[test]
fn a_cpu_spin_stops_at_the_cpu_limit() {
    let case = Case::new("while :; do :; done");
    let (_, scene, _) = case.grade(&["--cpu", "1", "--timeout", "120"]);
    assert_eq!(
        status(&scene),
        ("timeout", "CPU time limit (SIGXCPU)"),
        "{scene}"
    );
}

#[test]
fn no_image_and_garbage_have_their_statuses() {
    let case = Case::new("echo 'rendered nothing'");
    let (_, scene, _) = case.grade(&[]);
    assert_eq!(status(&scene).0, "no_image", "{scene}");
    assert_eq!(scene["stdout"], "rendered nothing\n");

    let case = Case::new("printf 'P6\\n32 32\\n255\\nshort' > \"$2\"");
    let (_, scene, _) = case.grade(&[]);
    assert_eq!(status(&scene).0, "bad_image", "{scene}");
    assert!(
        status(&scene).1.contains("ends before its last texel"),
        "{scene}"
    );

    let case = Case::new("head -c 5000 /dev/urandom > \"$2\"");
    let (_, scene, _) = case.grade(&[]);
    assert_eq!(status(&scene).0, "bad_image", "{scene}");
}

#[test]
fn a_fork_bomb_is_held_by_the_process_limit_and_killed_whole() {
    let case = Case::new("bomb() { bomb | bomb & }; bomb; sleep 1000");
    let (_, scene, seconds) = case.grade(&["--max-processes", "32"]);
    assert_eq!(status(&scene).0, "timeout", "{scene}");
    assert!(seconds < 15.0, "{seconds}");
}

#[test]
fn a_huge_write_stops_at_the_file_size_limit() {
    let case = Case::new("exec head -c 4000000000 /dev/zero > \"$2\"");
    let (_, scene, seconds) = case.grade(&[]);
    assert_eq!(
        status(&scene),
        ("crashed", "signal 25 (SIGXFSZ: file size limit)"),
        "{scene}"
    );
    assert!(seconds < 10.0, "{seconds}");
}

#[test]
fn a_stdout_flood_is_cut_at_the_bound() {
    let case = Case::new("yes flood | head -c 50000000; exec \"$RAYTRACER\" render \"$1\" \"$2\"");
    let (_, scene, _) = case.grade(&[]);
    assert_eq!(status(&scene).0, "match", "{scene}");
    let stdout = scene["stdout"].as_str().unwrap();
    assert!(stdout.starts_with("flood\nflood\n"));
    assert!(
        stdout.ends_with("[… 49995904 more bytes not kept]"),
        "{}",
        &stdout[stdout.len() - 60..]
    );
}

#[test]
fn the_network_is_out_of_reach() {
    let listener = TcpListener::bind("127.0.0.1:0").unwrap();
    listener.set_nonblocking(true).unwrap();
    let port = listener.local_addr().unwrap().port();
    let case = Case::new(&format!(
        "if (exec 3<>/dev/tcp/127.0.0.1/{port}) 2>/dev/null; then echo connected > \"$2\"; exit 0; fi\n\
         exec \"$RAYTRACER\" render \"$1\" \"$2\""
    ));
    let (_, scene, _) = case.grade(&[]);
    let report: Value = serde_json::from_slice(
        &std::fs::read(case.0.report(Kind::Tests).join("summary.json")).unwrap(),
    )
    .unwrap();
    let isolated = report["sandbox"]["network_isolated"].as_bool().unwrap();
    if !isolated && !crate::support::under_ci() {
        crate::support::skipped(
            "the network isolation check: no network namespace here, so the connection is not expected to fail",
        );
        return;
    }
    assert!(
        isolated,
        "CI runs as root, where a network namespace can always be had"
    );
    assert_eq!(status(&scene).0, "match", "{scene}");
    assert!(
        listener.accept().is_err(),
        "the program reached the test's port"
    );
}

#[test]
fn usage_errors_exit_2() {
    let output = run(&["grade", "-o", "r"]);
    assert_eq!(output.status.code(), Some(2));
    let dir = tempfile::tempdir().unwrap();
    let unused = dir.path().join("unused");
    let output = run(&["grade", "--tracer", "a 'b", "-o", unused.to_str().unwrap()]);
    assert_eq!(output.status.code(), Some(2));
    assert!(String::from_utf8_lossy(&output.stderr).contains("cannot split"));
    assert!(!unused.exists());
    // A tracer told neither the scene nor where to write is refused at
    // once, before any scene runs, with the form to write.
    for (tracer, missing) in [
        ("raytracer render", "found no `{scene}` and no `{out}`"),
        ("./tracer {scene} out.ppm", "found no `{out}`"),
    ] {
        let output = run(&["grade", "--tracer", tracer, "-o", unused.to_str().unwrap()]);
        let stderr = String::from_utf8_lossy(&output.stderr);
        assert_eq!(output.status.code(), Some(2), "{stderr}");
        // The words, whatever the width the message was wrapped at.
        let words: Vec<&str> = stderr.split_whitespace().filter(|w| *w != "│").collect();
        let words = words.join(" ");
        assert!(words.contains("usage::tracer"), "{stderr}");
        assert!(words.contains(missing), "{stderr}");
        assert!(
            words.contains("e.g. `--tracer './mytracer {scene} {out}'`"),
            "{stderr}"
        );
        assert!(!unused.exists());
    }
    // A script beside the program (docs/grading.md's forms) would be
    // missing from every box: refused at once, with the --student form.
    support::write(dir.path(), "tracer.py", "");
    support::write(dir.path(), "run.sh", "");
    for (tracer, word) in [
        ("python3 tracer.py {scene} {out}", "tracer.py"),
        ("java -cp . Main {scene} {out}", "."),
        ("sh run.sh {scene} {out}", "run.sh"),
    ] {
        let output = support::command(&["grade", "--tracer", tracer, "-o"])
            .arg(&unused)
            .current_dir(dir.path())
            .output()
            .expect("run raytracer");
        let stderr = String::from_utf8_lossy(&output.stderr);
        assert_eq!(output.status.code(), Some(2), "{stderr}");
        let words: Vec<&str> = stderr.split_whitespace().filter(|w| *w != "│").collect();
        let words = words.join(" ");
        assert!(words.contains("usage::tracer_files"), "{stderr}");
        assert!(
            words.contains(&format!("names `{word}`, a file beside it")),
            "{stderr}"
        );
        assert!(
            words.contains("raytracer grade --student FOLDER"),
            "{stderr}"
        );
        assert!(
            words.contains(&format!("put `{tracer}` in its `tracer.txt`")),
            "{stderr}"
        );
        assert!(!unused.exists());
    }
    let bad = dir.path().join("bad.txt");
    std::fs::write(&bad, "camera\n").unwrap();
    let report = dir.path().join("r");
    let output = run(&[
        "grade",
        "--tracer",
        "true {scene} {out}",
        "-o",
        report.to_str().unwrap(),
        "--cache",
        dir.path().join("c").to_str().unwrap(),
        bad.to_str().unwrap(),
    ]);
    let stderr = String::from_utf8_lossy(&output.stderr);
    assert_eq!(output.status.code(), Some(2), "{stderr}");
    assert!(stderr.contains("has errors"), "{stderr}");
}

/// Our tracer on the built-in suite: every scene matches, the second run
/// renders no reference, and the report is whole.
#[test]
fn our_tracer_matches_the_built_in_suite() {
    let dir = open_folder("grade-suite-");
    let report = dir.path().join("report");
    let cache = dir.path().join("cache");
    let tracer = format!("{} render {{scene}} {{out}}", student_binary().display());
    let grade = || {
        run(&[
            "grade",
            "--tracer",
            &tracer,
            "-o",
            report.to_str().unwrap(),
            "--cache",
            cache.to_str().unwrap(),
            "--jobs",
            "2",
        ])
    };
    let first = grade();
    let stderr = String::from_utf8_lossy(&first.stderr);
    assert_eq!(first.status.code(), Some(0), "{stderr}");
    assert!(stderr.contains("rendered 30 reference images"), "{stderr}");
    let second = grade();
    assert_eq!(second.status.code(), Some(0));
    assert!(
        second.stderr.is_empty(),
        "{}",
        String::from_utf8_lossy(&second.stderr)
    );

    let summary: Value =
        serde_json::from_slice(&std::fs::read(report.join("summary.json")).unwrap()).unwrap();
    let scenes = summary["scenes"].as_array().unwrap();
    assert_eq!(scenes.len(), 30);
    assert!(scenes.iter().all(|s| s["status"] == "match"), "{summary}");
    assert_eq!(summary["score"], summary["max_score"]);

    let schema_path = Path::new(env!("CARGO_MANIFEST_DIR")).join("docs/grade-summary.schema.json");
    let schema: Value =
        serde_json::from_str(&std::fs::read_to_string(schema_path).unwrap()).unwrap();
    let validator = jsonschema::validator_for(&schema).unwrap();
    let errors: Vec<String> = validator
        .iter_errors(&summary)
        .map(|e| e.to_string())
        .collect();
    assert!(errors.is_empty(), "{errors:?}");

    let results: Value =
        serde_json::from_slice(&std::fs::read(report.join("results.json")).unwrap()).unwrap();
    assert_eq!(results["score"], summary["score"]);
    let tests = results["tests"].as_array().unwrap();
    assert_eq!(tests.len(), 30);
    for test in tests {
        assert_eq!(test["score"], test["max_score"]);
        assert_eq!(test["visibility"], "visible");
        assert!(test["name"].is_string() && test["output"].is_string());
    }

    let html = std::fs::read_to_string(report.join("index.html")).unwrap();
    assert_eq!(html.matches("<tr class=\"scene\" id=\"scene-").count(), 30);
    assert!(!html.contains("http://") && !html.contains("https://") && !html.contains("<script"));
    for scene in scenes {
        for kind in ["reference", "student", "heatmap"] {
            let image = scene["images"][kind].as_str().unwrap();
            assert!(html.contains(&format!("src=\"{image}\"")));
            assert!(image::open(report.join(image)).is_ok(), "{image}");
        }
    }
}

#[test]
fn the_committed_schema_is_the_generated_one() {
    let path = Path::new(env!("CARGO_MANIFEST_DIR")).join("docs/grade-summary.schema.json");
    let generated = raytracer_app::grade::report::schema();
    if std::env::var_os("UPDATE_SCHEMA").is_some() {
        std::fs::write(&path, &generated).unwrap();
    }
    let committed = std::fs::read_to_string(&path).unwrap_or_default();
    assert!(
        committed == generated,
        "docs/grade-summary.schema.json is stale; regenerate it with \
         `UPDATE_SCHEMA=1 cargo test --release --test integration the_committed_schema_is_the_generated`"
    );
}

#[test]
fn the_suite_exports_and_grades_from_its_folder() {
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("suite");
    let output = run(&["grade", "--export-suite", out.to_str().unwrap()]);
    assert_eq!(output.status.code(), Some(0));
    let manifest: Value =
        serde_json::from_slice(&std::fs::read(out.join("suite.json")).unwrap()).unwrap();
    for entry in manifest["scenes"].as_array().unwrap() {
        let scene = out.join(entry["scene"].as_str().unwrap());
        let check = run(&["check", scene.to_str().unwrap()]);
        assert_eq!(check.status.code(), Some(0), "{}", scene.display());
    }
    assert!(out.join("hard/shadow_acne.txt").is_file() && out.join("wood_tex.ppm").is_file());
}

/// One scene of an exported suite graded alone, as docs/grading.md shows
/// (`grade --tracer … suite/hard/inside_sphere.txt`): its texture lies in
/// the suite's folder, above the scene's own, and the scene is graded
/// from there under its name in the suite.
#[test]
fn one_exported_scene_grades_with_its_suites_texture() {
    let dir = open_folder("grade-one-");
    let suite = dir.path().join("suite");
    let output = run(&["grade", "--export-suite", suite.to_str().unwrap()]);
    assert_eq!(output.status.code(), Some(0));
    let report = dir.path().join("report");
    let tracer = format!("{} render {{scene}} {{out}}", student_binary().display());
    let out = run(&[
        "grade",
        "--tracer",
        &tracer,
        "-o",
        report.to_str().unwrap(),
        "--cache",
        dir.path().join("cache").to_str().unwrap(),
        suite.join("hard/inside_sphere.txt").to_str().unwrap(),
    ]);
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert_eq!(out.status.code(), Some(0), "{stderr}");
    let summary: Value =
        serde_json::from_slice(&std::fs::read(report.join("summary.json")).unwrap()).unwrap();
    assert_eq!(summary["scenes"][0]["scene"], "hard/inside_sphere.txt");
    assert_eq!(summary["scenes"][0]["status"], "match", "{summary}");
}

/// Grade `tracer` on the scenes of `suite` (a folder) into `report`; the
/// exit code and summary.json.
fn grade_folder(tracer: &str, suite: &Path, report: &Path) -> (i32, Value) {
    let out = run(&[
        "grade",
        "--tracer",
        tracer,
        "-o",
        report.to_str().unwrap(),
        "--cache",
        report.with_extension("cache").to_str().unwrap(),
        suite.to_str().unwrap(),
    ]);
    let summary = std::fs::read(report.join("summary.json"))
        .unwrap_or_else(|_| panic!("no summary: {}", String::from_utf8_lossy(&out.stderr)));
    (
        out.status.code().unwrap(),
        serde_json::from_slice(&summary).unwrap(),
    )
}

/// The aspects a scene of a summary failed.
fn failed_aspects(scene: &Value) -> Vec<&str> {
    scene["aspects"]
        .as_array()
        .unwrap()
        .iter()
        .filter(|a| a["pass"] == false)
        .map(|a| a["aspect"].as_str().unwrap())
        .collect()
}

/// A light's colour ignored (every light drawn white) is a shading error
/// wherever it shows, on a textured plane as on a plain sphere: it fails
/// shading alone, never textures, and costs the scene what a missing
/// shadow costs it (shading and shadows weigh the same).
#[test]
fn a_light_colour_ignored_costs_shading_alone() {
    let dir = open_folder("grade-light-colour-");
    let d = dir.path();
    let suite = d.join("suite");
    std::fs::create_dir(&suite).unwrap();
    // A bold two-colour checker, 8 × 8 texels.
    let mut ppm = String::from("P3\n8 8\n255\n");
    for y in 0..8 {
        for x in 0..8 {
            ppm += if (x + y) % 2 == 0 {
                "230 200 40\n"
            } else {
                "40 120 220\n"
            };
        }
    }
    std::fs::write(suite.join("checker.ppm"), ppm).unwrap();
    std::fs::write(
        suite.join("tinted.txt"),
        "camera 64\n\nsphere\ndimension .8\ncenter .8 .2 -5\ncolor .9 .9 .9\n\n\
         plane\ndimension 8 8\ncenter 0 -1 -6\nnormal 0 1 0\nheadup 0 0 -1\ntexture checker.ppm\n\n\
         light\nlocation -2 4 -3\ncolor 1 .5 .2\n",
    )
    .unwrap();
    let student = d.join("white_lights.sh");
    std::fs::write(
        &student,
        "#!/bin/sh\nsed 's/^color 1 .5 .2$/color 1 1 1/' \"$1\" > white.txt && exec \"$3\" render white.txt \"$2\"\n",
    )
    .unwrap();
    std::fs::set_permissions(&student, std::fs::Permissions::from_mode(0o755)).unwrap();
    let tracer = format!(
        "{} {{scene}} {{out}} {}",
        student.display(),
        student_binary().display()
    );
    let (code, summary) = grade_folder(&tracer, &suite, &d.join("report"));
    assert_eq!(code, 1, "{summary}");
    let scene = &summary["scenes"][0];
    assert_eq!(failed_aspects(scene), ["shading"], "{scene}");
    let points = |name: &str| {
        scene["aspects"]
            .as_array()
            .unwrap()
            .iter()
            .find(|a| a["aspect"] == name)
            .unwrap()["points"]
            .as_f64()
            .unwrap()
    };
    assert_eq!(points("shading"), points("shadows"), "{scene}");
    assert_eq!(points("shading"), points("textures"), "{scene}");
}

/// An image written upside down (the scene rendered mirrored in y, so
/// exactly our image turned over) fails geometry, with the transform
/// named as the likely cause, and the other aspects, judged on the image
/// turned back, pass. The report's words: no fraction over an empty base,
/// and an aspect not judged says what it lacked, with no points.
#[test]
fn an_upside_down_image_is_named_and_costs_geometry_alone() {
    let dir = open_folder("grade-upside-down-");
    let d = dir.path();
    let suite = d.join("suite");
    std::fs::create_dir(&suite).unwrap();
    std::fs::write(suite.join("ball.txt"), SCENE).unwrap();
    let flipped = d.join("flipped.txt");
    std::fs::write(
        &flipped,
        SCENE
            .replace(
                "center 0 -1 -10\n  normal 0 1 0",
                "center 0 1 -10\n  normal 0 -1 0",
            )
            .replace("location 6 4 -3", "location 6 -4 -3"),
    )
    .unwrap();
    assert_ne!(std::fs::read_to_string(&flipped).unwrap(), SCENE);
    // The flipped scene and the renderer are words of the command, so the
    // box holds them.
    let student = d.join("upside_down.sh");
    std::fs::write(&student, "#!/bin/sh\nexec \"$4\" render \"$3\" \"$2\"\n").unwrap();
    std::fs::set_permissions(&student, std::fs::Permissions::from_mode(0o755)).unwrap();
    let tracer = format!(
        "{} {{scene}} {{out}} {} {}",
        student.display(),
        flipped.display(),
        student_binary().display()
    );
    let (code, summary) = grade_folder(&tracer, &suite, &d.join("report"));
    assert_eq!(code, 1, "{summary}");
    let scene = &summary["scenes"][0];
    assert_eq!(failed_aspects(scene), ["geometry"], "{scene}");
    let reason = scene["reason"].as_str().unwrap();
    assert!(reason.contains("upside down"), "{reason}");

    let results: Value =
        serde_json::from_slice(&std::fs::read(d.join("report/results.json")).unwrap()).unwrap();
    let output = results["tests"][0]["output"].as_str().unwrap();
    assert!(!output.contains(" of 0 "), "{output}");
    for line in output.lines().filter(|l| l.contains("not judged")) {
        assert!(!line.contains("points"), "{line}");
    }
    assert!(
        output.contains("reflection not judged: no mirror"),
        "{output}"
    );
}

/// The scenes beyond what the assignment asks (suite.json's `robustness`)
/// are judged and reported, and carry points only where the suite opts in
/// (`robustness_points`); class.csv counts them apart.
#[test]
fn robustness_scenes_carry_points_only_where_a_course_opts_in() {
    let dir = open_folder("grade-robustness-");
    let d = dir.path();
    let tracer = format!("{} render {{scene}} {{out}}", student_binary().display());
    for opt_in in [false, true] {
        let suite = d.join(format!("suite-{opt_in}"));
        std::fs::create_dir(&suite).unwrap();
        std::fs::write(suite.join("ball.txt"), SCENE).unwrap();
        std::fs::write(
            suite.join("far.txt"),
            SCENE.replace("camera 32", "camera 24"),
        )
        .unwrap();
        std::fs::write(
            suite.join("suite.json"),
            format!(
                r#"{{"robustness_points": {opt_in}, "scenes": [
                    {{"scene": "ball.txt", "points": 1}},
                    {{"scene": "far.txt", "points": 1, "robustness": true}}]}}"#
            ),
        )
        .unwrap();
        let report = d.join(format!("report-{opt_in}"));
        let (code, summary) = grade_folder(&tracer, &suite, &report);
        assert_eq!(code, 0, "{summary}");
        let far = &summary["scenes"].as_array().unwrap()[1];
        assert_eq!(far["robustness"], true, "{far}");
        assert_eq!(far["status"], "match", "{far}");
        let expected = if opt_in { 2.0 } else { 1.0 };
        assert_eq!(summary["max_score"], expected, "{summary}");
        let results: Value =
            serde_json::from_slice(&std::fs::read(report.join("results.json")).unwrap()).unwrap();
        let text = results.to_string();
        assert!(
            text.contains("robustness: beyond what the assignment asks"),
            "{text}"
        );
    }
}
