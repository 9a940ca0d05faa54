//! How long `raytracer lsp` takes to re-check a large scene after a
//! keystroke: a scene of about TARGET bytes (spheres in a grid, one with a
//! mistake) is opened in the server, then KEYS single-character edits are
//! sent one at a time (full sync, as most clients do: the whole text each
//! time), each timed from sending `didChange` to receiving the diagnostics
//! published for that version. The server runs with `--debounce-ms 0`, so
//! the time is the re-check and the messages, not the wait for a pause.
//!
//! On a shared machine the wall time includes waiting for a core, so the
//! server's own CPU time is measured too: its mean per edit over the run
//! (from `/proc/PID/stat`, on Linux).
//!
//! `cargo run --release --example lsp_latency -- BINARY [TARGET_BYTES] [KEYS]`
//! prints one line per edit to stderr and a summary line to stdout:
//! `bytes,keys,p50_ms,p95_ms,max_ms,cpu_mean_ms,diagnostics`, the
//! percentiles the nearest-rank ones of the unrounded times.

use std::io::{BufRead, BufReader, Write};
use std::process::{ChildStdin, Command, Stdio};
use std::time::Instant;

use serde_json::{json, Value};

fn main() {
    let args: Vec<String> = std::env::args().collect();
    let binary = args
        .get(1)
        .expect("usage: lsp_latency BINARY [BYTES] [KEYS]");
    let target: usize = args.get(2).map_or(1 << 20, |a| a.parse().expect("bytes"));
    let keys: usize = args.get(3).map_or(31, |a| a.parse().expect("keys"));

    let mut text = String::from(
        "# lsp_latency: a grid of spheres\ncamera 400\n\nlight\n  location 0 5 0\n  color 1 1 1\n",
    );
    let mut i = 0;
    while text.len() < target {
        let (x, y) = (i % 100, i / 100);
        text.push_str(&format!(
            "\nsphere\n  dimension 0.1\n  center {}.5 {}.25 -20\n  color 0.5 0.5 0.5\n  reflectivity 0.2\n",
            x as i64 - 50,
            y as i64 - 50
        ));
        i += 1;
    }
    text.push_str("\nsphere\n  dimension 1\n  center 0 0 -5\n  colr 1 0 0\n");
    // The keystroke: the last sphere's radius digit, changed back and forth.
    let key_at = text.rfind("dimension 1").unwrap() + "dimension ".len();

    let mut child = Command::new(binary)
        .args(["lsp", "--debounce-ms", "0"])
        .stdin(Stdio::piped())
        .stdout(Stdio::piped())
        .spawn()
        .expect("start the server");
    let mut stdin = child.stdin.take().unwrap();
    let mut stdout = BufReader::new(child.stdout.take().unwrap());
    let uri = "file:///tmp/lsp_latency/scene.txt";

    send(
        &mut stdin,
        &json!({"jsonrpc": "2.0", "id": 1, "method": "initialize", "params": {"capabilities": {}}}),
    );
    wait_for(&mut stdout, |m| m["id"] == 1);
    send(
        &mut stdin,
        &json!({"jsonrpc": "2.0", "method": "initialized", "params": {}}),
    );
    send(
        &mut stdin,
        &json!({"jsonrpc": "2.0", "method": "textDocument/didOpen", "params": {
        "textDocument": {"uri": uri, "languageId": "raytracer", "version": 1, "text": text}}}),
    );
    wait_for(&mut stdout, |m| m["params"]["version"] == 1);

    let pid = child.id();
    let mut times = Vec::new();
    let cpu_before = cpu_ms(pid);
    let mut diagnostics = 0;
    for key in 0..keys {
        let version = key as i64 + 2;
        let digit = if key % 2 == 0 { "2" } else { "1" };
        text.replace_range(key_at..key_at + 1, digit);
        let started = Instant::now();
        send(
            &mut stdin,
            &json!({"jsonrpc": "2.0", "method": "textDocument/didChange", "params": {
            "textDocument": {"uri": uri, "version": version},
            "contentChanges": [{"text": text}]}}),
        );
        let published = wait_for(&mut stdout, |m| {
            m["method"] == "textDocument/publishDiagnostics" && m["params"]["version"] == version
        });
        let ms = started.elapsed().as_secs_f64() * 1000.0;
        diagnostics = published["params"]["diagnostics"]
            .as_array()
            .map_or(0, Vec::len);
        eprintln!("edit {version}: {ms:.1} ms, {diagnostics} diagnostics");
        times.push(ms);
    }
    let cpu_per_edit = cpu_ms(pid)
        .zip(cpu_before)
        .map_or("n/a".to_string(), |(after, before)| {
            format!("{:.1}", (after - before) / keys as f64)
        });
    send(
        &mut stdin,
        &json!({"jsonrpc": "2.0", "id": 2, "method": "shutdown", "params": null}),
    );
    wait_for(&mut stdout, |m| m["id"] == 2);
    send(
        &mut stdin,
        &json!({"jsonrpc": "2.0", "method": "exit", "params": null}),
    );
    drop(stdin);
    let status = child.wait().expect("server exit");
    assert_eq!(status.code(), Some(0), "the server's exit code");

    times.sort_by(f64::total_cmp);
    // Nearest rank: the smallest time at least a share q of the edits
    // take no longer than.
    let at = |q: f64| times[((times.len() as f64 * q).ceil() as usize).clamp(1, times.len()) - 1];
    println!(
        "{},{},{:.1},{:.1},{:.1},{cpu_per_edit},{}",
        text.len(),
        keys,
        at(0.5),
        at(0.95),
        times[times.len() - 1],
        diagnostics
    );
}

/// The CPU time process `pid` has used so far, all threads, in
/// milliseconds: `utime` and `stime` of `/proc/PID/stat` (Linux), in ticks
/// of USER_HZ, which is 100 on every architecture Linux runs on.
fn cpu_ms(pid: u32) -> Option<f64> {
    let stat = std::fs::read_to_string(format!("/proc/{pid}/stat")).ok()?;
    // The command name, in parentheses, may hold spaces: count after it.
    let fields: Vec<&str> = stat[stat.rfind(')')? + 2..].split_whitespace().collect();
    let ticks: u64 = fields.get(11)?.parse::<u64>().ok()? + fields.get(12)?.parse::<u64>().ok()?;
    Some(ticks as f64 * 10.0)
}

fn send(stdin: &mut ChildStdin, message: &Value) {
    let body = message.to_string();
    write!(stdin, "Content-Length: {}\r\n\r\n{body}", body.len()).unwrap();
    stdin.flush().unwrap();
}

/// Read messages until one matches; return it.
fn wait_for(stdout: &mut impl BufRead, matches: impl Fn(&Value) -> bool) -> Value {
    loop {
        let mut length = 0;
        loop {
            let mut line = String::new();
            assert!(
                stdout.read_line(&mut line).unwrap() > 0,
                "the server closed its output"
            );
            let line = line.trim_end();
            if line.is_empty() {
                break;
            }
            if let Some(n) = line.strip_prefix("Content-Length: ") {
                length = n.parse().unwrap();
            }
        }
        let mut body = vec![0; length];
        stdout.read_exact(&mut body).unwrap();
        let message: Value = serde_json::from_slice(&body).unwrap();
        if matches(&message) {
            return message;
        }
    }
}
