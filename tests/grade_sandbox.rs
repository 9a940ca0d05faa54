//! Attacks on `raytracer grade`'s sandbox by a student who wants more
//! than marks.
//!
//! The link swap: a root grader gives each scene's working folder to the
//! user the program runs as. A student process that outlived its run (or
//! any process of that user) replaces every entry it can in every working
//! folder with a link to a folder of root's, for the whole run, hoping the
//! grader changes the owner of what a link points to. The attacker is a C
//! program, as a student would write it, built here with `cc`, run as
//! `nobody`; each scene references a few hundred textures, so the grader's
//! walk over a working folder takes long enough to be raced. The victim's
//! owner and mode must be what they were. The vector exists only where
//! the grader is root: an ordinary user's grader changes no owner.

use std::ffi::OsStr;
use std::os::unix::fs::{MetadataExt, PermissionsExt};
use std::path::{Path, PathBuf};
use std::process::{Command, Stdio};

use crate::support;
use crate::support::grading::{binary, kinds, open_folder, student_binary, Case, Kind, BALL};
use crate::support::namespaces::without_namespaces;

/// Replaces every entry it may rename under each `raytracer-grade-*`
/// folder of TMP with a link to VICTIM, over and over, until STOP exists.
const SWAPPER: &str = r#"
#include <dirent.h>
#include <limits.h>
#include <stdio.h>
#include <string.h>
#include <unistd.h>

static const char *victim;

static void swap_under(const char *dir) {
    DIR *d = opendir(dir);
    if (!d) return;
    struct dirent *e;
    while ((e = readdir(d))) {
        if (e->d_name[0] == '.') continue;
        char path[PATH_MAX], moved[PATH_MAX];
        snprintf(path, sizeof path, "%s/%s", dir, e->d_name);
        snprintf(moved, sizeof moved, "%s/.%s", dir, e->d_name);
        if (e->d_type == DT_DIR) swap_under(path);
        if (rename(path, moved) == 0) symlink(victim, path);
    }
    closedir(d);
}

int main(int argc, char **argv) {
    if (argc != 4) return 2;
    victim = argv[2];
    while (access(argv[3], F_OK) != 0) {
        DIR *d = opendir(argv[1]);
        if (!d) return 3;
        struct dirent *e;
        while ((e = readdir(d))) {
            if (strncmp(e->d_name, "raytracer-grade-", 16) != 0) continue;
            char path[PATH_MAX];
            snprintf(path, sizeof path, "%s/%s", argv[1], e->d_name);
            swap_under(path);
        }
        closedir(d);
    }
    return 0;
}
"#;

/// Scenes in the suite, and textures each references.
const SCENES: usize = 3;
const TEXTURES: usize = 300;

/// The owner, group and mode of `path`, not following a link.
fn stat(path: &Path) -> (u32, u32, u32) {
    let m = std::fs::symlink_metadata(path).unwrap();
    (m.uid(), m.gid(), m.permissions().mode())
}

#[test]
fn a_link_swapped_into_a_working_folder_never_redirects_the_chown() {
    if !support::is_root() {
        assert!(
            !support::under_ci(),
            "CI runs as root, where this vector exists"
        );
        support::skipped("the link swap: only a root grader changes owners");
        return;
    }
    if !support::tool_available("cc", "the link-swap attack", "apt-get install gcc") {
        return;
    }
    let dir = open_folder("grade-swap-");
    let d = dir.path();

    // The victim: root's, closed to everyone else.
    let victim = d.join("victim");
    std::fs::create_dir(&victim).unwrap();
    std::fs::write(victim.join("secret"), "root only\n").unwrap();
    std::fs::set_permissions(&victim, std::fs::Permissions::from_mode(0o700)).unwrap();
    std::fs::set_permissions(
        victim.join("secret"),
        std::fs::Permissions::from_mode(0o600),
    )
    .unwrap();
    let before = [stat(&victim), stat(&victim.join("secret"))];

    // The suite: scenes whose textures fill a folder the walk must cross.
    let suite = d.join("suite");
    std::fs::create_dir_all(suite.join("t")).unwrap();
    for t in 0..TEXTURES {
        std::fs::write(
            suite.join(format!("t/{t:03}.ppm")),
            "P3 1 1 255 200 100 50\n",
        )
        .unwrap();
    }
    for s in 0..SCENES {
        let mut scene = String::from("camera 4\n");
        for t in 0..TEXTURES {
            scene.push_str(&format!(
                "sphere\ndimension .01\ncenter {} 0 -5\ntexture t/{t:03}.ppm\n",
                t as f64 * 0.001
            ));
        }
        std::fs::write(suite.join(format!("scene{s}.txt")), scene).unwrap();
    }

    // The grader's temporary folder, /tmp's kind, watched by the attacker
    // alone (other tests' working folders are elsewhere).
    let tmp = d.join("tmp");
    std::fs::create_dir(&tmp).unwrap();
    std::fs::set_permissions(&tmp, std::fs::Permissions::from_mode(0o1777)).unwrap();

    let source = d.join("swapper.c");
    std::fs::write(&source, SWAPPER).unwrap();
    let swapper = d.join("swapper");
    let built = Command::new("cc")
        .arg("-O2")
        .arg("-o")
        .arg(&swapper)
        .arg(&source)
        .output()
        .unwrap();
    assert!(
        built.status.success(),
        "{}",
        String::from_utf8_lossy(&built.stderr)
    );
    let stop = d.join("stop");
    let mut attacker = Command::new("setpriv")
        .args(["--reuid=65534", "--regid=65534", "--clear-groups"])
        .arg(&swapper)
        .args([&tmp, &victim, &stop])
        .stdin(Stdio::null())
        .spawn()
        .unwrap();

    let report = d.join("report");
    let output = Command::new(binary())
        .args([
            "grade",
            "--tracer",
            "true {scene} {out}",
            "--timeout",
            "5",
            "-o",
        ])
        .arg(&report)
        .arg("--cache")
        .arg(d.join("cache"))
        .arg(&suite)
        .env("TMPDIR", &tmp)
        .output()
        .unwrap();
    std::fs::write(&stop, "").unwrap();
    let attacker_status = attacker.wait().unwrap();
    assert!(
        attacker_status.success(),
        "the attacker failed: {attacker_status}"
    );

    let after = [stat(&victim), stat(&victim.join("secret"))];
    assert_eq!(
        before,
        after,
        "the victim's owner or mode changed; grade said: {}",
        String::from_utf8_lossy(&output.stderr)
    );
    let summary: serde_json::Value =
        serde_json::from_slice(&std::fs::read(report.join("summary.json")).unwrap()).unwrap();
    assert_eq!(
        summary["scenes"].as_array().unwrap().len(),
        SCENES,
        "{summary}"
    );
}

/// A lone sphere, unlit, 16 pixels: the suite of the tests whose
/// students' runs, not their images, are what is tested.
const SPHERE: &str = "camera 16\nsphere\n  dimension 1\n  center 0 0 -5\n  color .9 .6 .3\n";

/// An attack's folder: a one-scene suite and the attacker's script
/// (`script` is the tracer's body, as [`Case::new`] says).
fn attack_folder(script: &str) -> Case {
    Case::new("grade-attack-", BALL, script)
}

use serde_json::Value;

fn status(scene: &Value) -> &str {
    scene["status"].as_str().unwrap()
}

/// A tracer that runs the grader's own executable, by its path, by PATH
/// or through a wrapper script, never matches: the executable is not in
/// the box. The student's own copy of a renderer does (the control).
#[test]
fn the_graders_own_executable_is_out_of_reach() {
    let grader = binary().display().to_string();
    let folder = binary().parent().unwrap().display().to_string();
    let wrapper = attack_folder(&format!("exec {grader} render \"$1\" \"$2\""));
    let honest = attack_folder("exec \"$RAYTRACER\" render \"$1\" \"$2\"");
    for kind in kinds() {
        let (_, scene, sandbox) = honest.grade(kind, None, &[], &[]);
        assert_eq!(status(&scene), "match", "{kind:?} control: {scene}");
        assert_eq!(sandbox["boxed"], true, "{kind:?}: {sandbox}");
        let by_path = format!("{grader} render {{scene}} {{out}}");
        let (_, scene, _) = wrapper.grade(kind, Some(&by_path), &[], &[]);
        assert_ne!(status(&scene), "match", "{kind:?} by path: {scene}");
        let path = format!("{folder}:/usr/bin:/bin");
        let (_, scene, _) = wrapper.grade(
            kind,
            Some("raytracer render {scene} {out}"),
            &[],
            &[("PATH", &path)],
        );
        assert_ne!(status(&scene), "match", "{kind:?} by PATH: {scene}");
        let (_, scene, _) = wrapper.grade(kind, None, &[], &[]);
        assert_ne!(status(&scene), "match", "{kind:?} by a wrapper: {scene}");
    }
}

/// The reference cache: a link to a cached reference is not read, a copy
/// cannot be made, and the cache cannot be overwritten.
#[test]
fn the_reference_cache_is_out_of_reach() {
    let attack = attack_folder(
        "for f in $CASE/cache-*/*.png; do ln -sf \"$f\" \"$2\"; \
         printf 'P3 1 1 255 0 0 0\\n' > \"$f\"; done\n\
         ls $CASE/cache-* >&2\n\
         exit 0",
    );
    let script = std::fs::read(attack.path().join("tracer.sh")).unwrap();
    for kind in kinds() {
        // The first run renders the reference; the second is attacked.
        let _ = attack.grade(kind, None, &[], &[]);
        let cache = attack.path().join(format!("cache-{kind:?}"));
        let cached: Vec<_> = std::fs::read_dir(&cache).unwrap().flatten().collect();
        assert_eq!(cached.len(), 1);
        let before = std::fs::read(cached[0].path()).unwrap();
        let (_, scene, _) = attack.grade(kind, None, &[], &[]);
        assert_ne!(status(&scene), "match", "{kind:?}: {scene}");
        assert!(
            scene["stderr"].as_str().unwrap().contains("No such file"),
            "{kind:?}: the cache is visible in the box: {scene}"
        );
        assert_eq!(std::fs::read(cached[0].path()).unwrap(), before, "{kind:?}");
        // The tracer knows the cached file's path: a link to it is not
        // read (the grader does not follow it), and no copy can be made.
        let path = cached[0].path().display().to_string();
        for (script, expected) in [
            (format!("ln -sf {path} \"$2\""), "bad_image"),
            (format!("cat {path} > \"$2\""), "crashed"),
        ] {
            let text = format!("#!/bin/bash\n{script}\n");
            std::fs::write(attack.path().join("tracer.sh"), text).unwrap();
            let (_, scene, _) = attack.grade(kind, None, &[], &[]);
            assert_eq!(status(&scene), expected, "{kind:?}: {scene}");
        }
        std::fs::write(attack.path().join("tracer.sh"), &script).unwrap();
        let mode = cached[0].metadata().unwrap().permissions().mode() & 0o777;
        assert_eq!(mode, 0o600, "{kind:?}");
        let mode = cache.metadata().unwrap().permissions().mode() & 0o777;
        assert_eq!(mode, 0o700, "{kind:?}");
    }
}

/// `{out}` as a link to a file only root may read is refused without
/// saying anything of the file; a hard link cannot even be made.
#[test]
fn an_image_that_is_a_link_is_not_read() {
    let soft = attack_folder("ln -s /etc/shadow \"$2\"");
    let hard = attack_folder("ln /etc/shadow \"$2\" 2>/dev/null || ln /etc/passwd \"$2\"");
    for kind in kinds() {
        let (_, scene, _) = soft.grade(kind, None, &[], &[]);
        assert_eq!(status(&scene), "bad_image", "{kind:?}: {scene}");
        assert!(
            scene["reason"].as_str().unwrap().contains("symbolic link"),
            "{kind:?}: {scene}"
        );
        let (_, scene, _) = hard.grade(kind, None, &[], &[]);
        assert_ne!(status(&scene), "match", "{kind:?}: {scene}");
        assert!(scene["images"]["student"].is_null(), "{kind:?}: {scene}");
    }
}

/// No process the program started outlives the run: a daemon in a
/// session of its own, a double fork, a `PR_SET_PDEATHSIG` heir (here a
/// child that ignores SIGHUP and SIGTERM) and decoys.
#[test]
fn no_process_of_a_run_survives_it() {
    let attack = attack_folder(
        "setsid sleep 4243 </dev/null >/dev/null 2>&1 &\n\
         ( ( trap '' HUP TERM; exec -a keeper-4243 sleep 4243 ) & ) </dev/null >/dev/null 2>&1\n\
         for i in 1 2 3 4 5; do nohup sleep 4243 </dev/null >/dev/null 2>&1 & done\n\
         exec \"$RAYTRACER\" render \"$1\" \"$2\"",
    );
    for kind in kinds() {
        let (_, scene, _) = attack.grade(kind, None, &[], &[]);
        assert_eq!(status(&scene), "match", "{kind:?}: {scene}");
        let left = processes_with("4243");
        assert!(left.is_empty(), "{kind:?}: survivors: {left:?}");
    }
}

/// The processes one of whose arguments is `marker` (a whole word, so a
/// path of another test's that happens to hold the digits never counts):
/// pid and command line.
fn processes_with(marker: &str) -> Vec<(i32, String)> {
    std::fs::read_dir("/proc")
        .unwrap()
        .flatten()
        .filter_map(|e| {
            let pid = e.file_name().to_str()?.parse().ok()?;
            let cmdline = std::fs::read(e.path().join("cmdline")).ok()?;
            let words: Vec<&[u8]> = cmdline.split(|&b| b == 0).collect();
            words
                .contains(&marker.as_bytes())
                .then(|| (pid, String::from_utf8_lossy(&cmdline).replace('\0', " ")))
        })
        .collect()
}

/// A grader killed with SIGKILL (no chance to clean up) leaves nothing of
/// its box running: the tracer, a daemon in a session of its own and a
/// double fork that ignores SIGHUP and SIGTERM all die with it.
#[test]
fn nothing_of_a_run_survives_a_killed_grader() {
    let attack = attack_folder(
        "setsid sleep 4245 </dev/null >/dev/null 2>&1 &\n\
         ( ( trap '' HUP TERM; exec -a orphan-4245 sleep 4245 ) & ) </dev/null >/dev/null 2>&1\n\
         exec sleep 4245",
    );
    let tmp = attack.path().display().to_string();
    for kind in kinds() {
        let mut grader = attack
            .command(kind, None, &["--timeout", "60"], &[("TMPDIR", &tmp)])
            .stdout(Stdio::null())
            .stderr(Stdio::null())
            .spawn()
            .unwrap();
        let start = std::time::Instant::now();
        while processes_with("4245").len() < 3 {
            assert!(
                start.elapsed().as_secs() < 30 && grader.try_wait().unwrap().is_none(),
                "{kind:?}: the tracer did not start: {:?}",
                processes_with("4245")
            );
            std::thread::sleep(std::time::Duration::from_millis(20));
        }
        grader.kill().unwrap();
        grader.wait().unwrap();
        let killed = std::time::Instant::now();
        let mut left = processes_with("4245");
        while !left.is_empty() && killed.elapsed().as_secs() < 5 {
            std::thread::sleep(std::time::Duration::from_millis(20));
            left = processes_with("4245");
        }
        for (pid, _) in &left {
            // The survivors are this test's own: end them before failing.
            // SAFETY: `kill` has no memory preconditions.
            unsafe { libc::kill(*pid, libc::SIGKILL) };
        }
        assert!(left.is_empty(), "{kind:?}: survivors: {left:?}");
        if kind == Kind::Root && cgroup_v1() {
            // Its control groups are left; the next grader removes them
            // once they are a minute old (made so here).
            let mine = format!("raytracer-grade-{}-", grader.id());
            let left = || -> Vec<std::path::PathBuf> {
                ["memory", "pids"]
                    .iter()
                    .flat_map(|c| std::fs::read_dir(Path::new("/sys/fs/cgroup").join(c)).unwrap())
                    .flatten()
                    .filter(|e| e.file_name().to_string_lossy().starts_with(&mine))
                    .map(|e| e.path())
                    .collect()
            };
            assert_eq!(left().len(), 2, "{kind:?}: {:?}", left());
            for group in left() {
                let aged = Command::new("touch")
                    .args(["-d", "2 minutes ago"])
                    .arg(&group)
                    .status()
                    .unwrap();
                assert!(aged.success());
            }
            attack.grade(kind, Some("true {scene} {out}"), &[], &[]);
            assert_eq!(left(), Vec::<std::path::PathBuf>::new(), "{kind:?}");
        }
    }
}

/// Two root graders running at once (a Slurm node grading many students)
/// never run two students as one uid: while both students' tracers run,
/// their uids differ, and each report names its own.
#[test]
fn concurrent_root_graders_give_students_different_uids() {
    if !kinds().contains(&Kind::Root) {
        return;
    }
    let attacks = [
        attack_folder("exec sleep 4246"),
        attack_folder("exec sleep 4246"),
    ];
    let mut graders: Vec<_> = attacks
        .iter()
        .map(|attack| {
            attack
                .command(Kind::Root, None, &["--timeout", "60"], &[])
                .stdout(Stdio::null())
                .stderr(Stdio::null())
                .spawn()
                .unwrap()
        })
        .collect();
    let start = std::time::Instant::now();
    let mut running = processes_with("4246");
    while running.len() < 2 {
        assert!(
            start.elapsed().as_secs() < 30,
            "the tracers did not start: {running:?}"
        );
        std::thread::sleep(std::time::Duration::from_millis(20));
        running = processes_with("4246");
    }
    let mut uids: Vec<u64> = running
        .iter()
        .map(|(pid, _)| uid_of(*pid).unwrap())
        .collect();
    for (pid, _) in &running {
        // SAFETY: `kill` has no memory preconditions.
        unsafe { libc::kill(*pid, libc::SIGKILL) };
    }
    for grader in &mut graders {
        grader.wait().unwrap();
    }
    assert_ne!(uids[0], uids[1], "two students ran as one uid at once");
    let mut reported: Vec<u64> = attacks
        .iter()
        .map(|attack| {
            let summary: Value = serde_json::from_slice(
                &std::fs::read(attack.path().join("report-Root/summary.json")).unwrap(),
            )
            .unwrap();
            summary["sandbox"]["user"].as_u64().unwrap()
        })
        .collect();
    uids.sort_unstable();
    reported.sort_unstable();
    assert_eq!(uids, reported);
}

/// The instructor's `--reference-tracer` never shares a uid with a
/// student: as root it runs as a uid leased for it as a student's is
/// (not `nobody`, not the student's); as an ordinary user, whose box maps
/// only the grader's own uid, it runs as the grader, as the students do,
/// each in a user namespace of its own. Each uid is read from the host's
/// /proc while the program runs.
#[test]
fn the_reference_tracer_runs_as_a_uid_of_its_own() {
    let attack = attack_folder("sleep 1; exec \"$RAYTRACER\" render \"$1\" \"$2\"");
    let d = attack.path();
    let student = student_binary().display().to_string();
    let reference = d.join("reference.sh");
    std::fs::write(
        &reference,
        "#!/bin/bash\nsleep 1\nexec \"$3\" render \"$1\" \"$2\"\n",
    )
    .unwrap();
    std::fs::set_permissions(&reference, std::fs::Permissions::from_mode(0o755)).unwrap();
    let reference = format!("{} {{scene}} {{out}} {student} 4260", reference.display());
    let tracer = format!(
        "{} {{scene}} {{out}} {student} 4261",
        d.join("tracer.sh").display()
    );
    for kind in kinds() {
        let mut grader = attack
            .command(
                kind,
                Some(&tracer),
                &["--reference-tracer", &reference],
                &[],
            )
            .stdout(Stdio::null())
            .stderr(Stdio::null())
            .spawn()
            .unwrap();
        let (mut reference_uid, mut student_uid) = (None, None);
        while grader.try_wait().unwrap().is_none() {
            let seen = |marker| {
                processes_with(marker)
                    .iter()
                    .find_map(|(pid, _)| uid_of(*pid))
            };
            reference_uid = reference_uid.or_else(|| seen("4260"));
            student_uid = student_uid.or_else(|| seen("4261"));
            std::thread::sleep(std::time::Duration::from_millis(20));
        }
        let summary = attack.summary(kind, "");
        let (scene, sandbox) = (&summary["scenes"][0], &summary["sandbox"]);
        assert_eq!(status(scene), "match", "{kind:?}: {scene}");
        let (Some(reference_uid), Some(student_uid)) = (reference_uid, student_uid) else {
            panic!(
                "{kind:?}: not seen running: reference {reference_uid:?}, student {student_uid:?}"
            );
        };
        match kind {
            Kind::Root => {
                assert!(
                    (60_000..=64_999).contains(&reference_uid),
                    "the reference ran as uid {reference_uid}, not a leased one"
                );
                assert_ne!(
                    reference_uid, student_uid,
                    "the reference shared the student's uid"
                );
                assert_eq!(sandbox["user"].as_u64(), Some(student_uid), "{sandbox}");
            }
            Kind::User | Kind::Tests => {
                // SAFETY: `getuid` has no preconditions.
                let grader = if support::is_root() {
                    65_534
                } else {
                    u64::from(unsafe { libc::getuid() })
                };
                assert_eq!((reference_uid, student_uid), (grader, grader));
                assert_eq!(sandbox["user"], Value::Null, "{sandbox}");
            }
        }
    }
}

/// The real uid of process `pid`, from /proc (none once it has gone).
fn uid_of(pid: i32) -> Option<u64> {
    let status = std::fs::read_to_string(format!("/proc/{pid}/status")).ok()?;
    let line = status.lines().find(|l| l.starts_with("Uid:"))?;
    line.split_whitespace().nth(1)?.parse().ok()
}

/// A program in a box starts with `PATH`, `HOME` and `LANG` alone in its
/// environment, the grader's `PATH` and `LANG`, whoever grades: nothing
/// else of the grader's environment (a secret) reaches it. Read from the
/// script's own starting environment, which its shell leaves as given.
#[test]
fn a_program_in_a_box_starts_with_path_home_and_lang_alone() {
    let attack = attack_folder("tr '\\0' '\\n' < /proc/$$/environ >&2; exit 3");
    let path = std::env::var("PATH").unwrap();
    for kind in kinds() {
        let env = [("GRADER_SECRET", "s3cret"), ("LANG", "C.UTF-8")];
        let (_, scene, sandbox) = attack.grade(kind, None, &[], &env);
        assert_eq!(sandbox["boxed"], true, "{kind:?}: {sandbox}");
        let stderr = scene["stderr"].as_str().unwrap();
        let mut variables: Vec<(&str, &str)> = stderr
            .lines()
            .filter_map(|line| line.split_once('='))
            .collect();
        variables.sort_unstable();
        let names: Vec<&str> = variables.iter().map(|(name, _)| *name).collect();
        assert_eq!(names, ["HOME", "LANG", "PATH"], "{kind:?}: {stderr}");
        assert_eq!(variables[1].1, "C.UTF-8", "{kind:?}: {stderr}");
        assert_eq!(variables[2].1, path, "{kind:?}: {stderr}");
    }
}

/// A program that stops its parent (and pid 1) stops neither the grader
/// nor its clock: the run ends at the timeout.
#[test]
fn a_program_cannot_stop_the_grader() {
    let attack = attack_folder(
        "kill -STOP $PPID 2>/dev/null; kill -STOP 1 2>/dev/null; \
         kill -STOP -1 2>/dev/null; exec sleep 30",
    );
    for kind in kinds() {
        let start = std::time::Instant::now();
        let (_, scene, _) = attack.grade(kind, None, &["--timeout", "2"], &[]);
        assert_eq!(status(&scene), "timeout", "{kind:?}: {scene}");
        assert!(
            start.elapsed().as_secs_f64() < 10.0,
            "{kind:?}: {:?}",
            start.elapsed()
        );
    }
}

/// A UNIX socket file in `dir` that anyone may connect to and an abstract
/// socket named `prefix` and this process's id, both listening while the
/// listeners are kept: the socket file's path and the abstract name.
fn socket_listeners(
    dir: &Path,
    prefix: &str,
) -> (PathBuf, String, [std::os::unix::net::UnixListener; 2]) {
    let file = dir.join("socket");
    let listener = std::os::unix::net::UnixListener::bind(&file).unwrap();
    std::fs::set_permissions(&file, std::fs::Permissions::from_mode(0o777)).unwrap();
    let name = format!("{prefix}{}", std::process::id());
    let abstract_address =
        <std::os::unix::net::SocketAddr as std::os::linux::net::SocketAddrExt>::from_abstract_name(
            name.as_bytes(),
        )
        .unwrap();
    let listening = std::os::unix::net::UnixListener::bind_addr(&abstract_address).unwrap();
    (file, name, [listener, listening])
}

/// A UNIX socket file of the grader's machine and an abstract socket are
/// out of reach; so is the network.
#[test]
fn sockets_outside_the_box_are_out_of_reach() {
    let dir = open_folder("grade-socket-");
    let (file, name, _listeners) = socket_listeners(dir.path(), "raytracer-grade-test-");
    let attack = attack_folder(&format!(
        r#"python3 - <<'END' || exit 3
import socket, sys
for address in ['{}', '\0{name}']:
    s = socket.socket(socket.AF_UNIX)
    try:
        s.connect(address)
        sys.exit(0)
    except OSError as e:
        print(address, e, file=sys.stderr)
sys.exit(1)
END
exec "$RAYTRACER" render "$1" "$2""#,
        file.display()
    ));
    for kind in kinds() {
        let (_, scene, _) = attack.grade(kind, None, &[], &[]);
        assert_eq!(status(&scene), "crashed", "{kind:?}: {scene}");
        assert_eq!(scene["exit_code"], 3, "{kind:?}: {scene}");
        let stderr = scene["stderr"].as_str().unwrap();
        assert_eq!(stderr.matches("Errno").count(), 2, "{kind:?}: {stderr}");
    }
}

/// What a tracer sees of `/`, `/tmp` and `/dev/shm`: the system folders
/// and its own working folder, nothing of the grader's, nothing another
/// run left; what it leaves in /tmp and /dev/shm dies with its box.
#[test]
fn a_tracer_sees_only_the_system_and_its_folder() {
    let attack = attack_folder(
        "ls -A / | tr '\\n' ' '; echo\n\
         ls -A /tmp | tr '\\n' ' '; echo\n\
         ls -A /dev/shm | tr '\\n' ' '; echo\n\
         ls -A $CASE | tr '\\n' ' '; echo\n\
         cat /proc/[0-9]*/cmdline | tr '\\0' ' '; echo\n\
         echo secret > /tmp/left-behind; echo secret > /dev/shm/left-behind\n\
         exec \"$RAYTRACER\" render \"$1\" \"$2\"",
    );
    for kind in kinds() {
        for _ in 0..2 {
            let (_, scene, _) = attack.grade(kind, None, &[], &[]);
            assert_eq!(status(&scene), "match", "{kind:?}: {scene}");
            let stdout = scene["stdout"].as_str().unwrap().to_string();
            let lines: Vec<&str> = stdout.lines().collect();
            let root: Vec<&str> = lines[0].split_whitespace().collect();
            let allowed = [
                "bin", "dev", "etc", "lib", "lib32", "lib64", "libx32", "proc", "sbin", "tmp",
                "usr", "var",
            ];
            assert!(
                root.iter().all(|e| allowed.contains(e)),
                "{kind:?}: / holds {root:?}"
            );
            let tmp: Vec<&str> = lines[1].split_whitespace().collect();
            let attack_folder = attack.path().file_name().unwrap().to_string_lossy();
            let renderer = student_binary().file_name().unwrap().to_string_lossy();
            let mine: Vec<&&str> = tmp
                .iter()
                .filter(|e| **e != attack_folder && **e != renderer)
                .collect();
            // Its working folder, and the folders of the files the command
            // names (bound read-only, alone), nothing else.
            assert_eq!(mine.len(), 1, "{kind:?}: /tmp holds {tmp:?}");
            assert!(mine[0].starts_with("raytracer-grade-"), "{kind:?}: {tmp:?}");
            assert_eq!(lines[2].trim(), "", "{kind:?}: /dev/shm holds {}", lines[2]);
            // Of the attack's folder only the tracer's own files.
            let case: Vec<&str> = lines[3].split_whitespace().collect();
            assert_eq!(case, ["tracer.sh"], "{kind:?}");
            // The box's processes: none names the report or the cache.
            assert!(
                !lines[4].contains("report-") && !lines[4].contains("cache-"),
                "{kind:?}: {}",
                lines[4]
            );
        }
    }
}

/// An image larger than the camera is judged `size` without being
/// decoded, and the report keeps no copy of it.
#[test]
fn an_image_larger_than_the_camera_is_not_decoded() {
    let attack = attack_folder(
        r#"python3 - "$2" <<'END'
import struct, sys, zlib
w, h = 16384, 1024
def chunk(kind, data):
    c = struct.pack('>I', len(data)) + kind + data
    return c + struct.pack('>I', zlib.crc32(kind + data) & 0xffffffff)
rows = zlib.compress(b'\0' * ((w * 3 + 1) * h), 9)
png = b'\x89PNG\r\n\x1a\n' + chunk(b'IHDR', struct.pack('>IIBBBBB', w, h, 8, 2, 0, 0, 0))
png += chunk(b'IDAT', rows) + chunk(b'IEND', b'')
open(sys.argv[1], 'wb').write(png)
END"#,
    );
    for kind in kinds() {
        let (_, scene, _) = attack.grade(kind, None, &[], &[]);
        assert_eq!(status(&scene), "differs", "{kind:?}: {scene}");
        assert!(
            scene["reason"].as_str().unwrap().contains("not decoded"),
            "{kind:?}: {scene}"
        );
        assert!(scene["images"]["student"].is_null(), "{kind:?}: {scene}");
    }
}

/// Students of a class cannot reach one another: what one leaves in /tmp
/// and /dev/shm, and a daemon it starts, are gone before the next runs; no
/// report or other student's folder is in its box; in a root run each
/// has a uid of its own; every student is graded and class.csv written.
#[test]
fn students_of_a_class_cannot_reach_one_another() {
    let case = Case::suite(
        "grade-class-attack-",
        &BALL.replace("camera 32", "camera 16"),
    );
    let d = case.path();
    let student = |name: &str, script: &str| {
        let tracer = "bash tracer.sh {scene} {out}\n";
        case.student(
            &format!("class/{name}"),
            tracer,
            &[("tracer.sh", script.as_bytes())],
        );
    };
    // Mallory looks for reports where they are (this test's folder, where
    // the other kind's run wrote its reports) and where a grader might
    // leave one, not over the whole of `/`, whose walk takes seconds.
    student(
        "a-mallory",
        &format!(
            "echo secret > /tmp/mallory; echo secret > /dev/shm/mallory\n\
             setsid sleep 4244 </dev/null >/dev/null 2>&1 &\n\
             find {} /tmp /var/tmp /dev/shm /run /home /root -name summary.json 2>/dev/null\n\
             ls /proc/*/cwd/ 2>/dev/null | head -3\n\
             exec ./renderer render \"$1\" \"$2\"\n",
            d.display()
        ),
    );
    student(
        "b-victim",
        "id -u; ls -A /tmp /dev/shm; ls -d /*/*mallory* 2>/dev/null\n\
         exec ./renderer render \"$1\" \"$2\"\n",
    );
    for kind in kinds() {
        let report = case.report(kind);
        let output = case
            .grade_command(
                kind,
                &report,
                [OsStr::new("--class"), d.join("class").as_os_str()],
            )
            .output()
            .unwrap();
        let stderr = String::from_utf8_lossy(&output.stderr);
        assert_eq!(output.status.code(), Some(0), "{kind:?}: {stderr}");
        let csv = std::fs::read_to_string(report.join("class.csv")).unwrap();
        assert_eq!(csv.lines().count(), 3, "{kind:?}: {csv}");
        let read = |name: &str| -> Value {
            serde_json::from_slice(&std::fs::read(report.join(name).join("summary.json")).unwrap())
                .unwrap()
        };
        let (mallory, victim) = (read("a-mallory"), read("b-victim"));
        let seen = mallory["scenes"][0]["stdout"].as_str().unwrap();
        assert!(!seen.contains("summary.json"), "{kind:?}: {seen}");
        let seen = victim["scenes"][0]["stdout"].as_str().unwrap();
        assert!(!seen.contains("mallory"), "{kind:?}: {seen}");
        if kind == Kind::Root {
            assert_ne!(
                mallory["sandbox"]["user"], victim["sandbox"]["user"],
                "{kind:?}"
            );
            assert_eq!(
                seen.lines().next(),
                victim["sandbox"]["user"].to_string().as_str().into()
            );
        }
        let left = processes_with("4244");
        assert!(left.is_empty(), "{kind:?}: the daemon survived: {left:?}");
    }
}

/// Four processes of 60 MiB each: under `--memory 128` they do not all
/// live where the run is held in a control group.
const MEMORY_ACROSS_PROCESSES: &str =
    "for i in 1 2 3 4; do python3 -c 'import time; b = bytearray(60 << 20); time.sleep(2)' & done\n\
     status=0; for job in $(jobs -p); do wait $job || status=1; done\n\
     exit $status";

/// Whether cgroup v1's `memory` and `pids` hierarchies are mounted here.
fn cgroup_v1() -> bool {
    ["memory", "pids"].iter().all(|c| {
        Path::new("/sys/fs/cgroup")
            .join(c)
            .join("cgroup.procs")
            .is_file()
    })
}

/// Memory is bounded per run where a control group can be made (a root
/// run here): four processes of 60 MiB each under `--memory 128` do not
/// all live; without one (a user run with no group delegated to it) each
/// process alone is bounded.
#[test]
fn memory_is_bounded_per_run_by_a_control_group() {
    let attack = attack_folder(MEMORY_ACROSS_PROCESSES);
    for kind in kinds() {
        let (_, scene, sandbox) = attack.grade(kind, None, &["--memory", "128"], &[]);
        let mechanisms = sandbox["mechanisms"].to_string();
        if kind == Kind::Root && cgroup_v1() {
            assert!(mechanisms.contains("cgroup"), "{sandbox}");
            assert_eq!(status(&scene), "crashed", "{kind:?}: {scene}");
        } else {
            assert!(!mechanisms.contains("cgroup"), "{sandbox}");
            assert_eq!(status(&scene), "no_image", "{kind:?}: {scene}");
        }
    }
}

/// A cgroup v1 `memory` and `pids` group delegated to `nobody` as an
/// administrator would (systemd's `Delegate=`, or by hand): a folder of
/// each hierarchy, it and its files given to uid 65534. Removed, with
/// whatever groups were left in it, when dropped.
struct Delegated {
    folders: Vec<std::path::PathBuf>,
}

impl Delegated {
    fn new() -> Delegated {
        use std::sync::atomic::{AtomicUsize, Ordering};
        static MADE: AtomicUsize = AtomicUsize::new(0);
        let name = format!(
            "raytracer-test-delegated-{}-{}",
            std::process::id(),
            MADE.fetch_add(1, Ordering::Relaxed)
        );
        let mut delegated = Delegated {
            folders: Vec::new(),
        };
        for controller in ["memory", "pids"] {
            let folder = Path::new("/sys/fs/cgroup").join(controller).join(&name);
            std::fs::create_dir(&folder).unwrap();
            delegated.folders.push(folder.clone());
            std::os::unix::fs::chown(&folder, Some(65_534), Some(65_534)).unwrap();
            for file in std::fs::read_dir(&folder).unwrap() {
                std::os::unix::fs::chown(file.unwrap().path(), Some(65_534), Some(65_534)).unwrap();
            }
        }
        delegated
    }

    /// The groups made in the delegated folders.
    fn children(&self) -> Vec<std::path::PathBuf> {
        self.folders
            .iter()
            .flat_map(|f| std::fs::read_dir(f).unwrap().flatten())
            .map(|e| e.path())
            .filter(|p| p.is_dir())
            .collect()
    }

    /// `command` started in the delegated groups: a root shell writes its
    /// pid to each group's `cgroup.procs`, then execs it (`setpriv`).
    fn inside(&self, command: &Command) -> Command {
        let mut script = String::new();
        for folder in &self.folders {
            script += &format!("echo $$ > {}/cgroup.procs && ", folder.display());
        }
        script += "exec \"$@\"";
        let mut wrapped = Command::new("sh");
        wrapped
            .args(["-c", &script, "sh"])
            .arg(command.get_program())
            .args(command.get_args())
            .stdin(Stdio::null());
        for (key, value) in command.get_envs() {
            match value {
                Some(value) => wrapped.env(key, value),
                None => wrapped.env_remove(key),
            };
        }
        wrapped
    }
}

impl Drop for Delegated {
    fn drop(&mut self) {
        for child in self.children() {
            let _ = std::fs::remove_dir(child);
        }
        for folder in &self.folders {
            // A process that left a group leaves it a moment later.
            for _ in 0..200 {
                if std::fs::remove_dir(folder).is_ok() {
                    break;
                }
                std::thread::sleep(std::time::Duration::from_millis(10));
            }
        }
    }
}

/// Whether a delegated group can be tried here: as root, with `setpriv`
/// and cgroup v1's `memory` and `pids` hierarchies.
fn delegation_possible(test: &str) -> bool {
    if !support::is_root() {
        assert!(!support::under_ci(), "CI runs as root");
        support::skipped(&format!("{test}: delegating a group needs root"));
        return false;
    }
    if !cgroup_v1() {
        support::skipped(&format!("{test}: no cgroup v1 `memory` and `pids` here"));
        return false;
    }
    kinds().contains(&Kind::User)
}

/// A user run whose grader holds a delegated group bounds each run's
/// memory across its processes in groups it makes there (summary.json
/// names `cgroup`), and removes them after.
#[test]
fn a_delegated_control_group_bounds_a_user_run() {
    if !delegation_possible("a delegated group") {
        return;
    }
    let attack = attack_folder(MEMORY_ACROSS_PROCESSES);
    let delegated = Delegated::new();
    let command = attack.command(Kind::User, None, &["--memory", "128"], &[]);
    let (_, scene, sandbox) = attack.grade_by(Kind::User, delegated.inside(&command));
    assert!(
        sandbox["mechanisms"].to_string().contains("cgroup"),
        "{sandbox}"
    );
    assert_eq!(status(&scene), "crashed", "{scene}");
    assert_eq!(delegated.children(), Vec::<std::path::PathBuf>::new());
}

/// The groups a delegated grader makes are its uid's, which is also the
/// program's: in the box the program can neither reach the delegated
/// folders to move itself out nor mount its own groups (through a user
/// and cgroup namespace of its own) to raise its limit. Outside a box the
/// same attack works (the control).
#[test]
fn a_program_cannot_leave_or_loosen_its_delegated_group() {
    if !delegation_possible("leaving a delegated group") {
        return;
    }
    let delegated = Delegated::new();
    let mut script = String::from("escaped=\n");
    for folder in &delegated.folders {
        script += &format!(
            "echo $$ 2>/dev/null > {}/cgroup.procs && escaped=\"$escaped procs\"\n",
            folder.display()
        );
    }
    script += "mounted=$(mktemp -d)\n\
        unshare -Urm -C sh -c \"mount -t cgroup -o memory none $mounted && \
          echo 9223372036854771712 > $mounted/memory.limit_in_bytes\" 2>/dev/null \
          && escaped=\"$escaped mount\"\n\
        rmdir \"$mounted\"\n\
        [ -z \"$escaped\" ] && exec \"$RAYTRACER\" render \"$1\" \"$2\"\n\
        echo \"escaped:$escaped\"; exit 1";
    let attack = attack_folder(&script);
    let command = attack.command(Kind::User, None, &["--memory", "128"], &[]);
    let (_, scene, sandbox) = attack.grade_by(Kind::User, delegated.inside(&command));
    assert!(
        sandbox["mechanisms"].to_string().contains("cgroup"),
        "{sandbox}"
    );
    assert_eq!(status(&scene), "match", "{scene}");
    // The control: the script as `nobody` in a group of the delegated
    // folders, as the grader makes them, with no box.
    let child = Delegated {
        folders: delegated
            .folders
            .iter()
            .map(|f| f.join("control"))
            .collect(),
    };
    for folder in &child.folders {
        let made = Command::new("setpriv")
            .args(["--reuid=65534", "--regid=65534", "--clear-groups", "mkdir"])
            .arg(folder)
            .status()
            .unwrap();
        assert!(made.success());
    }
    let mut control = Command::new("setpriv");
    control
        .args(["--reuid=65534", "--regid=65534", "--clear-groups", "--"])
        .arg(attack.path().join("tracer.sh"))
        .args(["scene", "image"])
        .current_dir(attack.path());
    let output = child.inside(&control).output().unwrap();
    let stdout = String::from_utf8_lossy(&output.stdout);
    assert_eq!(stdout.trim(), "escaped: procs procs mount", "{output:?}");
}

/// Where no namespace can be had, `grade` refuses (exit 2) unless told
/// `--unprotected`; then it grades without a box, says so, and what its
/// docs promise still holds: the uid (as root), the limits, `{out}` read
/// without following a link, and nothing the program started left
/// running once the run ends.
#[test]
fn without_namespaces_grade_refuses_unless_unprotected() {
    let honest = attack_folder(
        "setsid sleep 4248 </dev/null >/dev/null 2>&1 &\n\
         ( ( trap '' HUP TERM; exec -a orphan-4248 sleep 4248 ) & ) </dev/null >/dev/null 2>&1\n\
         exec \"$RAYTRACER\" render \"$1\" \"$2\"",
    );
    let link = attack_folder("ln -s /etc/passwd \"$2\"");
    for kind in kinds() {
        let output = without_namespaces(&mut honest.command(kind, None, &[], &[]))
            .output()
            .unwrap();
        let stderr = String::from_utf8_lossy(&output.stderr);
        assert_eq!(output.status.code(), Some(2), "{kind:?}: {stderr}");
        assert!(stderr.contains("--unprotected"), "{kind:?}: {stderr}");
        assert!(
            !honest
                .path()
                .join(format!("report-{kind:?}/summary.json"))
                .exists(),
            "{kind:?}"
        );

        let unprotected = ["--unprotected"];
        let grade = |attack: &Case| -> (Value, Value) {
            let report = attack.path().join(format!("report-{kind:?}"));
            let output = without_namespaces(&mut attack.command(kind, None, &unprotected, &[]))
                .output()
                .unwrap();
            let summary: Value =
                serde_json::from_slice(&std::fs::read(report.join("summary.json")).unwrap_or_else(
                    |_| panic!("{kind:?}: {}", String::from_utf8_lossy(&output.stderr)),
                ))
                .unwrap();
            (summary["scenes"][0].clone(), summary["sandbox"].clone())
        };
        let (scene, sandbox) = grade(&honest);
        assert_eq!(status(&scene), "match", "{kind:?}: {scene}");
        assert_eq!(sandbox["boxed"], false, "{kind:?}: {sandbox}");
        let mechanisms: Vec<&str> = sandbox["mechanisms"]
            .as_array()
            .unwrap()
            .iter()
            .map(|m| m.as_str().unwrap())
            .collect();
        for namespace in ["pid_namespace", "mount_namespace", "network_namespace"] {
            assert!(!mechanisms.contains(&namespace), "{kind:?}: {sandbox}");
        }
        for promised in ["rlimits", "no_new_privs"] {
            assert!(mechanisms.contains(&promised), "{kind:?}: {sandbox}");
        }
        assert_eq!(mechanisms.contains(&"uid"), kind == Kind::Root, "{sandbox}");
        let left = processes_with("4248");
        assert!(left.is_empty(), "{kind:?}: survivors: {left:?}");
        let (scene, _) = grade(&link);
        assert_eq!(status(&scene), "bad_image", "{kind:?}: {scene}");
    }
}

/// Without a box, the fence (Landlock and seccomp) keeps the program to
/// its folder and the system's: a world-readable file of the grader's,
/// the reference cache, a UNIX socket file, an abstract socket, a TCP
/// connection to the loopback and a signal to the grader are all refused,
/// as root and as `nobody`.
#[test]
fn without_a_box_the_fence_keeps_the_program_in() {
    let dir = open_folder("grade-fence-");
    let (file, name, _listeners) = socket_listeners(dir.path(), "raytracer-grade-fence-");
    let tcp = std::net::TcpListener::bind("127.0.0.1:0").unwrap();
    let port = tcp.local_addr().unwrap().port();
    let attack = attack_folder(&format!(
        r#"check() {{ what=$1; shift; if "$@" </dev/null >/dev/null 2>&1; then echo "$what allowed"; else echo "$what refused"; fi; }}
check secret cat $CASE/secret.txt
check cache cat $CASE/cache-*/*.png
check signal kill -0 $PPID
connect="import socket, sys; socket.socket(socket.AF_UNIX).connect(sys.argv[1])"
check socket_file python3 -c "$connect" {}
connect="import socket, sys; socket.socket(socket.AF_UNIX).connect(chr(0) + sys.argv[1])"
check abstract_socket python3 -c "$connect" {name}
check tcp python3 -c "import socket; socket.create_connection(('127.0.0.1', {port}))"
check control python3 -c "print(1)"
exec "$RAYTRACER" render "$1" "$2""#,
        file.display()
    ));
    let secret = attack.path().join("secret.txt");
    std::fs::write(&secret, "the grader's\n").unwrap();
    std::fs::set_permissions(&secret, std::fs::Permissions::from_mode(0o644)).unwrap();
    for kind in kinds() {
        // The first run renders the reference into the cache.
        let run = || {
            let report = attack.path().join(format!("report-{kind:?}"));
            let output =
                without_namespaces(&mut attack.command(kind, None, &["--unprotected"], &[]))
                    .output()
                    .unwrap();
            let summary: Value =
                serde_json::from_slice(&std::fs::read(report.join("summary.json")).unwrap_or_else(
                    |_| panic!("{kind:?}: {}", String::from_utf8_lossy(&output.stderr)),
                ))
                .unwrap();
            (summary["scenes"][0].clone(), summary["sandbox"].clone())
        };
        let _ = run();
        let (scene, sandbox) = run();
        assert_eq!(status(&scene), "match", "{kind:?}: {scene}");
        assert_eq!(sandbox["boxed"], false, "{kind:?}: {sandbox}");
        for mechanism in ["landlock", "seccomp"] {
            assert!(
                sandbox["mechanisms"].to_string().contains(mechanism),
                "{kind:?}: {sandbox}"
            );
        }
        let stdout = scene["stdout"].as_str().unwrap();
        let expected = "secret refused\ncache refused\nsignal refused\n\
                        socket_file refused\nabstract_socket refused\ntcp refused\ncontrol allowed\n";
        assert_eq!(stdout, expected, "{kind:?}: {scene}");
    }
}

/// Without a box, a daemon a student started outlives a grader killed
/// with SIGKILL (docs/grading.md says so), but not the next lease of its
/// uid: a root grader that takes a uid first kills every process left
/// running as it, so the next student never shares a uid with it. The
/// graders lease from a range of this test's own (`--uids`), so the
/// lowest free uid is the daemon's whatever other tests' graders hold.
#[test]
fn without_a_box_a_killed_graders_daemon_dies_with_the_next_lease_of_its_uid() {
    if !kinds().contains(&Kind::Root) {
        return;
    }
    const RANGE: &str = "65100-65109";
    let attack = attack_folder(
        "setsid sleep 4249 </dev/null >/dev/null 2>&1 &\n\
         exec sleep 4249",
    );
    let honest = attack_folder("exec \"$RAYTRACER\" render \"$1\" \"$2\"");
    let mut grader = without_namespaces(&mut attack.command(
        Kind::Root,
        None,
        &["--unprotected", "--timeout", "60", "--uids", RANGE],
        &[],
    ))
    .stdout(Stdio::null())
    .stderr(Stdio::null())
    .spawn()
    .unwrap();
    let start = std::time::Instant::now();
    while processes_with("4249").len() < 2 {
        assert!(
            start.elapsed().as_secs() < 30 && grader.try_wait().unwrap().is_none(),
            "the tracer did not start"
        );
        std::thread::sleep(std::time::Duration::from_millis(20));
    }
    let (pid, _) = processes_with("4249")[0].clone();
    let status = std::fs::read_to_string(format!("/proc/{pid}/status")).unwrap();
    let uid: u32 = status
        .lines()
        .find(|l| l.starts_with("Uid:"))
        .and_then(|l| l.split_whitespace().nth(1))
        .unwrap()
        .parse()
        .unwrap();
    assert_eq!(uid, 65_100, "the student ran as the range's first uid");
    grader.kill().unwrap();
    grader.wait().unwrap();
    assert!(
        !processes_with("4249").is_empty(),
        "the daemon died with the grader"
    );
    let output = without_namespaces(&mut honest.command(
        Kind::Root,
        None,
        &["--unprotected", "--uids", RANGE],
        &[],
    ))
    .output()
    .unwrap();
    assert!(
        output.status.success(),
        "{}",
        String::from_utf8_lossy(&output.stderr)
    );
    let left = processes_with("4249");
    for (pid, _) in &left {
        // SAFETY: `kill` has no memory preconditions.
        unsafe { libc::kill(*pid, libc::SIGKILL) };
    }
    assert!(left.is_empty(), "uid {uid}: survivors: {left:?}");
}

/// `command` started with descriptor 7 reading `secret` and 8 appending
/// to `log`, both left open without close-on-exec, as a careless caller
/// of `grade` (a script, a CI runner) might leave them: a shell of the
/// tests' user opens them, then execs `command` (for a user run,
/// `setpriv` and the grader, which keep them).
fn with_descriptors(command: &Command, secret: &Path, log: &Path) -> Command {
    let mut wrapped = Command::new("bash");
    wrapped
        .args([
            "-c",
            "exec 7<\"$1\" 8>>\"$2\"; shift 2; exec \"$@\"",
            "bash",
        ])
        .arg(secret)
        .arg(log)
        .arg(command.get_program())
        .args(command.get_args())
        .stdin(Stdio::null());
    for (key, value) in command.get_envs() {
        match value {
            Some(value) => wrapped.env(key, value),
            None => wrapped.env_remove(key),
        };
    }
    wrapped
}

/// The descriptors the process that starts `grade` leaves open reach no
/// program: a root-only file read through descriptor 7 and a root-only
/// log appended through 8, in a box and without one.
#[test]
fn inherited_descriptors_never_reach_the_program() {
    let attack = attack_folder(
        "cat <&7 2>/dev/null; echo appended >&8 2>/dev/null && echo wrote\n\
         exec \"$RAYTRACER\" render \"$1\" \"$2\"",
    );
    let secret = attack.path().join("root-only.txt");
    std::fs::write(&secret, "root only 4251\n").unwrap();
    let log = attack.path().join("root-only.log");
    std::fs::write(&log, "").unwrap();
    for file in [&secret, &log] {
        std::fs::set_permissions(file, std::fs::Permissions::from_mode(0o600)).unwrap();
    }
    for kind in kinds() {
        for unprotected in [false, true] {
            let extra: &[&str] = if unprotected { &["--unprotected"] } else { &[] };
            let mut command =
                with_descriptors(&attack.command(kind, None, extra, &[]), &secret, &log);
            if unprotected {
                without_namespaces(&mut command);
            }
            let (_, scene, _) = attack.grade_by(kind, command);
            let run = format!("{kind:?}, unprotected {unprotected}");
            assert_eq!(status(&scene), "match", "{run}: {scene}");
            let stdout = scene["stdout"].as_str().unwrap();
            assert!(!stdout.contains("4251"), "{run}: read through 7: {stdout}");
            assert!(
                !stdout.contains("wrote"),
                "{run}: wrote through 8: {stdout}"
            );
            assert_eq!(std::fs::read_to_string(&log).unwrap(), "", "{run}");
        }
    }
}

/// A `TMPDIR` open to every account (`/tmp`'s kind), for a test that
/// looks at what a run leaves there. Whatever is left in it is removed
/// when it is dropped (before the test's folder, whose removal recurses
/// per level: a deep folder left would overflow the test's stack).
struct Tmp(PathBuf);

impl Tmp {
    fn new(parent: &Path) -> Tmp {
        let tmp = parent.join("tmp");
        std::fs::create_dir_all(&tmp).unwrap();
        std::fs::set_permissions(&tmp, std::fs::Permissions::from_mode(0o1777)).unwrap();
        Tmp(tmp)
    }

    /// What is left: nothing of a finished run may be. It is removed
    /// (by `rm`, which walks without recursing) before it is returned.
    fn left(&self) -> Vec<String> {
        let left: Vec<String> = std::fs::read_dir(&self.0)
            .unwrap()
            .flatten()
            .map(|e| e.file_name().to_string_lossy().into_owned())
            .collect();
        for name in &left {
            let path = self.0.join(name);
            let _ = Command::new("chmod")
                .arg("-R")
                .arg("u+rwx")
                .arg(&path)
                .status();
            let removed = Command::new("rm").arg("-rf").arg(&path).status().unwrap();
            assert!(removed.success(), "cannot remove {}", path.display());
        }
        left
    }
}

impl Drop for Tmp {
    fn drop(&mut self) {
        self.left();
    }
}

/// A tracer opens its working folder (`chmod 755`) and makes a
/// set-user-ID and set-group-ID copy of `id`, then waits; meanwhile
/// another local account (uid 65533) looks for it under the grader's
/// `TMPDIR` and runs what it finds. It must find nothing that runs as the
/// student's uid (a root run) or the grader's (a user run): the run's
/// folders lie in a folder only the grader may enter, and without a box
/// the `chmod` itself is refused. Nothing of the run is left in `TMPDIR`
/// once `grade` ends.
#[test]
fn a_set_user_id_file_a_run_makes_is_out_of_other_accounts_reach() {
    let attack = attack_folder(
        "cp /usr/bin/id helper && chmod 6755 helper 2>&1 || echo refused\n\
         chmod 755 . .. 2>/dev/null\n\
         exec sleep 4250",
    );
    let tmp = Tmp::new(attack.path());
    let tmp_text = tmp.0.display().to_string();
    for kind in kinds() {
        for unprotected in [false, true] {
            let run = format!("{kind:?}, unprotected {unprotected}");
            let mut extra = vec!["--timeout", "60"];
            if unprotected {
                extra.push("--unprotected");
            }
            let mut command = attack.command(kind, None, &extra, &[("TMPDIR", &tmp_text)]);
            if unprotected {
                without_namespaces(&mut command);
            }
            let report = attack.path().join(format!("report-{kind:?}"));
            let mut grading = command
                .stdout(Stdio::null())
                .stderr(Stdio::null())
                .spawn()
                .unwrap();
            let start = std::time::Instant::now();
            while processes_with("4250").is_empty() {
                assert!(
                    start.elapsed().as_secs() < 60 && grading.try_wait().unwrap().is_none(),
                    "{run}: the tracer did not start"
                );
                std::thread::sleep(std::time::Duration::from_millis(20));
            }
            let classmate = Command::new("setpriv")
                .args(["--reuid=65533", "--regid=65533", "--clear-groups", "find"])
                .arg(&tmp.0)
                .args(["-name", "helper", "-perm", "-4000", "-exec", "{}", ";"])
                .stderr(Stdio::null())
                .output()
                .unwrap();
            for (pid, _) in processes_with("4250") {
                // SAFETY: `kill` has no memory preconditions.
                unsafe { libc::kill(pid, libc::SIGKILL) };
            }
            grading.wait().unwrap();
            let seen = String::from_utf8_lossy(&classmate.stdout);
            assert!(!seen.contains("euid="), "{run}: the classmate ran: {seen}");
            assert_eq!(tmp.left(), Vec::<String>::new(), "{run}");
            let summary: Value =
                serde_json::from_slice(&std::fs::read(report.join("summary.json")).unwrap())
                    .unwrap();
            let stdout = summary["scenes"][0]["stdout"].as_str().unwrap();
            if unprotected {
                assert!(stdout.contains("refused"), "{run}: {stdout}");
            }
        }
    }
}

/// A tracer's script that leaves `levels` nested folders (`d/d/d/…`) and
/// a `chmod 000` folder holding a file in its working folder, printing
/// how deep it is every 1,000 levels.
fn nested_folders(levels: usize) -> String {
    format!(
        "python3 - <<'END'\n\
         import os\n\
         os.mkdir('closed')\n\
         open('closed/file', 'w').close()\n\
         top = os.open('.', os.O_RDONLY)\n\
         for level in range(1, {levels} + 1):\n    os.mkdir('d')\n    os.chdir('d')\n    \
         if level % 1000 == 0: print(level, flush=True)\n\
         os.fchdir(top)\n\
         os.chmod('closed', 0)\n\
         END\n"
    )
}

/// A tracer that leaves 30,000 nested folders and a `chmod 000` one is
/// graded like any other, and its working folder goes with the run, in
/// a box and without one: the removal walks without a frame per level
/// and opens what it must before removing. Without a box, Landlock checks
/// each new folder against every folder above it, so the nesting takes
/// minutes and the run ends at its timeout with as many folders as it
/// made: the folder must still go.
#[test]
fn deep_and_closed_folders_a_run_leaves_are_removed() {
    let attack = attack_folder(&format!(
        "{}exec \"$RAYTRACER\" render \"$1\" \"$2\"",
        nested_folders(30_000)
    ));
    let tmp = Tmp::new(attack.path());
    let tmp_text = tmp.0.display().to_string();
    for kind in kinds() {
        for unprotected in [false, true] {
            let run = format!("{kind:?}, unprotected {unprotected}");
            // In a box the folders take a second or two; on a busy
            // machine more: the run's time is not what is tested.
            let extra: &[&str] = if unprotected {
                &["--unprotected", "--timeout", "5"]
            } else {
                &["--timeout", "120"]
            };
            let mut command = attack.command(kind, None, extra, &[("TMPDIR", &tmp_text)]);
            if unprotected {
                without_namespaces(&mut command);
            }
            let (code, scene, _) = attack.grade_by(kind, command);
            if unprotected {
                assert!(
                    ["match", "timeout"].contains(&status(&scene)),
                    "{run}: {scene}"
                );
            } else {
                assert_eq!(code, 0, "{run}: {scene}");
                assert_eq!(status(&scene), "match", "{run}: {scene}");
            }
            assert_eq!(tmp.left(), Vec::<String>::new(), "{run}");
        }
    }
}

/// A student's build that leaves 25,000 nested folders and a `chmod 000`
/// one in its prepared folder: the student is graded (each scene's copy
/// refuses a folder that deep) and the prepared folder goes with the run.
/// Without a box, Landlock checks each new folder against every folder
/// above it, so the nesting takes about 40 s: the build then ends at a
/// timeout of 5 s with as many folders as it made, at least 2,000 (a path
/// past `PATH_MAX`), and the folder must still go.
#[test]
fn deep_folders_a_build_leaves_are_removed() {
    let case = Case::suite("grade-deep-build-", SPHERE);
    let d = case.path();
    let build = nested_folders(25_000);
    let student = case.student(
        "student",
        "./renderer render {scene} {out}\n",
        &[
            ("build.txt", b"bash build.sh\n"),
            ("build.sh", build.as_bytes()),
        ],
    );
    let tmp = Tmp::new(d);
    let check = |run: &str, report: &Path, stderr: &str| {
        let summary: Value = serde_json::from_slice(
            &std::fs::read(report.join("summary.json"))
                .unwrap_or_else(|_| panic!("{run}: no summary: {stderr}")),
        )
        .unwrap();
        let printed = summary["build"]["stdout"].as_str().unwrap_or_default();
        let deepest = printed
            .lines()
            .filter_map(|l| l.parse::<usize>().ok())
            .max();
        assert!(deepest >= Some(2_000), "{run}: {summary}");
        assert_eq!(tmp.left(), Vec::<String>::new(), "{run}: {stderr}");
    };
    grade_each_way(&case, &student, &tmp, &["--timeout", "5"], check);
}

/// Grade `student` in each kind of run this machine allows, in a box and
/// `--unprotected` (with `unprotected_options` besides), with `tmp` as
/// `TMPDIR`; `check` is given each run's name, report folder and stderr.
fn grade_each_way(
    case: &Case,
    student: &Path,
    tmp: &Tmp,
    unprotected_options: &[&str],
    check: impl Fn(&str, &Path, &str),
) {
    for kind in kinds() {
        for unprotected in [false, true] {
            let run = format!("{kind:?}, unprotected {unprotected}");
            let report = case.path().join(format!("report-{kind:?}-{unprotected}"));
            let mut command = case.grade_command(
                kind,
                &report,
                [OsStr::new("--student"), student.as_os_str()],
            );
            command.env("TMPDIR", &tmp.0);
            if unprotected {
                command.arg("--unprotected").args(unprotected_options);
                without_namespaces(&mut command);
            }
            let output = command.output().unwrap();
            check(&run, &report, &String::from_utf8_lossy(&output.stderr));
        }
    }
}

/// A build runs with a `HOME` of its own, not the student's folder: what
/// a compiler caches there (Go's build cache) is not copied into each
/// scene's working folder, and goes with the build. The build's output in
/// the folder reaches every scene.
#[test]
fn a_builds_home_is_its_own_and_goes_with_the_build() {
    let case = Case::suite("grade-build-home-", SPHERE);
    let d = case.path();
    let build = "[ \"$HOME\" != \"$PWD\" ] || exit 3\n\
                 mkdir -p \"$HOME/.cache/go-build/00\" && echo cached > \"$HOME/.cache/go-build/00/a\"\n\
                 echo built > built.txt\n";
    let tracer = "[ -e built.txt ] || exit 4\n\
                  [ ! -e .cache ] && [ ! -e \"$HOME/.cache\" ] || exit 5\n\
                  exec ./renderer render \"$1\" \"$2\"\n";
    let student = case.student(
        "student",
        "bash tracer.sh {scene} {out}\n",
        &[
            ("build.txt", b"bash build.sh\n"),
            ("build.sh", build.as_bytes()),
            ("tracer.sh", tracer.as_bytes()),
        ],
    );
    let tmp = Tmp::new(d);
    grade_each_way(&case, &student, &tmp, &[], |run, report, stderr| {
        let summary: Value = serde_json::from_slice(
            &std::fs::read(report.join("summary.json"))
                .unwrap_or_else(|_| panic!("{run}: no summary: {stderr}")),
        )
        .unwrap();
        assert_eq!(summary["build"]["ok"], true, "{run}: {summary}");
        assert_eq!(summary["scenes"][0]["status"], "match", "{run}: {summary}");
        assert_eq!(tmp.left(), Vec::<String>::new(), "{run}: {stderr}");
    });
}

/// A tracer that fills its disk space, blocks or inodes, is told so
/// (the scene's reason names the run's disk space and says it was full),
/// and the next run has all of its own: in a box the working folder is a
/// tmpfs of `--disk` MiB and a bounded number of inodes, gone with the
/// box.
#[test]
fn a_run_that_fills_its_disk_is_told_and_the_next_is_not_hurt() {
    let blocks = attack_folder(
        "for i in $(seq 64); do head -c 1048576 /dev/zero > fill$i 2>/dev/null || break; done\n\
         mkdir closed; chmod 000 closed\n\
         exec \"$RAYTRACER\" render \"$1\" \"$2\"",
    );
    let inodes = attack_folder(
        "for i in $(seq 40000); do : 2>/dev/null > f$i || break; done\n\
         exec \"$RAYTRACER\" render \"$1\" \"$2\"",
    );
    let honest = attack_folder("exec \"$RAYTRACER\" render \"$1\" \"$2\"");
    for kind in kinds() {
        for attack in [&blocks, &inodes] {
            // Making 32,768 files takes seconds on a busy machine: the
            // run's time is not what is tested.
            let extra = ["--disk", "8", "--timeout", "60"];
            let (_, scene, _) = attack.grade(kind, None, &extra, &[]);
            let reason = scene["reason"].as_str().unwrap_or_default();
            assert!(
                reason.contains("the run's disk space (8 MiB) was full"),
                "{kind:?}: {scene}"
            );
            let (_, scene, _) = honest.grade(kind, None, &["--disk", "8"], &[]);
            assert_eq!(status(&scene), "match", "{kind:?}: {scene}");
            assert!(scene["reason"].is_null(), "{kind:?}: {scene}");
        }
    }
}

/// A student whose folder does not fit the run's disk space is told so,
/// and to raise `--disk`, rather than given the kernel's words.
#[test]
fn a_student_folder_larger_than_the_disk_is_told_so() {
    let case = Case::suite("grade-large-student-", SPHERE);
    let data = vec![7u8; 3 << 20];
    let student = case.student(
        "student",
        "./renderer render {scene} {out}\n",
        &[("data.bin", &data)],
    );
    for kind in kinds() {
        let args = [
            OsStr::new("--disk"),
            OsStr::new("2"),
            OsStr::new("--student"),
        ];
        let output = case
            .grade_command(
                kind,
                &case.report(kind),
                args.iter().chain([&student.as_os_str()]),
            )
            .output()
            .unwrap();
        let summary = case.summary(kind, &String::from_utf8_lossy(&output.stderr));
        let reason = summary["scenes"][0]["reason"].as_str().unwrap_or_default();
        assert!(
            reason.contains("do not fit the run's disk space (2 MiB, 32768 files): raise `--disk`"),
            "{kind:?}: {summary}"
        );
    }
}

/// A class where one student leaves 30,000 nested folders, fills its
/// disk and starts a daemon is graded to the end: the honest student
/// matches, class.csv is written, no daemon and nothing of a run is left.
#[test]
fn a_class_survives_a_student_who_leaves_a_mess() {
    let case = Case::suite("grade-class-mess-", SPHERE);
    let d = case.path();
    let student = |name: &str, script: &str| {
        let tracer = "bash tracer.sh {scene} {out}\n";
        case.student(
            &format!("class/{name}"),
            tracer,
            &[("tracer.sh", script.as_bytes())],
        );
    };
    student(
        "a-mess",
        &format!(
            "setsid sleep 4252 </dev/null >/dev/null 2>&1 &\n{}\
             for i in $(seq 32); do head -c 1048576 /dev/zero > fill$i 2>/dev/null || break; done\n\
             exit 0\n",
            nested_folders(30_000)
        ),
    );
    student("b-honest", "exec ./renderer render \"$1\" \"$2\"\n");
    // The honest student's folder (its copy of the renderer, whose size
    // the build profile sets) fits the run's disk with 16 MiB to spare,
    // which the mess's 32 MiB of writes fill.
    let renderer = std::fs::metadata(student_binary()).unwrap().len();
    let disk = (renderer >> 20) + 1 + 16;
    let disk = disk.to_string();
    let tmp = Tmp::new(d);
    for kind in kinds() {
        for unprotected in [false, true] {
            let run = format!("{kind:?}, unprotected {unprotected}");
            let report = d.join(format!("report-{kind:?}-{unprotected}"));
            let class = d.join("class");
            let args = ["--disk", &disk, "--timeout", "30", "--class"].map(OsStr::new);
            let mut command =
                case.grade_command(kind, &report, args.iter().chain([&class.as_os_str()]));
            command.env("TMPDIR", &tmp.0);
            if unprotected {
                command.arg("--unprotected");
                without_namespaces(&mut command);
            }
            let output = command.output().unwrap();
            let stderr = String::from_utf8_lossy(&output.stderr);
            assert_eq!(output.status.code(), Some(1), "{run}: {stderr}");
            let csv = std::fs::read_to_string(report.join("class.csv")).unwrap();
            assert_eq!(csv.lines().count(), 3, "{run}: {csv}");
            let honest: Value = serde_json::from_slice(
                &std::fs::read(report.join("b-honest/summary.json")).unwrap(),
            )
            .unwrap();
            assert_eq!(status(&honest["scenes"][0]), "match", "{run}: {honest}");
            assert_eq!(tmp.left(), Vec::<String>::new(), "{run}: {stderr}");
            let left = processes_with("4252");
            assert!(left.is_empty(), "{run}: the daemon survived: {left:?}");
        }
    }
}

/// Adds a key to the user keyring of its uid (`add`), or looks for it there and
/// prints what it found (`find`): what one run could leave for the next.
const KEYRING: &str = r#"
#include <stdio.h>
#include <string.h>
#include <sys/syscall.h>
#include <unistd.h>

int main(int argc, char **argv) {
    const long user = -4; /* KEY_SPEC_USER_KEYRING: the uid's own, kept between its processes */
    if (argc == 2 && strcmp(argv[1], "add") == 0) {
        long key = syscall(SYS_add_key, "user", "raytracer-left", "secret 4252", 11, user);
        printf("added %s\n", key < 0 ? "no" : "yes");
        return 0;
    }
    long key = syscall(SYS_keyctl, 10 /* KEYCTL_SEARCH */, user, "user", "raytracer-left", 0);
    char found[64] = {0};
    if (key >= 0) syscall(SYS_keyctl, 11 /* KEYCTL_READ */, key, found, sizeof found - 1);
    printf("found %s\n", key < 0 ? "nothing" : found);
    return 0;
}
"#;

/// A key one run leaves in its uid's keyring is not there for the next
/// run, of another grader taking the same uid: a lease empties the uid's
/// keyrings, each run joins a session keyring of its own, and without a
/// box the fence refuses the keyring calls (root and user graders).
#[test]
fn a_key_one_run_leaves_is_not_there_for_the_next() {
    if !support::tool_available("cc", "the keyring attack", "apt-get install gcc") {
        return;
    }
    let dir = open_folder("grade-keyring-");
    let source = dir.path().join("keyring.c");
    std::fs::write(&source, KEYRING).unwrap();
    let program = dir.path().join("keyring");
    let built = Command::new("cc")
        .arg("-o")
        .arg(&program)
        .arg(&source)
        .output()
        .unwrap();
    assert!(
        built.status.success(),
        "{}",
        String::from_utf8_lossy(&built.stderr)
    );
    // The program is named on the command line, so a box holds it.
    let add = attack_folder("\"$4\" add\nexec \"$RAYTRACER\" render \"$1\" \"$2\"");
    let find = attack_folder("\"$4\" find\nexec \"$RAYTRACER\" render \"$1\" \"$2\"");
    let tracer = |attack: &Case| {
        format!(
            "{} {{scene}} {{out}} {} {}",
            attack.path().join("tracer.sh").display(),
            student_binary().display(),
            program.display()
        )
    };
    for kind in kinds() {
        for unprotected in [false, true] {
            let grade = |attack: &Case| -> Value {
                let tracer = tracer(attack);
                let command = if unprotected {
                    let mut command = attack.command(kind, Some(&tracer), &["--unprotected"], &[]);
                    without_namespaces(&mut command);
                    command
                } else {
                    attack.command(kind, Some(&tracer), &[], &[])
                };
                attack.grade_by(kind, command).1
            };
            let added = grade(&add);
            assert_eq!(status(&added), "match", "{kind:?} {unprotected}: {added}");
            // In a box the key is made, in the uid's keyring, which the next
            // lease of the uid empties; without one the fence refuses it.
            let made = if unprotected {
                "added no\n"
            } else {
                "added yes\n"
            };
            assert_eq!(
                added["stdout"].as_str(),
                Some(made),
                "{kind:?} {unprotected}"
            );
            let found = grade(&find);
            assert_eq!(
                found["stdout"].as_str(),
                Some("found nothing\n"),
                "{kind:?} {unprotected}: {found}"
            );
        }
    }
}
