//! README.md's install section, followed in a fresh home: its commands,
//! run as written with `HOME` an empty folder, give working completions in
//! bash, zsh and fish and `man raytracer-grade`. The binary under test
//! stands in for what the section's `cargo install --locked --path .` puts
//! in `~/.cargo/bin` (building the workspace again here would take
//! minutes); every other command of the section runs as the page has it.

use std::path::Path;
use std::process::{Command, Output};

use crate::support::{self, bin, under_ci};

const TEST: &str = "a_fresh_home_follows_the_install_section_to_completions_and_man_pages";

/// `program` with `args` in the fresh `home`: nothing of the test's
/// environment but a plain `PATH` led by `~/.cargo/bin`.
fn in_home(home: &Path, program: &str, args: &[&str]) -> Command {
    let mut command = Command::new(program);
    command
        .args(args)
        .env_clear()
        .env("HOME", home)
        .env(
            "PATH",
            format!(
                "{}:/usr/local/bin:/usr/bin:/bin",
                home.join(".cargo/bin").display()
            ),
        )
        .env("LC_ALL", "C.UTF-8")
        .current_dir(home);
    command
}

fn stdout(output: &Output) -> String {
    assert!(
        output.status.success(),
        "{}{}",
        String::from_utf8_lossy(&output.stdout),
        String::from_utf8_lossy(&output.stderr)
    );
    String::from_utf8_lossy(&output.stdout).into_owned()
}

/// bash-completion's loader, or `None` (a failure under CI) when the
/// package is missing.
fn bash_completion(test: &str) -> Option<&'static str> {
    let loader = "/usr/share/bash-completion/bash_completion";
    if Path::new(loader).is_file() {
        return Some(loader);
    }
    assert!(
        !under_ci(),
        "bash-completion is not installed, and CI must run {test}: .ci/run installs it \
         (apt-get install bash-completion)"
    );
    support::skipped(&format!("{test}: bash-completion is not installed"));
    None
}

/// A fresh home with the binary under test where `cargo install` puts it.
fn fresh_home() -> tempfile::TempDir {
    let home = tempfile::tempdir().expect("temp dir");
    let installed = home.path().join(".cargo/bin/raytracer");
    std::fs::create_dir_all(installed.parent().unwrap()).unwrap();
    std::fs::copy(bin(), &installed).expect("install the binary");
    home
}

/// bash (through bash-completion's `loader`) and fish complete
/// `raytracer gr` in `home`.
fn bash_and_fish_complete(home: &Path, loader: &str) {
    let script = format!(
        "source {loader}; _comp_load raytracer 2>/dev/null || __load_completion raytracer; \
         function=$(complete -p raytracer | sed 's/.* -F \\([^ ]*\\) .*/\\1/'); \
         COMP_WORDS=(raytracer gr); COMP_CWORD=1; COMP_LINE='raytracer gr'; \
         COMP_POINT=${{#COMP_LINE}}; \"$function\" raytracer gr raytracer; \
         printf '%s\\n' \"${{COMPREPLY[@]}}\""
    );
    let bash = stdout(&in_home(home, "bash", &["-c", &script]).output().unwrap());
    assert_eq!(
        bash.trim(),
        "grade",
        "bash completes `raytracer gr` as: {bash}"
    );
    let fish = stdout(
        &in_home(home, "fish", &["-c", "complete -C 'raytracer gr'"])
            .output()
            .unwrap(),
    );
    assert!(
        fish.starts_with("grade\t"),
        "fish completes `raytracer gr` as: {fish}"
    );
}

/// The commands `raytracer completions --help` gives for each shell work
/// in a fresh home too.
#[test]
fn the_completions_help_works_in_a_fresh_home() {
    const TEST: &str = "the_completions_help_works_in_a_fresh_home";
    let mut available = true;
    for (tool, install) in [
        ("bash", "apt-get install bash"),
        ("fish", "apt-get install fish"),
    ] {
        available &= support::tool_available(tool, TEST, install);
    }
    let Some(loader) = bash_completion(TEST) else {
        return;
    };
    if !available {
        return;
    }
    let help = stdout(&crate::support::run(&["completions", "--help"]));
    let commands: Vec<&str> = help
        .lines()
        .skip_while(|line| !line.starts_with("Where each shell"))
        .take_while(|line| !line.is_empty())
        .filter_map(|line| line.strip_prefix("    "))
        .collect();
    assert_eq!(commands.len(), 5, "{help}");
    let home = fresh_home();
    let output = in_home(
        home.path(),
        "bash",
        &["-euo", "pipefail", "-c", &commands.join("\n")],
    )
    .output()
    .unwrap();
    stdout(&output);
    bash_and_fish_complete(home.path(), loader);
    assert!(home.path().join(".zfunc/_raytracer").is_file());
}

#[test]
fn a_fresh_home_follows_the_install_section_to_completions_and_man_pages() {
    let tools = [
        ("bash", "apt-get install bash"),
        ("zsh", "apt-get install zsh"),
        ("fish", "apt-get install fish"),
        ("man", "apt-get install man-db"),
    ];
    let mut available = true;
    for (tool, install) in tools {
        available &= support::tool_available(tool, TEST, install);
    }
    let Some(loader) = bash_completion(TEST) else {
        return;
    };
    if !available {
        return;
    }
    let blocks = support::doc_recipes("README.md", "## Install");
    assert!(blocks.len() >= 5, "{blocks:?}");
    assert_eq!(blocks[0].trim(), "cargo install --locked --path .");

    let home = fresh_home();
    let home = home.path();
    for block in &blocks[1..] {
        let output = in_home(home, "bash", &["-euo", "pipefail", "-c", block])
            .output()
            .expect("run bash");
        stdout(&output);
    }

    // bash: the loader finds the script on demand; fish reads
    // ~/.config/fish/completions as it is.
    bash_and_fish_complete(home, loader);
    let fish = stdout(
        &in_home(home, "fish", &["-c", "complete -C 'raytracer grade --exp'"])
            .output()
            .unwrap(),
    );
    assert!(fish.starts_with("--export-suite"), "{fish}");

    // zsh: an interactive shell runs ~/.zshrc, whose compinit finds
    // _raytracer in ~/.zfunc and binds it to `raytracer`.
    let zsh = stdout(
        &in_home(home, "zsh", &["-i", "-c", "print -r -- $_comps[raytracer]"])
            .stdin(std::process::Stdio::null())
            .output()
            .unwrap(),
    );
    assert_eq!(zsh.trim(), "_raytracer");

    // man: the pages beside the program are found through PATH.
    let path = stdout(
        &in_home(home, "man", &["-w", "raytracer-grade"])
            .output()
            .unwrap(),
    );
    assert_eq!(
        Path::new(path.trim()),
        home.join(".cargo/share/man/man1/raytracer-grade.1")
    );
    let page = stdout(
        &in_home(home, "man", &["raytracer-grade"])
            .env("MANPAGER", "cat")
            .env("MANWIDTH", "80")
            .output()
            .unwrap(),
    );
    let page = page.split_whitespace().collect::<Vec<_>>().join(" ");
    for part in [
        "raytracer-grade",
        "--timeout <SECONDS>",
        "--export-suite <DIR>",
        "Exit codes: 0 every scene matches",
    ] {
        assert!(
            page.contains(part),
            "`man raytracer-grade` lacks `{part}`: {page}"
        );
    }
}
