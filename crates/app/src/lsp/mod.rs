//! `raytracer lsp`: a Language Server Protocol server over stdio.
//!
//! One thread runs [`serve`], a loop over the messages lsp-server reads
//! from stdin: documents are kept whole (full sync; ranged changes are
//! applied too), and each change schedules the document's diagnostics
//! after a quiet spell (the debounce), so typing does not re-check on
//! every keystroke; opening publishes at once. Requests are answered from
//! the current text through the library: the front end for diagnostics,
//! [`raytracer_scene::format`] for formatting, the parser and the language table for
//! the outline, hover and completion, and the fixes the diagnostics carry
//! for code actions. Nothing here panics on a client's input: bad parameters
//! get an error response, unknown documents an empty answer.
//!
//! Semantic tokens (`tokens.rs`) come from the syntax tree and the comments
//! beside it, marked `invalid` where the diagnostics' errors point.
//!
//! The protocol's ending: `shutdown` is answered, then `exit` ends the
//! loop with [`Ending::Shutdown`] (exit code 0); `exit` without `shutdown`,
//! or the client closing stdin, ends with [`Ending::Abandoned`] (exit 1).

mod actions;
mod completion;
mod document;
mod hover;
mod outline;
pub mod position;
mod tokens;

use std::collections::HashMap;
use std::time::{Duration, Instant};

use lsp_server::{Connection, ErrorCode, Message, Notification, Request, RequestId, Response};
use lsp_types::notification::{self, Notification as _};
use lsp_types::request::{self, Request as _};
use lsp_types::{
    CodeActionKind, CodeActionOptions, CodeActionProviderCapability, CompletionOptions,
    HoverProviderCapability, OneOf, PublishDiagnosticsParams, ServerCapabilities,
    TextDocumentSyncCapability, TextDocumentSyncKind, TextEdit, Url,
};
use serde::de::DeserializeOwned;
use serde_json::Value;

pub use document::Document;

/// How the server is set up.
#[derive(Clone, Debug)]
pub struct Options {
    /// How long a document must go unchanged before it is re-checked.
    pub debounce: Duration,
}

/// How the conversation with the client ended.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Ending {
    /// `shutdown` then `exit`: exit code 0.
    Shutdown,
    /// `exit` without `shutdown`, or stdin closed: exit code 1.
    Abandoned,
}

/// The connection failed before the conversation began.
#[derive(Debug, thiserror::Error, miette::Diagnostic)]
#[error("the language server could not start: {reason}")]
#[diagnostic(
    code(io::lsp),
    help("`raytracer lsp` speaks the Language Server Protocol on stdin and stdout; start it from an editor")
)]
pub struct StartError {
    pub reason: String,
}

/// Serve on stdin and stdout until the client ends the conversation.
pub fn serve_stdio(options: &Options) -> Result<Ending, StartError> {
    let (connection, io_threads) = Connection::stdio();
    let ending = serve(&connection, options);
    drop(connection);
    // The reader stops after `exit` or at the end of stdin, the writer when
    // the connection is dropped.
    if ending.is_ok() {
        let _ = io_threads.join();
    }
    ending
}

/// Serve on `connection` (stdio, or memory in tests).
pub fn serve(connection: &Connection, options: &Options) -> Result<Ending, StartError> {
    let (id, params) = connection.initialize_start().map_err(|e| StartError {
        reason: e.to_string(),
    })?;
    let docs = serde_json::from_value::<lsp_types::InitializeParams>(params)
        .ok()
        .and_then(|p| p.initialization_options)
        .and_then(|o| o.get("diagnosticsDocs")?.as_str()?.parse().ok());
    let result = serde_json::json!({
        "capabilities": capabilities(),
        "serverInfo": {"name": "raytracer", "version": env!("CARGO_PKG_VERSION")},
    });
    connection
        .initialize_finish(id, result)
        .map_err(|e| StartError {
            reason: e.to_string(),
        })?;
    let mut server = Server {
        connection,
        options: options.clone(),
        docs,
        documents: HashMap::new(),
        due: HashMap::new(),
    };
    Ok(server.run())
}

fn capabilities() -> ServerCapabilities {
    ServerCapabilities {
        text_document_sync: Some(TextDocumentSyncCapability::Kind(TextDocumentSyncKind::FULL)),
        document_formatting_provider: Some(OneOf::Left(true)),
        document_symbol_provider: Some(OneOf::Left(true)),
        hover_provider: Some(HoverProviderCapability::Simple(true)),
        completion_provider: Some(CompletionOptions {
            trigger_characters: Some(vec![" ".to_string()]),
            ..CompletionOptions::default()
        }),
        code_action_provider: Some(CodeActionProviderCapability::Options(CodeActionOptions {
            code_action_kinds: Some(vec![
                CodeActionKind::QUICKFIX,
                CodeActionKind::SOURCE_FIX_ALL,
            ]),
            ..CodeActionOptions::default()
        })),
        semantic_tokens_provider: Some(
            lsp_types::SemanticTokensOptions {
                legend: tokens::legend(),
                full: Some(lsp_types::SemanticTokensFullOptions::Bool(true)),
                range: Some(true),
                ..lsp_types::SemanticTokensOptions::default()
            }
            .into(),
        ),
        ..ServerCapabilities::default()
    }
}

struct Server<'a> {
    connection: &'a Connection,
    options: Options,
    docs: Option<Url>,
    documents: HashMap<Url, Document>,
    /// When each changed document is to be re-checked.
    due: HashMap<Url, Instant>,
}

/// A request's answer: its result, or an error code and message.
type Answer = Result<Value, (ErrorCode, String)>;

impl Server<'_> {
    fn run(&mut self) -> Ending {
        loop {
            let next = self.due.values().min().copied();
            let message = match next {
                Some(at) => {
                    let wait = at.saturating_duration_since(Instant::now());
                    match self.connection.receiver.recv_timeout(wait) {
                        Ok(message) => message,
                        Err(e) if e.is_timeout() => {
                            self.publish_due();
                            continue;
                        }
                        Err(_) => return Ending::Abandoned,
                    }
                }
                None => match self.connection.receiver.recv() {
                    Ok(message) => message,
                    Err(_) => return Ending::Abandoned,
                },
            };
            match message {
                Message::Request(request) if request.method == request::Shutdown::METHOD => {
                    self.respond(request.id, Ok(Value::Null));
                    return self.after_shutdown();
                }
                Message::Request(request) => {
                    let answer = self.answer(&request);
                    self.respond(request.id, answer);
                }
                Message::Notification(n) if n.method == notification::Exit::METHOD => {
                    return Ending::Abandoned;
                }
                Message::Notification(n) => self.notified(n),
                Message::Response(_) => {}
            }
        }
    }

    /// After `shutdown`, only `exit` is expected; other requests are errors.
    fn after_shutdown(&mut self) -> Ending {
        while let Ok(message) = self.connection.receiver.recv() {
            match message {
                Message::Notification(n) if n.method == notification::Exit::METHOD => break,
                Message::Request(request) => self.respond(
                    request.id,
                    Err((
                        ErrorCode::InvalidRequest,
                        "the server is shutting down".to_string(),
                    )),
                ),
                _ => {}
            }
        }
        Ending::Shutdown
    }

    fn respond(&self, id: RequestId, answer: Answer) {
        let response = match answer {
            Ok(result) => Response::new_ok(id, result),
            Err((code, message)) => Response::new_err(id, code as i32, message),
        };
        // A closed channel means the client is gone: the loop sees it next.
        let _ = self.connection.sender.send(response.into());
    }

    fn answer(&mut self, request: &Request) -> Answer {
        match request.method.as_str() {
            request::Formatting::METHOD => {
                let p: lsp_types::DocumentFormattingParams = params(request)?;
                Ok(self.formatting(&p.text_document.uri))
            }
            request::DocumentSymbolRequest::METHOD => {
                let p: lsp_types::DocumentSymbolParams = params(request)?;
                let symbols = self
                    .documents
                    .get(&p.text_document.uri)
                    .map(outline::symbols);
                Ok(serde_json::to_value(symbols.unwrap_or_default()).unwrap_or_default())
            }
            request::HoverRequest::METHOD => {
                let p: lsp_types::HoverParams = params(request)?;
                let at = p.text_document_position_params;
                let hover = self.documents.get(&at.text_document.uri).and_then(|d| {
                    let offset = position::Positions::new(&d.text).offset(at.position);
                    hover::hover(d, offset)
                });
                Ok(serde_json::to_value(hover).unwrap_or_default())
            }
            request::Completion::METHOD => {
                let p: lsp_types::CompletionParams = params(request)?;
                let at = p.text_document_position;
                let items = self.documents.get(&at.text_document.uri).map(|d| {
                    let offset = position::Positions::new(&d.text).offset(at.position);
                    completion::complete(d, offset)
                });
                Ok(serde_json::to_value(items.unwrap_or_default()).unwrap_or_default())
            }
            request::CodeActionRequest::METHOD => {
                let p: lsp_types::CodeActionParams = params(request)?;
                let found = self.checked(&p.text_document.uri).map(|d| {
                    let fixed = d.diagnostics();
                    actions::actions(&d.uri, &d.text, fixed, p.range, p.context.only.as_deref())
                });
                Ok(serde_json::to_value(found.unwrap_or_default()).unwrap_or_default())
            }
            request::SemanticTokensFullRequest::METHOD => {
                let p: lsp_types::SemanticTokensParams = params(request)?;
                Ok(self.semantic_tokens(&p.text_document.uri, None))
            }
            request::SemanticTokensRangeRequest::METHOD => {
                let p: lsp_types::SemanticTokensRangeParams = params(request)?;
                Ok(self.semantic_tokens(&p.text_document.uri, Some(p.range)))
            }
            method => Err((
                ErrorCode::MethodNotFound,
                format!("`{method}` is not supported"),
            )),
        }
    }

    /// One edit replacing the whole text, or none when it is formatted
    /// already or has syntax errors (the diagnostics show those).
    fn formatting(&self, uri: &Url) -> Value {
        let Some(document) = self.documents.get(uri) else {
            return Value::Null;
        };
        if document.language != raytracer_scene::frontend::Language::Text {
            return Value::Null;
        }
        match raytracer_scene::format::format(&document.text) {
            Ok(formatted) if formatted != document.text => {
                let index = position::Positions::new(&document.text);
                let whole = lsp_types::Range::new(lsp_types::Position::new(0, 0), index.end());
                serde_json::to_value(vec![TextEdit::new(whole, formatted)]).unwrap_or_default()
            }
            Ok(_) => serde_json::json!([]),
            Err(_) => Value::Null,
        }
    }

    /// The document's semantic tokens (all, or those in `within`), each
    /// marked `invalid` where an error of its diagnostics points; none for
    /// JSON, which its client colours itself.
    fn semantic_tokens(&mut self, uri: &Url, within: Option<lsp_types::Range>) -> Value {
        let Some(document) = self.checked(uri) else {
            return Value::Null;
        };
        if document.language != raytracer_scene::frontend::Language::Text {
            return Value::Null;
        }
        let errors: Vec<lsp_types::Range> = document
            .diagnostics()
            .iter()
            .filter(|(d, _)| d.severity == Some(lsp_types::DiagnosticSeverity::ERROR))
            .map(|(d, _)| d.range)
            .collect();
        serde_json::to_value(tokens::tokens(&document.text, &errors, within)).unwrap_or_default()
    }

    fn notified(&mut self, n: Notification) {
        match n.method.as_str() {
            notification::DidOpenTextDocument::METHOD => {
                if let Ok(p) =
                    serde_json::from_value::<lsp_types::DidOpenTextDocumentParams>(n.params)
                {
                    let d = p.text_document;
                    let document = Document::new(d.uri.clone(), d.text, d.version, &d.language_id);
                    self.documents.insert(d.uri.clone(), document);
                    self.due.insert(d.uri, Instant::now());
                }
            }
            notification::DidChangeTextDocument::METHOD => {
                if let Ok(p) =
                    serde_json::from_value::<lsp_types::DidChangeTextDocumentParams>(n.params)
                {
                    let uri = p.text_document.uri;
                    if let Some(document) = self.documents.get_mut(&uri) {
                        document.apply(p.content_changes, p.text_document.version);
                        self.due.insert(uri, Instant::now() + self.options.debounce);
                    }
                }
            }
            notification::DidCloseTextDocument::METHOD => {
                if let Ok(p) =
                    serde_json::from_value::<lsp_types::DidCloseTextDocumentParams>(n.params)
                {
                    let uri = p.text_document.uri;
                    self.documents.remove(&uri);
                    self.due.remove(&uri);
                    self.publish(uri, Vec::new(), None);
                }
            }
            _ => {}
        }
    }

    /// Re-check every document whose quiet spell is over.
    fn publish_due(&mut self) {
        let now = Instant::now();
        let ready: Vec<Url> = self
            .due
            .iter()
            .filter(|(_, &at)| at <= now)
            .map(|(uri, _)| uri.clone())
            .collect();
        for uri in ready {
            self.due.remove(&uri);
            if let Some(document) = self.checked(&uri) {
                let diagnostics = document
                    .diagnostics()
                    .iter()
                    .map(|(d, _)| d.clone())
                    .collect();
                let version = Some(document.version);
                self.publish(uri, diagnostics, version);
            }
        }
    }

    /// The open document at `uri`, checked unless its last check was of
    /// this version.
    fn checked(&mut self, uri: &Url) -> Option<&Document> {
        let document = self.documents.get_mut(uri)?;
        document.check_if_changed(self.docs.as_ref());
        Some(document)
    }

    fn publish(&self, uri: Url, diagnostics: Vec<lsp_types::Diagnostic>, version: Option<i32>) {
        let params = PublishDiagnosticsParams::new(uri, diagnostics, version);
        let n = Notification::new(notification::PublishDiagnostics::METHOD.to_string(), params);
        let _ = self.connection.sender.send(n.into());
    }
}

/// A request's parameters, or an `InvalidParams` error.
fn params<P: DeserializeOwned>(request: &Request) -> Result<P, (ErrorCode, String)> {
    serde_json::from_value(request.params.clone())
        .map_err(|e| (ErrorCode::InvalidParams, format!("invalid parameters: {e}")))
}

#[cfg(test)]
mod tests {
    use serde_json::json;

    use super::*;

    fn notification(method: &str, params: Value) -> Notification {
        Notification::new(method.to_string(), params)
    }

    /// Code actions (and semantic tokens) of a version already checked
    /// are answered from that check; a change makes the next request check
    /// once more.
    #[test]
    fn requests_answer_from_the_last_check_of_a_version() {
        let (server_side, _client) = Connection::memory();
        let mut server = Server {
            connection: &server_side,
            options: Options {
                debounce: Duration::ZERO,
            },
            docs: None,
            documents: HashMap::new(),
            due: HashMap::new(),
        };
        let uri = Url::parse("file:///scenes/ball.txt").expect("a URI");
        let text = "camera 4\nsphere dimension 1 center 0 0 -5 colour 1 0 0\n";
        server.notified(notification(
            notification::DidOpenTextDocument::METHOD,
            json!({"textDocument": {"uri": uri, "languageId": "raytracer", "version": 1, "text": text}}),
        ));
        server.publish_due();
        let checks = |server: &Server<'_>| server.documents[&uri].checks;
        assert_eq!(checks(&server), 1);
        let actions = Request::new(
            RequestId::from(1),
            request::CodeActionRequest::METHOD.to_string(),
            json!({
                "textDocument": {"uri": uri},
                "range": {"start": {"line": 1, "character": 0}, "end": {"line": 1, "character": 0}},
                "context": {"diagnostics": []},
            }),
        );
        let tokens = Request::new(
            RequestId::from(2),
            request::SemanticTokensFullRequest::METHOD.to_string(),
            json!({"textDocument": {"uri": uri}}),
        );
        let first = server.answer(&actions).expect("code actions");
        assert_eq!(
            first[0]["title"], "replace `colour` with `color`",
            "{first}"
        );
        assert_eq!(server.answer(&actions).expect("code actions"), first);
        server.answer(&tokens).expect("semantic tokens");
        assert_eq!(
            checks(&server),
            1,
            "a request re-checked an unchanged version"
        );
        server.notified(notification(
            notification::DidChangeTextDocument::METHOD,
            json!({"textDocument": {"uri": uri, "version": 2}, "contentChanges": [{"text": "camera 4\nsphere dimension 1 center 0 0 -5\n"}]}),
        ));
        assert_eq!(server.answer(&actions).expect("code actions"), json!([]));
        server.answer(&actions).expect("code actions");
        assert_eq!(checks(&server), 2);
    }
}
