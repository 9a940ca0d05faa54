//! `raytracer grade --class`, `--student` and `--merge` on a class written
//! here: `alice` builds a tracer that runs ours (every scene matches),
//! `bob`'s build fails (every scene `crashed`, no scene run), and the
//! third student, whose folder name holds quotes, `<&>` and `#`, crashes
//! on every scene. class.csv has their scores, class.html links each cell
//! to the scene in the right student's report, and the overview merged
//! from reports made one student at a time (`--student`, then `--merge`)
//! is the one `--class` writes. docs/grading.md's GNU parallel recipe, run
//! as written, gives the same class.csv.
//!
//! GNU parallel is a Debian package (`parallel`) that .ci/run installs;
//! without it the recipe's test fails under CI (`support::under_ci`) and
//! says it was skipped otherwise.

use std::os::unix::fs::PermissionsExt;
use std::path::Path;

use percent_encoding::percent_decode_str;
use serde_json::Value;

use crate::support::grading::{open_folder, student_binary};
use crate::support::{self, run};

/// Two small scenes: a ball, and a red ball off centre.
const SCENES: [(&str, &str); 2] = [
    (
        "ball.txt",
        "camera 24\nsphere\n  dimension 1\n  center 0 0 -5\n  color .9 .6 .3\n\
         light\n  location 6 4 -3\n  color 1 1 1\n",
    ),
    (
        "red.txt",
        "camera 24\nsphere\n  dimension 1\n  center .3 0 -5\n  color .9 .1 .2\n\
         light\n  location 6 4 -3\n  color 1 1 1\n",
    ),
];

/// The third student's folder name.
const CAROL: &str = "carol \"<&>\" #1";

/// The class.csv every way of grading the class must give.
fn expected_csv() -> String {
    format!(
        "student,score,max_score,build,ball.txt,red.txt\n\
         alice,2,2,ok,1,1\n\
         bob,0,2,failed,0,0\n\
         \"{}\",0,2,,0,0\n",
        CAROL.replace('"', "\"\"")
    )
}

/// Write `text` to `path`, executable by anyone.
fn write_executable(path: &Path, text: &str) {
    std::fs::write(path, text).unwrap();
    std::fs::set_permissions(path, std::fs::Permissions::from_mode(0o755)).unwrap();
}

/// A folder with `suite/` and `students/`. The student folders are open
/// to anyone: as root, `grade` builds and runs them as `nobody`.
pub(crate) fn class_folder() -> tempfile::TempDir {
    let dir = open_folder("grade-class-");
    let d = dir.path();
    for (name, text) in SCENES {
        support::write(d, &format!("suite/{name}"), text);
    }
    let student = |name: &str, files: &[(&str, &str)]| {
        let folder = d.join("students").join(name);
        std::fs::create_dir_all(&folder).unwrap();
        std::fs::set_permissions(&folder, std::fs::Permissions::from_mode(0o777)).unwrap();
        for (file, text) in files {
            write_executable(&folder.join(file), text);
        }
    };
    let build =
        "printf '#!/bin/sh\\nexec ./renderer render \"$1\" \"$2\"\\n' > tracer.sh\nchmod 755 tracer.sh\n";
    student(
        "alice",
        &[
            ("build.txt", "# the build\nsh build.sh\n"),
            ("build.sh", build),
            ("tracer.txt", "./tracer.sh {scene} {out}\n"),
        ],
    );
    // Alice's own renderer (a copy: the grader's executable is not in the box).
    std::fs::copy(student_binary(), d.join("students/alice/renderer")).unwrap();
    student(
        "bob",
        &[
            ("build.txt", "sh build.sh\n"),
            (
                "build.sh",
                "echo 'tracer.c:3: error: expected ;' >&2\nexit 2\n",
            ),
            ("tracer.txt", "./tracer {scene} {out}\n"),
        ],
    );
    student(
        CAROL,
        &[
            ("tracer.sh", "#!/bin/sh\nkill -SEGV $$\n"),
            ("tracer.txt", "./tracer.sh {scene} {out}\n"),
        ],
    );
    dir
}

/// Run `grade` with `args` in `dir`; its exit code and stderr.
fn grade_in(dir: &Path, args: &[&str]) -> (i32, String) {
    let output = support::command(&[&["grade"], args].concat())
        .current_dir(dir)
        .output()
        .unwrap();
    (
        output.status.code().unwrap(),
        String::from_utf8_lossy(&output.stderr).into_owned(),
    )
}

fn read(path: &Path) -> String {
    std::fs::read_to_string(path).unwrap_or_else(|e| panic!("{}: {e}", path.display()))
}

/// The `href`s of each `<tr class="student">` row of class.html.
fn row_links(html: &str) -> Vec<Vec<String>> {
    html.split("<tr class=\"student\">")
        .skip(1)
        .map(|row| {
            let row = &row[..row.find("</tr>").unwrap()];
            row.split("href=\"")
                .skip(1)
                .map(|rest| rest[..rest.find('"').unwrap()].to_string())
                .collect()
        })
        .collect()
}

#[test]
fn a_class_is_graded_and_merged_from_separate_reports_the_same_way() {
    let dir = class_folder();
    let d = dir.path();
    let (code, stderr) = grade_in(
        d,
        &[
            "--class", "students", "-o", "class", "--cache", "cache", "suite",
        ],
    );
    assert_eq!(code, 1, "{stderr}");
    assert_eq!(read(&d.join("class/class.csv")), expected_csv());

    // Each cell links to a scene's row in that student's own report.
    let html = read(&d.join("class/class.html"));
    let links = row_links(&html);
    assert_eq!(links.len(), 3, "{html}");
    for (student, links) in ["alice", "bob", CAROL].iter().zip(&links) {
        // The name, then the build when it failed, then each scene.
        let build = usize::from(*student == "bob");
        assert_eq!(links.len(), 1 + build + SCENES.len(), "{links:?}");
        for link in links {
            let (file, anchor) = link.split_once('#').unwrap_or((link, ""));
            let file = percent_decode_str(file).decode_utf8().unwrap();
            assert_eq!(file, format!("{student}/index.html"), "{link}");
            let report = read(&d.join("class").join(&*file));
            assert!(
                anchor.is_empty() || report.contains(&format!(" id=\"{anchor}\"")),
                "{link}"
            );
        }
        for (scene, _) in SCENES {
            let cell = format!("#scene-{scene}");
            assert!(links.iter().any(|l| l.ends_with(&cell)), "{links:?}");
        }
    }
    assert!(
        html.contains("carol &quot;&lt;&amp;&gt;&quot; #1"),
        "{html}"
    );
    assert!(!html.contains(CAROL));

    let alice: Value = serde_json::from_str(&read(&d.join("class/alice/summary.json"))).unwrap();
    assert_eq!(alice["build"]["ok"], true, "{alice}");
    let bob: Value = serde_json::from_str(&read(&d.join("class/bob/summary.json"))).unwrap();
    assert_eq!(bob["build"]["reason"], "exit code 2", "{bob}");
    assert!(bob["build"]["stderr"]
        .as_str()
        .unwrap()
        .contains("expected ;"));
    for scene in bob["scenes"].as_array().unwrap() {
        assert_eq!(scene["status"], "crashed");
        assert_eq!(scene["reason"], "the build failed: exit code 2");
    }
    assert!(read(&d.join("class/bob/index.html")).contains("build failed"));

    // One student at a time, then the merge.
    for student in ["alice", "bob", CAROL] {
        let (code, stderr) = grade_in(
            d,
            &[
                "--student",
                &format!("students/{student}"),
                "-o",
                &format!("separate/{student}"),
                "--cache",
                "cache",
                "suite",
            ],
        );
        assert!(code == 0 || code == 1, "{student}: {stderr}");
    }
    let (code, stderr) = grade_in(d, &["--merge", "separate"]);
    assert_eq!(code, 0, "{stderr}");
    for file in ["class.csv", "class.html"] {
        assert_eq!(
            read(&d.join("separate").join(file)),
            read(&d.join("class").join(file)),
            "{file}"
        );
    }
}

#[test]
fn bad_student_folders_and_merges_are_clear_errors() {
    let dir = class_folder();
    let d = dir.path();
    std::fs::create_dir(d.join("students/dave")).unwrap();
    support::write(d, "students/erin/tracer.txt", "./a {scene} {out}\n./b\n");
    let (code, stderr) = grade_in(
        d,
        &[
            "--class", "students", "-o", "class", "--cache", "cache", "suite",
        ],
    );
    assert_eq!(code, 2, "{stderr}");
    assert!(
        stderr.contains("2 student folders cannot be graded"),
        "{stderr}"
    );
    assert!(
        stderr.contains("dave/tracer.txt`: no such file"),
        "{stderr}"
    );
    assert!(
        stderr.contains("erin/tracer.txt` holds 2 command lines; expected one"),
        "{stderr}"
    );
    assert!(!d.join("class").exists(), "nothing is graded");

    let (code, stderr) = grade_in(d, &["--merge", "students"]);
    assert_eq!(code, 2, "{stderr}");
    assert!(
        stderr.contains("alice/summary.json`: no such file"),
        "{stderr}"
    );
    support::write(d, "reports/alice/summary.json", "{\"score\": 1}");
    let (code, stderr) = grade_in(d, &["--merge", "reports"]);
    assert_eq!(code, 2, "{stderr}");
    assert!(stderr.contains("is not a summary of"), "{stderr}");
    assert!(stderr.contains("missing field `max_score`"), "{stderr}");
    assert!(!d.join("reports/class.csv").exists());
    let output = run(&["grade", "--tracer", "t", "--class", "students", "-o", "r"]);
    assert_eq!(output.status.code(), Some(2));
}

#[test]
fn the_parallel_recipe_grades_the_class_as_class_does() {
    if !support::tool_available(
        "parallel",
        "docs/grading.md's class recipe",
        "apt-get install parallel",
    ) {
        return;
    }
    let recipe = support::doc_recipe("docs/grading.md", "### GNU parallel on one machine");
    let dir = class_folder();
    let d = dir.path();
    let output = support::run_recipe(d, &recipe);
    assert!(
        output.status.success(),
        "the recipe failed:\n{}{}",
        String::from_utf8_lossy(&output.stdout),
        String::from_utf8_lossy(&output.stderr)
    );
    assert_eq!(read(&d.join("reports/class.csv")), expected_csv());
    let html = read(&d.join("reports/class.html"));
    assert_eq!(row_links(&html).len(), 3, "{html}");
}

/// A student folder as students write them: the tracer is an argument to
/// an interpreter (`sh tracer.sh`), reads a helper file of its own beside
/// it, and the folder holds an image left from home and a `tracer.txt`
/// link to a file it may not read. The program runs beside its files; the
/// stale image is not judged; the folder itself is unchanged; the link is
/// refused without its target being read.
#[test]
fn a_student_folder_runs_as_at_home_and_is_only_read() {
    let dir = class_folder();
    let d = dir.path();
    let folder = d.join("students/dora");
    std::fs::create_dir_all(&folder).unwrap();
    std::fs::set_permissions(&folder, std::fs::Permissions::from_mode(0o755)).unwrap();
    std::fs::write(folder.join("tracer.txt"), "sh tracer.sh {scene} {out}\n").unwrap();
    std::fs::copy(student_binary(), folder.join("tracer-bin")).unwrap();
    std::fs::write(folder.join("renderer"), "./tracer-bin").unwrap();
    write_executable(
        &folder.join("tracer.sh"),
        "exec \"$(cat renderer)\" render \"$1\" \"$2\"\n",
    );
    // A stale image from home, the right size: it must not pass as this run's.
    let stale = d.join("stale.ppm");
    let rendered = run(&[
        "render",
        &d.join("suite/ball.txt").to_string_lossy(),
        &stale.to_string_lossy(),
    ]);
    assert!(rendered.status.success());
    std::fs::copy(&stale, folder.join("out.ppm")).unwrap();
    let before = support::listing(&folder);

    let (code, stderr) = grade_in(
        d,
        &[
            "--student",
            "students/dora",
            "--cache",
            "cache",
            "-o",
            "dora",
            "suite",
        ],
    );
    assert_eq!(code, 0, "{stderr}");
    let summary: Value = serde_json::from_str(&read(&d.join("dora/summary.json"))).unwrap();
    for scene in summary["scenes"].as_array().unwrap() {
        assert_eq!(scene["status"], "match", "{scene}");
    }
    assert_eq!(
        support::listing(&folder),
        before,
        "the student's folder changed"
    );

    // Now a tracer that writes nothing: the stale image is not judged.
    std::fs::write(folder.join("tracer.txt"), "sh -c true {scene} {out}\n").unwrap();
    let (code, _) = grade_in(
        d,
        &[
            "--student",
            "students/dora",
            "--cache",
            "cache",
            "-o",
            "dora2",
            "suite",
        ],
    );
    assert_eq!(code, 1);
    let summary: Value = serde_json::from_str(&read(&d.join("dora2/summary.json"))).unwrap();
    for scene in summary["scenes"].as_array().unwrap() {
        assert_eq!(scene["status"], "no_image", "{scene}");
    }

    // `tracer.txt` as a link to a file the grader may read and the
    // student may not: refused, and its text shown nowhere.
    let secret = d.join("secret.txt");
    std::fs::write(&secret, "sh top-secret-line {scene} {out}\n").unwrap();
    std::fs::set_permissions(&secret, std::fs::Permissions::from_mode(0o600)).unwrap();
    std::fs::remove_file(folder.join("tracer.txt")).unwrap();
    std::os::unix::fs::symlink(&secret, folder.join("tracer.txt")).unwrap();
    let (code, stderr) = grade_in(
        d,
        &[
            "--student",
            "students/dora",
            "--cache",
            "cache",
            "-o",
            "dora3",
            "suite",
        ],
    );
    assert_eq!(code, 2, "{stderr}");
    assert!(!stderr.contains("top-secret-line"), "{stderr}");
    assert!(stderr.contains("tracer.txt"), "{stderr}");
}

/// Student folders named as the class's own report files, or holding an
/// escape sequence, a line break or a spreadsheet formula, are graded like
/// any: class.csv and class.html are written, each student has a report
/// of its own, the terminal is shown every control character escaped, and
/// no name is a formula in class.csv.
#[test]
fn student_folder_names_cannot_take_a_report_file_forge_a_line_or_a_formula() {
    let dir = open_folder("grade-class-names-");
    let d = dir.path();
    for (name, text) in SCENES {
        support::write(d, &format!("suite/{name}"), text);
    }
    let names = [
        "class.csv",
        "class.html",
        "red\u{1b}[31m\nforged: 9 of 9",
        " =1+1",
        "＝2+2",
    ];
    for name in names {
        let folder = d.join("students").join(name);
        std::fs::create_dir_all(&folder).unwrap();
        std::fs::set_permissions(&folder, std::fs::Permissions::from_mode(0o777)).unwrap();
        std::fs::copy(student_binary(), folder.join("renderer")).unwrap();
        write_executable(
            &folder.join("tracer.sh"),
            "#!/bin/sh\nexec ./renderer render \"$1\" \"$2\"\n",
        );
        write_executable(&folder.join("tracer.txt"), "./tracer.sh {scene} {out}\n");
    }
    let output = support::command(&["grade", "--class", "students", "suite", "-o", "report"])
        .current_dir(d)
        .output()
        .unwrap();
    let stdout = String::from_utf8_lossy(&output.stdout);
    let stderr = String::from_utf8_lossy(&output.stderr);
    assert_eq!(output.status.code(), Some(0), "{stdout}{stderr}");
    assert!(!stdout.contains('\u{1b}'), "{stdout}");
    assert!(stdout.contains("red\\u{1b}[31m\\nforged"), "{stdout}");
    assert!(!stdout.lines().any(|l| l.starts_with("forged")), "{stdout}");
    let report = d.join("report");
    assert!(report.join("class.csv").is_file());
    assert!(report.join("class.html").is_file());
    for folder in ["class.csv~", "class.html~"] {
        assert!(
            report.join(folder).join("summary.json").is_file(),
            "{folder}"
        );
    }
    let csv = read(&report.join("class.csv"));
    let rows: Vec<&str> = csv.lines().skip(1).collect();
    assert!(rows.iter().any(|r| r.starts_with("class.csv,")), "{csv}");
    assert!(rows.iter().any(|r| r.starts_with("' =1+1,")), "{csv}");
    assert!(rows.iter().any(|r| r.starts_with("'＝2+2,")), "{csv}");
}
