//! `raytracer lsp` spoken to over its stdio, as an editor does: JSON-RPC
//! messages with `Content-Length` headers. Diagnostics (with codes, links
//! and related information, for scene text and JSON, textures from the
//! document's folder), formatting, the outline, hover, completion, quick
//! fixes and fix-all, the protocol's shutdown and exit codes, bytes that are
//! no protocol at all, and random edit sequences whose final diagnostics
//! must equal `raytracer check`'s on the final text.

use crate::support;

use std::io::{BufRead, BufReader, Write};
use std::path::Path;
use std::process::{Child, ChildStdin, Command, Stdio};
use std::sync::mpsc::{self, Receiver};
use std::time::Duration;

use proptest::prelude::*;
use serde_json::{json, Value};

/// A running server and the messages it sends.
struct Client {
    child: Child,
    stdin: Option<ChildStdin>,
    messages: Receiver<Value>,
    next_id: i64,
    /// Notifications seen while waiting for something else.
    notifications: Vec<Value>,
}

const WAIT: Duration = Duration::from_secs(20);

impl Client {
    fn start() -> Client {
        Client::start_with(json!({"capabilities": {}}))
    }

    /// Start the server and initialise it with `params`.
    fn start_with(params: Value) -> Client {
        let mut child = Command::new(support::bin())
            .args(["lsp", "--debounce-ms", "0"])
            .stdin(Stdio::piped())
            .stdout(Stdio::piped())
            .stderr(Stdio::null())
            .spawn()
            .expect("start raytracer lsp");
        let stdout = child.stdout.take().unwrap();
        let (sender, messages) = mpsc::channel();
        std::thread::spawn(move || {
            let mut reader = BufReader::new(stdout);
            while let Some(message) = read_message(&mut reader) {
                if sender.send(message).is_err() {
                    break;
                }
            }
        });
        let stdin = child.stdin.take();
        let mut client = Client {
            child,
            stdin,
            messages,
            next_id: 0,
            notifications: Vec::new(),
        };
        let result = client.request("initialize", params);
        assert!(result["capabilities"]["documentFormattingProvider"] == json!(true));
        client.notify("initialized", json!({}));
        client
    }

    fn send(&mut self, message: &Value) {
        let body = message.to_string();
        let stdin = self.stdin.as_mut().expect("stdin open");
        write!(stdin, "Content-Length: {}\r\n\r\n{body}", body.len()).unwrap();
        stdin.flush().unwrap();
    }

    fn notify(&mut self, method: &str, params: Value) {
        self.send(&json!({"jsonrpc": "2.0", "method": method, "params": params}));
    }

    /// Send a request and wait for its response (the whole message).
    fn request_raw(&mut self, method: &str, params: Value) -> Value {
        self.next_id += 1;
        let id = self.next_id;
        self.send(&json!({"jsonrpc": "2.0", "id": id, "method": method, "params": params}));
        loop {
            let message = self.messages.recv_timeout(WAIT).expect("a response");
            if message["id"] == json!(id) {
                return message;
            }
            self.notifications.push(message);
        }
    }

    fn request(&mut self, method: &str, params: Value) -> Value {
        let response = self.request_raw(method, params);
        assert!(response.get("error").is_none(), "{response}");
        response["result"].clone()
    }

    /// The next diagnostics published for `uri` (at `version`, if given).
    fn diagnostics(&mut self, uri: &str, version: Option<i64>) -> Vec<Value> {
        let matches = |m: &Value| {
            m["method"] == "textDocument/publishDiagnostics"
                && m["params"]["uri"] == uri
                && version.is_none_or(|v| m["params"]["version"] == json!(v))
        };
        if let Some(i) = self.notifications.iter().position(matches) {
            let found = self.notifications.remove(i);
            return found["params"]["diagnostics"].as_array().unwrap().clone();
        }
        loop {
            let message = self.messages.recv_timeout(WAIT).expect("diagnostics");
            if matches(&message) {
                return message["params"]["diagnostics"].as_array().unwrap().clone();
            }
        }
    }

    fn open(&mut self, uri: &str, language: &str, text: &str) -> Vec<Value> {
        self.notify(
            "textDocument/didOpen",
            json!({"textDocument": {"uri": uri, "languageId": language, "version": 1, "text": text}}),
        );
        self.diagnostics(uri, Some(1))
    }

    fn change(&mut self, uri: &str, version: i64, text: &str) {
        self.notify(
            "textDocument/didChange",
            json!({"textDocument": {"uri": uri, "version": version}, "contentChanges": [{"text": text}]}),
        );
    }

    /// `shutdown`, `exit`, and the exit code.
    fn shut_down(mut self) -> Option<i32> {
        assert_eq!(self.request("shutdown", Value::Null), Value::Null);
        self.notify("exit", Value::Null);
        self.stdin = None;
        self.child.wait().unwrap().code()
    }
}

fn read_message(reader: &mut impl BufRead) -> Option<Value> {
    let mut length = None;
    loop {
        let mut line = String::new();
        if reader.read_line(&mut line).ok()? == 0 {
            return None;
        }
        let line = line.trim_end();
        if line.is_empty() {
            break;
        }
        if let Some(n) = line.strip_prefix("Content-Length: ") {
            length = n.parse().ok();
        }
    }
    let mut body = vec![0; length?];
    reader.read_exact(&mut body).ok()?;
    serde_json::from_slice(&body).ok()
}

fn uri_of(path: &Path) -> String {
    format!("file://{}", path.display())
}

const MISTAKES: &str = "camera 400\nsphere\n  dimension 1\n  center 0 0 -5\n  colr 1 0 0\nplane\n  dimension 4 4\n  center 0 -1 -5\n  normal 0 2 0\n  headup 0 1 1\n";

#[test]
fn the_docs_link_goes_where_the_client_says() {
    let dir = tempfile::tempdir().unwrap();
    let uri = uri_of(&dir.path().join("scene.txt"));
    let docs = "https://course.example/docs/diagnostics.md";
    let mut client = Client::start_with(json!({
        "capabilities": {},
        "initializationOptions": {"diagnosticsDocs": docs},
    }));
    let diagnostics = client.open(&uri, "raytracer", MISTAKES);
    let unknown = diagnostics
        .iter()
        .find(|d| d["code"] == "scene::unknown_attribute")
        .unwrap();
    assert_eq!(
        unknown["codeDescription"]["href"],
        "https://course.example/docs/diagnostics/scene.md#sceneunknown_attribute"
    );
}

#[test]
fn diagnostics_carry_codes_and_related_information() {
    let dir = tempfile::tempdir().unwrap();
    let uri = uri_of(&dir.path().join("scene.txt"));
    let mut client = Client::start();
    let diagnostics = client.open(&uri, "raytracer", MISTAKES);
    let codes: Vec<&str> = diagnostics
        .iter()
        .map(|d| d["code"].as_str().unwrap())
        .collect();
    assert!(codes.contains(&"scene::unknown_attribute"), "{codes:?}");
    let unknown = diagnostics
        .iter()
        .find(|d| d["code"] == "scene::unknown_attribute")
        .unwrap();
    assert_eq!(
        unknown["range"]["start"],
        json!({"line": 4, "character": 2})
    );
    assert_eq!(unknown["severity"], json!(1));
    // No link unless the client says where the docs are (see
    // `the_docs_link_goes_where_the_client_says`).
    assert!(unknown.get("codeDescription").is_none(), "{unknown}");
    assert!(
        unknown["message"].as_str().unwrap().contains("help:"),
        "{unknown}"
    );
    assert!(
        unknown["relatedInformation"][0]["message"].is_string(),
        "{unknown}"
    );

    // A duplicate: the related information points at both lines.
    client.change(&uri, 2, "camera 4\ncamera 5\n");
    let diagnostics = client.diagnostics(&uri, Some(2));
    let twice = diagnostics
        .iter()
        .find(|d| d["code"] == "scene::repeated_camera");
    let twice = twice.unwrap_or_else(|| panic!("{diagnostics:?}"));
    let lines: Vec<&Value> = twice["relatedInformation"]
        .as_array()
        .unwrap()
        .iter()
        .map(|r| &r["location"]["range"]["start"]["line"])
        .collect();
    assert_eq!(lines, [&json!(0), &json!(1)]);
    assert_eq!(client.shut_down(), Some(0));
}

#[test]
fn json_scenes_and_textures_from_the_documents_folder() {
    let dir = tempfile::tempdir().unwrap();
    std::fs::write(dir.path().join("wood.ppm"), "P3\n1 1\n255\n1 2 3\n").unwrap();
    let mut client = Client::start();
    let text = "camera 4\nsphere\n  dimension 1\n  center 0 0 -5\n  texture wood.ppm\nlight\n  location 0 5 0\n  color 1 1 1\n";
    let uri = uri_of(&dir.path().join("a.txt"));
    assert_eq!(client.open(&uri, "raytracer", text), Vec::<Value>::new());
    let missing = uri_of(&dir.path().join("sub").join("b.txt"));
    let diagnostics = client.open(&missing, "raytracer", text);
    assert_eq!(
        diagnostics[0]["code"], "scene::texture_not_found",
        "{diagnostics:?}"
    );

    let json_uri = uri_of(&dir.path().join("c.json"));
    let diagnostics = client.open(
        &json_uri,
        "json",
        r#"{"format": "raytracer-scene/1", "camera": {"resolution": 0}}"#,
    );
    let codes: Vec<&str> = diagnostics
        .iter()
        .map(|d| d["code"].as_str().unwrap())
        .collect();
    assert_eq!(codes, ["scene::resolution_out_of_range"], "{diagnostics:?}");
    let symbols = client.request(
        "textDocument/documentSymbol",
        json!({"textDocument": {"uri": json_uri}}),
    );
    assert_eq!(symbols[0]["name"], "camera");

    // Hover on the texture path: the resolved file and its size.
    let hover = client.request(
        "textDocument/hover",
        json!({"textDocument": {"uri": uri}, "position": {"line": 4, "character": 12}}),
    );
    let shown = hover["contents"]["value"].as_str().unwrap();
    assert!(
        shown.contains(&dir.path().join("wood.ppm").display().to_string()),
        "{shown}"
    );
    assert!(shown.contains("1 × 1 pixels"), "{shown}");
    assert_eq!(client.shut_down(), Some(0));
}

#[test]
fn formatting_outline_hover_and_completion() {
    let dir = tempfile::tempdir().unwrap();
    std::fs::write(dir.path().join("wood.ppm"), "P3\n1 1\n255\n1 2 3\n").unwrap();
    std::fs::write(dir.path().join("notes.md"), "").unwrap();
    std::fs::write(dir.path().join("old #2.png"), "").unwrap();
    let uri = uri_of(&dir.path().join("scene.txt"));
    let mut client = Client::start();
    let text = "camera 4 # four\nsphere dimension 1 center 0 0 -5\nsphere\n";
    client.open(&uri, "raytracer", text);

    let edits = client.request(
        "textDocument/formatting",
        json!({"textDocument": {"uri": uri}, "options": {"tabSize": 2, "insertSpaces": true}}),
    );
    assert_eq!(
        edits[0]["newText"],
        "camera 4 # four\n\nsphere\n  dimension 1\n  center 0 0 -5\n\nsphere\n"
    );
    assert_eq!(edits[0]["range"]["end"], json!({"line": 3, "character": 0}));

    let symbols = client.request(
        "textDocument/documentSymbol",
        json!({"textDocument": {"uri": uri}}),
    );
    let names: Vec<&str> = symbols
        .as_array()
        .unwrap()
        .iter()
        .map(|s| s["name"].as_str().unwrap())
        .collect();
    assert_eq!(names, ["camera", "sphere 1", "sphere 2"]);
    assert_eq!(symbols[1]["children"][1]["name"], "center");

    let hover = |client: &mut Client, line: u32, character: u32| {
        let result = client.request(
            "textDocument/hover",
            json!({"textDocument": {"uri": uri}, "position": {"line": line, "character": character}}),
        );
        result["contents"]["value"]
            .as_str()
            .unwrap_or("")
            .to_string()
    };
    assert!(hover(&mut client, 1, 2).contains("`dimension RADIUS`"));
    let center = hover(&mut client, 1, 20);
    assert!(center.contains("required in every `sphere`"), "{center}");
    assert!(center.contains("the centre, in world units"), "{center}");
    assert!(hover(&mut client, 0, 2).contains("N × N pixels"));
    client.change(&uri, 3, "sphere color 1 0 0");
    let color = hover(&mut client, 0, 8);
    assert!(color.contains("default `1 1 1`"), "{color}");

    let complete = |client: &mut Client, text: &str, line: u32, character: u32| {
        client.change(&uri, 9, text);
        let result = client.request(
            "textDocument/completion",
            json!({"textDocument": {"uri": uri}, "position": {"line": line, "character": character}}),
        );
        let mut labels: Vec<String> = result
            .as_array()
            .unwrap()
            .iter()
            .map(|i| i["label"].as_str().unwrap().to_string())
            .collect();
        labels.sort();
        labels
    };
    assert_eq!(
        complete(&mut client, "", 0, 0),
        ["camera", "light", "plane", "sphere"]
    );
    assert_eq!(
        complete(&mut client, "camera 4\nlight\n  color 1 1 1\n  ", 3, 2),
        ["light", "location", "plane", "sphere"]
    );
    assert_eq!(
        complete(&mut client, "light\n  color 1 ", 1, 10),
        Vec::<String>::new()
    );
    assert_eq!(
        complete(&mut client, "sphere\n  texture ", 1, 10),
        ["old #2.png", "wood.ppm"]
    );
    assert_eq!(
        complete(&mut client, "sphere\n  texture w", 1, 11),
        ["old #2.png", "wood.ppm"]
    );
    assert_eq!(client.shut_down(), Some(0));
}

#[test]
fn quick_fixes_and_fix_all() {
    let dir = tempfile::tempdir().unwrap();
    let uri = uri_of(&dir.path().join("scene.txt"));
    let mut client = Client::start();
    let diagnostics = client.open(&uri, "raytracer", MISTAKES);
    let actions_at = |client: &mut Client, line: u32, only: Value| {
        client.request(
            "textDocument/codeAction",
            json!({"textDocument": {"uri": uri},
                   "range": {"start": {"line": line, "character": 2}, "end": {"line": line, "character": 2}},
                   "context": {"diagnostics": diagnostics, "only": only}}),
        )
    };
    // The headup's projection: a safe fix, preferred, and the fix-all.
    let actions = actions_at(&mut client, 9, Value::Null);
    let titles: Vec<&str> = actions
        .as_array()
        .unwrap()
        .iter()
        .map(|a| a["title"].as_str().unwrap())
        .collect();
    assert_eq!(
        titles,
        [
            "project `headup` onto the plane",
            "apply every safe fix (1)"
        ]
    );
    assert_eq!(actions[0]["kind"], "quickfix");
    assert_eq!(actions[0]["isPreferred"], true);
    assert_eq!(
        actions[0]["diagnostics"][0]["code"],
        "scene::headup_not_perpendicular"
    );
    let edits = &actions[0]["edit"]["changes"][&uri];
    assert_eq!(edits.as_array().unwrap().len(), 1, "{edits}");
    assert_eq!(edits[0]["newText"], "0");
    assert_eq!(
        edits[0]["range"]["start"],
        json!({"line": 9, "character": 11})
    );
    // The misspelt attribute: an unsafe fix, offered but not preferred.
    let actions = actions_at(&mut client, 4, json!(["quickfix"]));
    assert_eq!(actions.as_array().unwrap().len(), 1, "{actions}");
    assert_eq!(actions[0]["title"], "replace `colr` with `color`");
    assert_eq!(actions[0]["isPreferred"], false);
    // Fix-all only: the safe fixes of the whole document.
    let fix_all = actions_at(&mut client, 0, json!(["source.fixAll"]));
    assert_eq!(fix_all.as_array().unwrap().len(), 1);
    assert_eq!(fix_all[0]["kind"], "source.fixAll");
    assert_eq!(
        fix_all[0]["edit"]["changes"][&uri]
            .as_array()
            .unwrap()
            .len(),
        1
    );
    // A missing attribute: an unsafe fix that inserts the registry's
    // example lines, an empty range replaced after the section's last line.
    let plane_uri = uri_of(&dir.path().join("plane.txt"));
    let plane = "camera 4\nplane\n  dimension 4 4\n  center 0 -1 -5\n";
    let plane_diagnostics = client.open(&plane_uri, "raytracer", plane);
    let actions = client.request(
        "textDocument/codeAction",
        json!({"textDocument": {"uri": plane_uri},
               "range": {"start": {"line": 1, "character": 0}, "end": {"line": 1, "character": 0}},
               "context": {"diagnostics": plane_diagnostics}}),
    );
    assert_eq!(actions.as_array().unwrap().len(), 1, "{actions}");
    assert_eq!(
        actions[0]["title"],
        "add `normal 0 1 0` and `headup 0 0 -1`, the example values"
    );
    assert_eq!(actions[0]["isPreferred"], false);
    let edit = &actions[0]["edit"]["changes"][&plane_uri][0];
    let end_of_center = json!({"line": 3, "character": 16});
    assert_eq!(
        edit["range"],
        json!({"start": end_of_center, "end": end_of_center})
    );
    assert_eq!(edit["newText"], "\n  normal 0 1 0\n  headup 0 0 -1");
    assert_eq!(client.shut_down(), Some(0));
}

#[test]
fn protocol_errors_and_endings() {
    let mut client = Client::start();
    let response = client.request_raw("textDocument/hover", json!({"nonsense": true}));
    assert_eq!(response["error"]["code"], json!(-32602), "{response}");
    let response = client.request_raw("workspace/unknown", json!({}));
    assert_eq!(response["error"]["code"], json!(-32601), "{response}");
    // Requests about documents never opened get empty answers.
    let result = client.request(
        "textDocument/formatting",
        json!({"textDocument": {"uri": "file:///nowhere.txt"}, "options": {"tabSize": 2, "insertSpaces": true}}),
    );
    assert_eq!(result, Value::Null);
    assert_eq!(client.shut_down(), Some(0));

    // `exit` without `shutdown`: exit code 1.
    let mut client = Client::start();
    client.notify("exit", Value::Null);
    client.stdin = None;
    assert_eq!(client.child.wait().unwrap().code(), Some(1));

    // Bytes that are no protocol, then the end of input: no crash, exit 1.
    let mut child = Command::new(support::bin())
        .arg("lsp")
        .stdin(Stdio::piped())
        .stdout(Stdio::null())
        .stderr(Stdio::piped())
        .spawn()
        .unwrap();
    let mut stdin = child.stdin.take().unwrap();
    let _ = stdin.write_all(b"Content-Length: 5\r\n\r\n\xff\xfe{]\x00garbage\r\n\r\n");
    drop(stdin);
    let output = child.wait_with_output().unwrap();
    assert!(matches!(output.status.code(), Some(1 | 2)), "{output:?}");
    let stderr = String::from_utf8_lossy(&output.stderr);
    assert!(!stderr.contains("panicked"), "{stderr}");
}

/// `raytracer check --format json` on `text`: (code, message, line) of each.
fn check_says(dir: &Path, text: &str) -> Vec<(String, String, u64)> {
    let path = dir.join("final.txt");
    std::fs::write(&path, text).unwrap();
    let output = support::run(&["check", "--format", "json", path.to_str().unwrap()]);
    let all: Vec<Value> = serde_json::from_slice(&output.stdout).unwrap();
    all.iter()
        .map(|d| {
            let line = d["labels"][0]["line"].as_u64().unwrap_or(1) - 1;
            let message = d["message"].as_str().unwrap().to_string();
            (d["code"].as_str().unwrap().to_string(), message, line)
        })
        .collect()
}

/// One edit: replace a range of the text (by character index) with a
/// fragment of scene text or junk.
fn edit() -> impl Strategy<Value = (usize, usize, String)> {
    let fragment = prop_oneof![
        Just("sphere ".to_string()),
        Just("\ncamera 4\n".to_string()),
        Just(" center 0 0 -5".to_string()),
        Just("\n  normal 0 2 0 headup 1 1 0".to_string()),
        Just("plane\n".to_string()),
        Just("# note\n".to_string()),
        Just("\"".to_string()),
        Just("1e999 ".to_string()),
        "[a-z0-9 .\n#\"é😀-]{0,12}",
    ];
    (0usize..400, 0usize..20, fragment)
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(256))]
    /// Any sequence of edits: the server survives, and what it last
    /// published equals `check` on the final text.
    #[test]
    fn random_edits_end_where_check_does(edits in prop::collection::vec(edit(), 1..25)) {
        let dir = tempfile::tempdir().unwrap();
        let uri = uri_of(&dir.path().join("final.txt"));
        let mut client = Client::start();
        let mut text = MISTAKES.to_string();
        client.open(&uri, "raytracer", &text);
        let mut version = 1;
        for (at, length, insert) in edits {
            let chars: Vec<char> = text.chars().collect();
            let start = at.min(chars.len());
            let end = (start + length).min(chars.len());
            text = chars[..start].iter().chain(insert.chars().collect::<Vec<_>>().iter()).chain(chars[end..].iter()).collect();
            version += 1;
            client.change(&uri, version, &text);
        }
        let published = client.diagnostics(&uri, Some(version));
        let ours: Vec<(String, String, u64)> = published
            .iter()
            .map(|d| {
                let message = d["message"].as_str().unwrap();
                let message = message.split("\nhelp: ").next().unwrap().to_string();
                (d["code"].as_str().unwrap().to_string(), message, d["range"]["start"]["line"].as_u64().unwrap())
            })
            .collect();
        prop_assert_eq!(ours, check_says(dir.path(), &text));
        prop_assert_eq!(client.shut_down(), Some(0));
    }
}
