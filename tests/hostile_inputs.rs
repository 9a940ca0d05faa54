//! The files a class produces, and the pipes a shell gives, never crash a
//! command: every command (`check`, `render`, `convert`, `fmt`, `lsp`,
//! `stitch`, `accuracy`) runs over a set of hostile inputs (a line past
//! 65535 columns, a file past 65535 lines, a binary, random bytes, UTF-16
//! and UTF-32 with and without a byte-order mark, an empty file) and ends
//! with its documented exit code, never 101 and never "panicked". A closed
//! stdout ends a command quietly with exit 0 (as ripgrep does), a closed
//! stderr does not change the exit code, and a file that is not text is
//! one diagnostic that names what it is.

use std::io::Write;
use std::path::Path;
use std::process::{Command, Output, Stdio};

use crate::support::hostile::{inputs, long_line};
use crate::support::{bin, write};

fn run_in(dir: &Path, args: &[&str]) -> Output {
    Command::new(bin())
        .args(args)
        .current_dir(dir)
        .env_remove("COLUMNS")
        .env("NO_COLOR", "1")
        .stdin(Stdio::null())
        .output()
        .expect("run raytracer")
}

fn assert_no_panic(what: &str, output: &Output) {
    let stderr = String::from_utf8_lossy(&output.stderr);
    assert!(
        output.status.code().is_some_and(|code| code != 101) && !stderr.contains("panicked"),
        "{what}: {:?}\n{stderr}",
        output.status
    );
}

/// A minimal LSP session: open `text`, shut down, exit.
fn lsp_session(text: &str) -> Vec<u8> {
    let messages = [
        serde_json::json!({"jsonrpc": "2.0", "id": 1, "method": "initialize", "params": {"capabilities": {}}}),
        serde_json::json!({"jsonrpc": "2.0", "method": "initialized", "params": {}}),
        serde_json::json!({"jsonrpc": "2.0", "method": "textDocument/didOpen", "params": {"textDocument": {
            "uri": "file:///tmp/hostile.txt", "languageId": "raytracer", "version": 1, "text": text}}}),
        serde_json::json!({"jsonrpc": "2.0", "id": 2, "method": "shutdown", "params": null}),
        serde_json::json!({"jsonrpc": "2.0", "method": "exit", "params": null}),
    ];
    let mut bytes = Vec::new();
    for message in messages {
        let body = message.to_string();
        write!(bytes, "Content-Length: {}\r\n\r\n{body}", body.len()).expect("in memory");
    }
    bytes
}

#[test]
fn every_command_gives_its_exit_code_on_every_hostile_input() {
    let dir = tempfile::tempdir().expect("temp dir");
    for (what, name, bytes, is_text) in inputs() {
        write(dir.path(), name, &bytes);
        // Every input has errors (or, for the empty file, lacks a camera).
        for args in [
            vec!["check", name],
            vec!["check", "--format", "short", name],
            vec!["check", "--format", "json", name],
            vec!["check", "--format", "sarif", name],
            vec!["render", name, "out.png"],
            vec!["convert", name, "--to", "scene"],
            vec!["accuracy", name, "--reps", "1", "--reference-spp", "1"],
        ] {
            let output = run_in(dir.path(), &args);
            assert_no_panic(&format!("{what}: {args:?}"), &output);
            assert_eq!(output.status.code(), Some(1), "{what}: {args:?}");
        }
        let output = run_in(dir.path(), &["check", name]);
        let stdout = String::from_utf8_lossy(&output.stdout);
        if is_text {
            assert!(!stdout.contains("syntax::not_text"), "{what}:\n{stdout}");
        } else {
            // One diagnostic naming what the file is.
            assert_eq!(stdout.matches("×").count(), 1, "{what}:\n{stdout}");
            assert!(stdout.contains("syntax::not_text"), "{what}:\n{stdout}");
            let expected = if name.starts_with("u16") {
                "UTF-16"
            } else if name.starts_with("u32") {
                "UTF-32"
            } else {
                "binary"
            };
            assert!(stdout.contains(expected), "{what}:\n{stdout}");
        }
        // `fmt` formats the empty file (as nothing) and refuses the rest:
        // syntax errors (1) or, for the JSON scene, its language (2).
        let output = run_in(dir.path(), &["fmt", "--check", name]);
        assert_no_panic(&format!("{what}: fmt"), &output);
        let fmt_code = match name {
            "empty.txt" => 0,
            "long.json" => 2,
            _ => 1,
        };
        assert_eq!(output.status.code(), Some(fmt_code), "{what}: fmt");
        // Not a tile: exit 1, as for any part that is no tile.
        let output = run_in(dir.path(), &["stitch", "out.png", name]);
        assert_no_panic(&format!("{what}: stitch"), &output);
        assert_eq!(output.status.code(), Some(1), "{what}: stitch");
        // The language server takes the text (as the protocol carries it,
        // UTF-8) and shuts down cleanly.
        let mut lsp = Command::new(bin())
            .arg("lsp")
            .stdin(Stdio::piped())
            .stdout(Stdio::piped())
            .stderr(Stdio::piped())
            .spawn()
            .expect("start lsp");
        let session = lsp_session(&String::from_utf8_lossy(&bytes));
        let mut stdin = lsp.stdin.take().expect("stdin");
        let writer = std::thread::spawn(move || stdin.write_all(&session));
        let output = lsp.wait_with_output().expect("lsp ran");
        writer.join().expect("writer").expect("session written");
        assert_no_panic(&format!("{what}: lsp"), &output);
        assert_eq!(output.status.code(), Some(0), "{what}: lsp");
    }
}

/// Run `args` with stdout (or stderr) a pipe whose reader has gone before
/// the command starts, so its first write fails whatever it writes and
/// however fast (a reader closed after the spawn would race it: output
/// that fits the pipe's buffer could be written first).
fn with_closed(dir: &Path, args: &[&str], stdout: bool) -> Output {
    use std::os::fd::{FromRawFd, OwnedFd};
    let mut ends = [0; 2];
    // SAFETY: `pipe` writes two descriptors into the array it is given.
    assert_eq!(unsafe { libc::pipe(ends.as_mut_ptr()) }, 0, "a pipe");
    // SAFETY: the descriptors are fresh and owned here alone.
    let (reader, writer) =
        unsafe { (OwnedFd::from_raw_fd(ends[0]), OwnedFd::from_raw_fd(ends[1])) };
    drop(reader);
    let mut command = Command::new(bin());
    command.args(args).current_dir(dir).stdin(Stdio::null());
    if stdout {
        command.stdout(Stdio::from(writer)).stderr(Stdio::piped());
    } else {
        command.stdout(Stdio::null()).stderr(Stdio::from(writer));
    }
    command.output().expect("ran")
}

#[test]
fn a_closed_stdout_ends_quietly_and_a_closed_stderr_changes_nothing() {
    let dir = tempfile::tempdir().expect("temp dir");
    for i in 0..200 {
        write(
            dir.path(),
            &format!("scenes/s{i:03}.txt"),
            "camera 4\nsphere\n  dimension 0\n",
        );
    }
    write(dir.path(), "long.txt", long_line());
    for args in [
        vec!["check", "scenes"],
        vec!["check", "--format", "short", "scenes"],
        vec!["check", "--format", "github", "scenes"],
        vec!["check", "--format", "json", "scenes"],
        vec!["convert", "long.txt", "--to", "json"],
        vec!["fmt", "-"],
    ] {
        let output = with_closed(dir.path(), &args, true);
        assert_no_panic(&format!("{args:?} | closed"), &output);
        let stderr = String::from_utf8_lossy(&output.stderr);
        if args[0] == "check" {
            assert_eq!(output.status.code(), Some(0), "{args:?}: {stderr}");
            assert!(stderr.is_empty(), "{args:?}: {stderr}");
        }
    }
    // Diagnostics on stderr (render's and convert's) with stderr closed:
    // the exit code says what it would have.
    for args in [
        vec!["render", "long.txt", "out.png"],
        vec!["convert", "long.txt", "--to", "json"],
        vec!["check", "missing.txt"],
    ] {
        let output = with_closed(dir.path(), &args, false);
        assert_no_panic(&format!("{args:?} 2> closed"), &output);
        let expected = if args[0] == "check" { 2 } else { 1 };
        assert_eq!(output.status.code(), Some(expected), "{args:?}");
    }
}
