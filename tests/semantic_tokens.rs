//! Semantic tokens from the language server, asked for as a client does
//! (over an in-memory connection to [`raytracer_app::lsp::serve`]) and decoded
//! with the legend the server announced: every token of a scene at its
//! line, UTF-16 column and length, including tokens after multibyte text
//! on their line, the `invalid` modifier where the diagnostics put an
//! error, and the range request.

use std::time::Duration;

use lsp_server::{Connection, Message, Notification, Request, RequestId};
use raytracer_app::lsp::{serve, Options};
use serde_json::{json, Value};

/// Accents and an emoji (two UTF-16 units, four bytes) in a comment, a
/// texture path that is missing, an unknown attribute with an accent, a
/// light without its required colour.
const SCENE: &str = "# scène 😀\ncamera 40\nsphere center 0 0 -5 # ball\n  dimension 1 texture \"é😀.ppm\" color 1 1 1\n  cölor 0.5 0.5 0.5\nlight location 0 5 0\n";

struct Session {
    client: Connection,
    server: Option<std::thread::JoinHandle<()>>,
    legend: Value,
    next_id: i32,
    /// The scene's folder, where no texture is: its path is an error.
    dir: tempfile::TempDir,
}

impl Session {
    fn start() -> Session {
        let (server_side, client) = Connection::memory();
        let server = std::thread::spawn(move || {
            let options = Options {
                debounce: Duration::ZERO,
            };
            serve(&server_side, &options).expect("the server starts");
        });
        let mut session = Session {
            client,
            server: Some(server),
            legend: Value::Null,
            next_id: 0,
            dir: tempfile::tempdir().unwrap(),
        };
        let result = session.request("initialize", json!({"capabilities": {}}));
        let provider = &result["capabilities"]["semanticTokensProvider"];
        assert_eq!(provider["full"], json!(true), "{provider}");
        assert_eq!(provider["range"], json!(true), "{provider}");
        session.legend = provider["legend"].clone();
        session.notify("initialized", json!({}));
        session.notify(
            "textDocument/didOpen",
            json!({"textDocument": {"uri": session.uri("scene.txt"), "languageId": "raytracer", "version": 1, "text": SCENE}}),
        );
        session
    }

    fn uri(&self, name: &str) -> String {
        lsp_types::Url::from_file_path(self.dir.path().join(name))
            .unwrap()
            .to_string()
    }

    fn notify(&self, method: &str, params: Value) {
        let n = Notification::new(method.to_string(), params);
        self.client.sender.send(n.into()).unwrap();
    }

    fn request(&mut self, method: &str, params: Value) -> Value {
        self.next_id += 1;
        let id = RequestId::from(self.next_id);
        let request = Request::new(id.clone(), method.to_string(), params);
        self.client.sender.send(request.into()).unwrap();
        loop {
            let message = self
                .client
                .receiver
                .recv_timeout(Duration::from_secs(20))
                .expect("a response");
            if let Message::Response(response) = message {
                assert_eq!(response.id, id);
                assert!(response.error.is_none(), "{:?}", response.error);
                return response.result.unwrap_or(Value::Null);
            }
        }
    }

    /// The answer to a `full` request for the document `name`.
    fn full(&mut self, name: &str) -> Value {
        let uri = self.uri(name);
        self.request(
            "textDocument/semanticTokens/full",
            json!({"textDocument": {"uri": uri}}),
        )
    }

    /// The tokens of a `full` or `range` answer, decoded with the legend,
    /// each as `line:column:length type` and its modifiers, separated by
    /// commas.
    fn decode(&self, answer: &Value) -> String {
        let data: Vec<u32> = serde_json::from_value(answer["data"].clone()).unwrap();
        assert_eq!(data.len() % 5, 0, "{data:?}");
        let name = |list: &str, i: usize| self.legend[list][i].as_str().unwrap().to_string();
        let (mut line, mut column) = (0, 0);
        data.chunks(5)
            .map(|t| {
                if t[0] > 0 {
                    column = 0;
                }
                line += t[0];
                column += t[1];
                let modifiers: String = (0..32)
                    .filter(|bit| t[4] & (1 << bit) != 0)
                    .map(|bit| format!(" {}", name("tokenModifiers", bit)))
                    .collect();
                let kind = name("tokenTypes", t[3] as usize);
                format!("{line}:{column}:{} {kind}{modifiers}", t[2])
            })
            .collect::<Vec<_>>()
            .join(", ")
    }

    fn shut_down(mut self) {
        self.request("shutdown", Value::Null);
        self.notify("exit", Value::Null);
        self.server.take().unwrap().join().unwrap();
    }
}

#[test]
fn the_legend_uses_the_standard_token_types() {
    let session = Session::start();
    assert_eq!(
        session.legend,
        json!({
            "tokenTypes": ["keyword", "property", "number", "string", "comment"],
            "tokenModifiers": ["invalid"],
        })
    );
    session.shut_down();
}

#[test]
fn every_token_at_its_utf16_position_with_errors_marked() {
    let mut session = Session::start();
    let answer = session.full("scene.txt");
    let found = session.decode(&answer);
    let expected = [
        // `😀` is two UTF-16 units: the comment is 10 long, not 9 chars.
        "0:0:10 comment",
        "1:0:6 keyword, 1:7:2 number",
        "2:0:6 keyword, 2:7:6 property, 2:14:1 number, 2:16:1 number, 2:18:2 number, \
         2:21:6 comment",
        // The texture is missing: an error labels its path. After
        // `"é😀.ppm"` (12 bytes, 9 UTF-16 units) comes column 32, byte 35.
        "3:2:9 property, 3:12:1 number, 3:14:7 property, 3:22:9 string invalid, \
         3:32:5 property, 3:38:1 number, 3:40:1 number, 3:42:1 number",
        // An unknown attribute is an error; its values are not.
        "4:2:5 property invalid, 4:8:3 number, 4:12:3 number, 4:16:3 number",
        // A light needs a `color`: the error labels its keyword.
        "5:0:5 keyword invalid, 5:6:8 property, 5:15:1 number, 5:17:1 number, 5:19:1 number",
    ];
    assert_eq!(found, expected.join(", "));
    session.shut_down();
}

#[test]
fn a_range_request_answers_the_tokens_in_it() {
    let mut session = Session::start();
    let answer = session.request(
        "textDocument/semanticTokens/range",
        json!({
            "textDocument": {"uri": session.uri("scene.txt")},
            "range": {"start": {"line": 3, "character": 30}, "end": {"line": 4, "character": 7}},
        }),
    );
    assert_eq!(
        session.decode(&answer),
        "3:22:9 string invalid, 3:32:5 property, 3:38:1 number, 3:40:1 number, 3:42:1 number, \
         4:2:5 property invalid"
    );
    session.shut_down();
}

#[test]
fn an_unknown_document_has_no_tokens() {
    let mut session = Session::start();
    assert_eq!(session.full("other.txt"), Value::Null);
    session.shut_down();
}
