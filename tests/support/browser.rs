//! Headless Chromium driven over the DevTools protocol (JSON over a
//! WebSocket, with `tungstenite`), for the tests of pages in a real
//! browser: `raytracer preview`'s (tests/preview_browser.rs), `grade`'s
//! reports (tests/grade_browser.rs) and the playground
//! (tests/playground.rs).

use std::io::{BufRead, BufReader, Read, Write};
use std::net::{SocketAddr, TcpStream};
use std::process::{Child, Command, Stdio};
use std::sync::mpsc;
use std::time::Duration;

use serde_json::{json, Value};
use tungstenite::{Message, WebSocket};

/// How long a step may take before the test fails.
pub const PATIENCE: Duration = Duration::from_secs(60);

/// True when `chromium` runs; under CI its absence is a failure.
pub fn chromium_available(test: &str) -> bool {
    crate::support::tool_available("chromium", test, "apt-get install chromium")
}

/// A headless Chromium with one page, driven over the DevTools protocol;
/// killed when dropped. tests/grade_browser.rs drives the reports of
/// `raytracer grade` with it too, and tests/playground.rs the playground.
pub struct Browser {
    child: Child,
    socket: WebSocket<TcpStream>,
    next_id: u64,
    _profile: tempfile::TempDir,
}

impl Browser {
    /// Start Chromium on a blank page `width`×`height` CSS pixels.
    pub fn start(width: u32, height: u32) -> Browser {
        let profile = tempfile::tempdir().expect("profile folder");
        let mut child = Command::new("chromium")
            .args([
                "--headless",
                // The tests run as root in CI, where the sandbox cannot start.
                "--no-sandbox",
                "--disable-gpu",
                // Nothing but the page under test reaches the network.
                "--disable-background-networking",
                "--disable-component-update",
                "--disable-sync",
                "--disable-dev-shm-usage",
                "--no-first-run",
                "--no-default-browser-check",
                "--hide-scrollbars",
                "--remote-debugging-address=127.0.0.1",
                "--remote-debugging-port=0",
                &format!("--window-size={width},{height}"),
            ])
            .arg(format!("--user-data-dir={}", profile.path().display()))
            .arg("about:blank")
            .stdin(Stdio::null())
            .stdout(Stdio::null())
            .stderr(Stdio::piped())
            .spawn()
            .expect("start chromium");
        // Chromium says where its DevTools endpoint is on stderr.
        let stderr = child.stderr.take().expect("stderr");
        let (found, endpoint) = mpsc::channel();
        std::thread::spawn(move || {
            for line in BufReader::new(stderr).lines().map_while(Result::ok) {
                if let Some(url) = line.strip_prefix("DevTools listening on ") {
                    let _ = found.send(url.to_string());
                }
            }
        });
        let browser_url = endpoint
            .recv_timeout(PATIENCE)
            .expect("chromium prints its DevTools URL");
        let address = browser_url
            .trim_start_matches("ws://")
            .split('/')
            .next()
            .expect("host:port")
            .parse()
            .expect("a socket address");
        let targets = targets(address);
        let page_url = targets
            .as_array()
            .and_then(|targets| targets.iter().find(|t| t["type"] == "page"))
            .and_then(|page| page["webSocketDebuggerUrl"].as_str())
            .expect("a page target")
            .to_string();
        let stream = TcpStream::connect(address).expect("connect to DevTools");
        stream.set_read_timeout(Some(PATIENCE)).expect("timeout");
        let (socket, _) = tungstenite::client(page_url.as_str(), stream).expect("WebSocket");
        let mut browser = Browser {
            child,
            socket,
            next_id: 0,
            _profile: profile,
        };
        browser.call(
            "Emulation.setDeviceMetricsOverride",
            json!({"width": width, "height": height, "deviceScaleFactor": 1, "mobile": false}),
        );
        browser
    }

    /// Call `method` and return its result (events on the way are skipped).
    pub fn call(&mut self, method: &str, params: Value) -> Value {
        let id = self.send(method, params);
        loop {
            let reply = self.receive();
            if reply["id"] == id {
                assert!(reply["error"].is_null(), "{method}: {reply}");
                return reply["result"].clone();
            }
        }
    }

    /// Send a call of `method`; its id.
    fn send(&mut self, method: &str, params: Value) -> u64 {
        self.next_id += 1;
        let message = json!({"id": self.next_id, "method": method, "params": params});
        self.socket
            .send(Message::Text(message.to_string().into()))
            .expect("send to DevTools");
        self.next_id
    }

    /// The next message from DevTools: a reply or an event.
    fn receive(&mut self) -> Value {
        loop {
            if let Message::Text(text) = self.socket.read().expect("read from DevTools") {
                return serde_json::from_str(text.as_str()).expect("DevTools JSON");
            }
        }
    }

    /// The value of the JavaScript expression `expression` (awaited when it
    /// is a promise).
    pub fn eval(&mut self, expression: &str) -> Value {
        let result = self.call(
            "Runtime.evaluate",
            json!({"expression": expression, "returnByValue": true, "awaitPromise": true}),
        );
        assert!(
            result["exceptionDetails"].is_null(),
            "{expression}: {result}"
        );
        result["result"]["value"].clone()
    }

    /// Wait in the page until `condition` (JavaScript) holds, then return
    /// the value of `value`; fails after [`PATIENCE`].
    pub fn wait_for(&mut self, condition: &str, value: &str) -> Value {
        let limit = PATIENCE.as_millis();
        let found = self.eval(&format!(
            "new Promise((resolve) => {{
               const start = Date.now();
               const check = () => {{
                 if ({condition}) resolve({{ ok: true, value: ({value}) }});
                 else if (Date.now() - start > {limit}) resolve({{ ok: false, value: document.body.outerHTML }});
                 else setTimeout(check, 10);
               }};
               check();
             }})"
        ));
        assert_eq!(
            found["ok"], true,
            "waited for {condition}: {}",
            found["value"]
        );
        found["value"].clone()
    }

    /// Load `url` and wait for its `load` event, so that scripts then run
    /// in the new document.
    pub fn navigate(&mut self, url: &str) {
        self.call("Page.enable", json!({}));
        self.send("Page.navigate", json!({ "url": url }));
        loop {
            let message = self.receive();
            assert!(message["error"].is_null(), "Page.navigate: {message}");
            if message["method"] == "Page.loadEventFired" {
                return;
            }
        }
    }

    /// A PNG of the page as it is shown.
    pub fn screenshot(&mut self) -> Vec<u8> {
        let shot = self.call("Page.captureScreenshot", json!({"format": "png"}));
        let data = shot["data"].as_str().expect("base64 data");
        data_encoding::BASE64
            .decode(data.as_bytes())
            .expect("base64")
    }
}

impl Drop for Browser {
    fn drop(&mut self) {
        let _ = self.child.kill();
        let _ = self.child.wait();
    }
}

/// The targets Chromium's DevTools HTTP endpoint at `address` lists.
fn targets(address: SocketAddr) -> Value {
    let mut stream = TcpStream::connect(address).expect("connect to DevTools");
    stream.set_read_timeout(Some(PATIENCE)).expect("timeout");
    write!(
        stream,
        "GET /json/list HTTP/1.1\r\nHost: {address}\r\nConnection: close\r\n\r\n"
    )
    .expect("send request");
    let mut reader = BufReader::new(stream);
    let mut length = None;
    loop {
        let mut line = String::new();
        reader.read_line(&mut line).expect("read the head");
        let line = line.trim_end();
        if line.is_empty() {
            break;
        }
        if let Some((name, value)) = line.split_once(':') {
            if name.eq_ignore_ascii_case("content-length") {
                length = value.trim().parse::<usize>().ok();
            }
        }
    }
    let mut body = vec![0; length.expect("a Content-Length")];
    reader.read_exact(&mut body).expect("read the body");
    serde_json::from_slice(&body).expect("the target list")
}
