//! End-to-end in a real client: headless Neovim (its built-in LSP client)
//! runs tests/editors/neovim.lua against `raytracer lsp` on a scene with
//! mistakes: it waits for the diagnostics, applies the headup quick fix,
//! formats, and writes the file, which must then read as expected.
//!
//! Without `nvim` on PATH the test prints that it was skipped, and fails
//! under CI (`support::under_ci`; .ci/run installs Debian's `neovim`).

use crate::support;

use std::process::{Command, Stdio};
use std::time::{Duration, Instant};

const SCRIPT: &str = concat!(env!("CARGO_MANIFEST_DIR"), "/tests/editors/neovim.lua");

const SCENE: &str = "camera 40\nsphere dimension 1 center 0 0 -5   # the ball\n  colr .5 .5 .5\nplane dimension 4 4 center 0 -1 -5\n  normal 0 1 0 headup 0 1 1\nlight location 0 5 0 color 1 1 1\n";

const EXPECTED: &str = "camera 40\n\nsphere\n  dimension 1\n  center 0 0 -5 # the ball\n  colr 0.5 0.5 0.5\n\nplane\n  dimension 4 4\n  center 0 -1 -5\n  normal 0 1 0\n  headup 0 0 1\n\nlight\n  location 0 5 0\n  color 1 1 1\n";

#[test]
fn neovim_shows_diagnostics_applies_a_quick_fix_and_formats() {
    if !support::tool_available(
        "nvim",
        "the neovim end-to-end test",
        "apt-get install neovim",
    ) {
        return;
    }
    let dir = tempfile::tempdir().unwrap();
    let scene = support::write(dir.path(), "scene.txt", SCENE);
    let mut child = Command::new("nvim")
        .args(["--headless", "--clean", "-c", &format!("luafile {SCRIPT}")])
        .env("RAYTRACER", support::bin())
        .env("SCENE", &scene)
        .env("HOME", dir.path())
        .stdin(Stdio::null())
        .stdout(Stdio::piped())
        .stderr(Stdio::piped())
        .spawn()
        .expect("start nvim");
    let deadline = Instant::now() + Duration::from_secs(60);
    while child.try_wait().unwrap().is_none() {
        if Instant::now() > deadline {
            let _ = child.kill();
            panic!("nvim did not finish within 60 s");
        }
        std::thread::sleep(Duration::from_millis(50));
    }
    let output = child.wait_with_output().unwrap();
    let stdout = String::from_utf8_lossy(&output.stdout);
    let stderr = String::from_utf8_lossy(&output.stderr);
    eprintln!("nvim stdout:\n{stdout}\nnvim stderr:\n{stderr}");
    assert_eq!(output.status.code(), Some(0));
    assert!(stdout.contains("scene::unknown_attribute"), "{stdout}");
    assert!(
        stdout.contains("scene::headup_not_perpendicular"),
        "{stdout}"
    );
    assert!(
        stdout.contains("action quickfix: project `headup` onto the plane"),
        "{stdout}"
    );
    assert_eq!(std::fs::read_to_string(&scene).unwrap(), EXPECTED);
}

/// The Neovim 0.7 recipe of docs/editors.md, pasted into an `init.lua` as
/// a user would (the server's name replaced by the binary under test),
/// with `editors/vim/` installed as the docs say, attaches the server to
/// every scene Neovim detects: one under `scenes/` (by the recipe's
/// pattern) and `~/hw1.txt` (by the package's content detection, which
/// colours it too): the diagnostics of each arrive.
#[test]
fn the_neovim_0_7_recipe_in_the_docs_attaches_the_server() {
    if !support::tool_available("nvim", "the neovim recipe test", "apt-get install neovim") {
        return;
    }
    let docs = include_str!("../docs/editors.md");
    let start = docs
        .find("-- Neovim 0.7: one client")
        .expect("docs/editors.md has the Neovim 0.7 recipe");
    let recipe = &docs[start..];
    let recipe = &recipe[..recipe.find("```").expect("the recipe's block ends")];
    let server = format!("{:?}, \"lsp\"", support::bin());
    assert!(recipe.contains("\"raytracer\", \"lsp\""), "{recipe}");
    let init = recipe.replace("\"raytracer\", \"lsp\"", &server);
    let home = tempfile::tempdir().unwrap();
    let init_path = support::write(home.path(), "init.lua", init);
    let start = home
        .path()
        .join(".local/share/nvim/site/pack/raytracer/start");
    std::fs::create_dir_all(&start).unwrap();
    let package = concat!(env!("CARGO_MANIFEST_DIR"), "/editors/vim");
    std::os::unix::fs::symlink(package, start.join("raytracer")).unwrap();
    for name in ["scenes/scene.txt", "hw1.txt"] {
        let scene = support::write(home.path(), name, SCENE);
        let wait = "lua if vim.wait(10000, function() return #vim.diagnostic.get(0) > 0 end, 20) \
                    then io.stdout:write('diagnostics: ' .. #vim.diagnostic.get(0) .. ' filetype: ' .. vim.bo.filetype .. '\\n') vim.cmd('qa!') \
                    else vim.cmd('cquit 1') end";
        let output = Command::new("nvim")
            .args([
                "--headless",
                "-u",
                &init_path,
                "-i",
                "NONE",
                &scene,
                "-c",
                wait,
            ])
            .env("HOME", home.path())
            .env_remove("XDG_DATA_HOME")
            .env_remove("XDG_CONFIG_HOME")
            .stdin(Stdio::null())
            .output()
            .expect("run nvim");
        let stdout = String::from_utf8_lossy(&output.stdout);
        let stderr = String::from_utf8_lossy(&output.stderr);
        assert_eq!(output.status.code(), Some(0), "{name}: {stdout}\n{stderr}");
        assert!(
            stdout.contains("diagnostics: "),
            "{name}: {stdout}\n{stderr}"
        );
        assert!(
            stdout.contains("filetype: raytracer"),
            "{name}: {stdout}\n{stderr}"
        );
    }
}
