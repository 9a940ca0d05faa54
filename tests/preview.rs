//! `raytracer preview` end to end over loopback HTTP: the binary is started
//! on a free port (`--port 0`, the URL read from its first line), and a
//! plain `TcpStream` client fetches the page, the image and the
//! diagnostics, follows the event stream while the scene is edited,
//! broken, deleted and restored, and tries to reach files it must not.
//! tests/preview_browser.rs drives the same page in Chromium.

use std::io::{BufRead, BufReader, Read, Write};
use std::net::{Ipv4Addr, SocketAddr, TcpStream};
use std::path::{Path, PathBuf};
use std::process::{Child, ChildStdout, Command, Stdio};
use std::time::{Duration, Instant};

use serde_json::Value;

use crate::support::{bin, run, write};

/// How long any one wait may take before the test fails.
pub const PATIENCE: Duration = Duration::from_secs(60);

/// A small valid scene; `color` is the sphere's colour.
pub fn scene_text(color: &str) -> String {
    format!(
        "camera 48\n\
         sphere\n  dimension 1\n  center 0 0 -4\n  color {color}\n\
         light\n  location 2 2 0\n  color 1 1 1\n"
    )
}

/// A running `raytracer preview`, killed when dropped.
pub struct Server {
    child: Child,
    /// Kept open so the server's later writes to stdout cannot fail.
    _stdout: BufReader<ChildStdout>,
    pub address: SocketAddr,
}

impl Server {
    /// Start `raytracer preview SCENE --port 0 ARGS` and read its URL.
    pub fn start(scene: &Path, args: &[&str]) -> Server {
        Server::start_in(Path::new("."), scene, args)
    }

    /// [`Server::start`] in the working folder `dir` (SCENE relative to it).
    pub fn start_in(dir: &Path, scene: &Path, args: &[&str]) -> Server {
        Server::start_with(dir, scene, args, &[])
    }

    /// [`Server::start_in`] with the environment variables `env` set.
    pub fn start_with(dir: &Path, scene: &Path, args: &[&str], env: &[(&str, &Path)]) -> Server {
        let mut child = Command::new(bin())
            .current_dir(dir)
            .envs(env.iter().copied())
            .arg("preview")
            .arg(scene)
            .args(["--port", "0", "--threads", "1"])
            .args(args)
            .stdin(Stdio::null())
            .stdout(Stdio::piped())
            .stderr(Stdio::piped())
            .spawn()
            .expect("start raytracer preview");
        let mut stdout = BufReader::new(child.stdout.take().expect("stdout"));
        let mut line = String::new();
        stdout.read_line(&mut line).expect("read the first line");
        let url = line
            .split_whitespace()
            .find(|word| word.starts_with("http://"))
            .unwrap_or_else(|| panic!("no URL in {line:?}"));
        let address = url
            .trim_start_matches("http://")
            .trim_end_matches('/')
            .parse()
            .unwrap_or_else(|e| panic!("{url}: {e}"));
        Server {
            child,
            _stdout: stdout,
            address,
        }
    }

    /// `GET target` (sent as written, not normalised): status, headers
    /// (lowercase names) and body.
    pub fn get(&self, target: &str) -> Response {
        self.request(&format!("GET {target} HTTP/1.1"))
    }

    /// Send `request_line` and read the whole response.
    pub fn request(&self, request_line: &str) -> Response {
        http(self.address, request_line)
    }

    /// Open `/events`.
    pub fn events(&self) -> Events {
        let mut stream = TcpStream::connect(self.address).expect("connect");
        stream.set_read_timeout(Some(PATIENCE)).expect("timeout");
        write!(
            stream,
            "GET /events HTTP/1.1\r\nHost: {}\r\nAccept: text/event-stream\r\n\r\n",
            self.address
        )
        .expect("send request");
        let mut reader = BufReader::new(stream);
        let mut status = String::new();
        reader.read_line(&mut status).expect("status line");
        assert!(status.starts_with("HTTP/1.1 200"), "{status}");
        loop {
            let mut header = String::new();
            reader.read_line(&mut header).expect("header");
            if header.trim().is_empty() {
                break;
            }
            if let Some(value) = header.to_ascii_lowercase().strip_prefix("content-type:") {
                assert_eq!(value.trim(), "text/event-stream");
            }
        }
        Events { reader }
    }

    /// Stop the server with SIGINT (Ctrl-C) and return its exit code and
    /// everything it wrote to stderr.
    pub fn interrupt(mut self) -> (Option<i32>, String) {
        let sent = Command::new("kill")
            .args(["-INT", &self.child.id().to_string()])
            .status()
            .expect("run kill");
        assert!(sent.success());
        let code = self.child.wait().expect("wait").code();
        let mut stderr = String::new();
        if let Some(mut pipe) = self.child.stderr.take() {
            pipe.read_to_string(&mut stderr).expect("read stderr");
        }
        (code, stderr)
    }
}

impl Drop for Server {
    fn drop(&mut self) {
        let _ = self.child.kill();
        let _ = self.child.wait();
    }
}

/// Send `request_line` to `address` and read the whole response.
pub fn http(address: SocketAddr, request_line: &str) -> Response {
    http_to_host(address, request_line, &address.to_string())
}

/// [`http`] with the `Host` header `host`.
pub fn http_to_host(address: SocketAddr, request_line: &str, host: &str) -> Response {
    let mut stream = TcpStream::connect(address).expect("connect");
    stream.set_read_timeout(Some(PATIENCE)).expect("timeout");
    write!(
        stream,
        "{request_line}\r\nHost: {host}\r\nConnection: close\r\n\r\n"
    )
    .expect("send request");
    // Read the head, then the body: `Content-Length` bytes when given (a
    // server may keep the connection open regardless), else to the end.
    let mut reader = BufReader::new(stream);
    let mut raw = Vec::new();
    while !raw.ends_with(b"\r\n\r\n") {
        let read = reader.read_until(b'\n', &mut raw).expect("read the head");
        assert!(read > 0, "the response ended in its head");
    }
    let mut response = Response::parse(&raw);
    match response.header("content-length").map(str::parse::<usize>) {
        Some(Ok(length)) => {
            response.body = vec![0; length];
            reader
                .read_exact(&mut response.body)
                .expect("read the body");
        }
        _ => {
            reader
                .read_to_end(&mut response.body)
                .expect("read the body");
        }
    }
    response
}

/// An HTTP response.
pub struct Response {
    pub status: u16,
    pub headers: Vec<(String, String)>,
    pub body: Vec<u8>,
}

impl Response {
    fn parse(raw: &[u8]) -> Response {
        let end = raw
            .windows(4)
            .position(|w| w == b"\r\n\r\n")
            .unwrap_or_else(|| panic!("no header end in {:?}", String::from_utf8_lossy(raw)));
        let head = String::from_utf8_lossy(&raw[..end]);
        let mut lines = head.lines();
        let status = lines
            .next()
            .and_then(|line| line.split_whitespace().nth(1))
            .and_then(|code| code.parse().ok())
            .expect("a status code");
        let headers = lines
            .filter_map(|line| line.split_once(':'))
            .map(|(name, value)| (name.trim().to_ascii_lowercase(), value.trim().to_string()))
            .collect();
        Response {
            status,
            headers,
            body: raw[end + 4..].to_vec(),
        }
    }

    pub fn header(&self, name: &str) -> Option<&str> {
        self.headers
            .iter()
            .find(|(n, _)| n == name)
            .map(|(_, v)| v.as_str())
    }
}

/// The `/events` stream.
pub struct Events {
    reader: BufReader<TcpStream>,
}

impl Events {
    /// The next `update` event's data.
    pub fn next(&mut self) -> Value {
        let mut event = String::new();
        loop {
            let mut line = String::new();
            let read = self.reader.read_line(&mut line).expect("read an event");
            assert!(read > 0, "the event stream ended");
            let line = line.trim_end_matches(['\r', '\n']);
            if line.is_empty() {
                if !event.is_empty() {
                    return serde_json::from_str(&event).expect("an update is JSON");
                }
            } else if let Some(data) = line.strip_prefix("data: ") {
                event.push_str(data);
            } else {
                assert_eq!(line, "event: update", "an unexpected event line");
            }
        }
    }

    /// Read updates until one satisfies `wanted`; it is returned.
    pub fn until(&mut self, what: &str, wanted: impl Fn(&Value) -> bool) -> Value {
        let start = Instant::now();
        loop {
            let update = self.next();
            if wanted(&update) {
                return update;
            }
            assert!(
                start.elapsed() < PATIENCE,
                "no update {what} within {PATIENCE:?}; last: {update}"
            );
        }
    }

    /// Read updates until the scene is rendered in full (`phase` `ok`).
    pub fn until_rendered(&mut self) -> Value {
        self.until("rendered", |u| u["phase"] == "ok")
    }
}

/// The stdout of `raytracer check --format json SCENE`, which `/diagnostics`
/// must equal byte for byte.
fn check_json(scene: &Path) -> Vec<u8> {
    let scene = scene.to_str().expect("a UTF-8 path");
    run(&["check", "--format", "json", scene]).stdout
}

/// The side of a PNG and its pixels.
fn decode_png(bytes: &[u8]) -> (u32, Vec<u8>) {
    let image = image::load_from_memory_with_format(bytes, image::ImageFormat::Png)
        .expect("a PNG")
        .to_rgb8();
    assert_eq!(image.width(), image.height());
    (image.width(), image.into_raw())
}

/// Replace the file at `path` with `text` as editors save: a new file
/// renamed over the old one, so the server never reads half a save.
pub fn save(path: &Path, text: &str) {
    let temporary = path.with_extension("saving");
    std::fs::write(&temporary, text).expect("write the new version");
    std::fs::rename(&temporary, path).expect("rename it over the scene");
}

/// A scene in a fresh folder.
fn scene_in_temp(text: &str) -> (tempfile::TempDir, PathBuf) {
    let dir = tempfile::tempdir().expect("temp dir");
    let scene = PathBuf::from(write(dir.path(), "scene.txt", text));
    (dir, scene)
}

#[test]
fn the_page_image_and_diagnostics_follow_edits_errors_and_deletion() {
    let (_dir, scene) = scene_in_temp(&scene_text("1 0 0"));
    let server = Server::start(&scene, &[]);
    let mut events = server.events();
    let first = events.until_rendered();
    assert_eq!(first["stale"], false);
    assert_eq!(first["stats"]["resolution"], 48);

    let page = server.get("/");
    assert_eq!(page.status, 200);
    assert_eq!(
        page.header("content-type"),
        Some("text/html; charset=utf-8")
    );
    let html = String::from_utf8(page.body).expect("UTF-8 page");
    assert!(html.contains("<img id=\"image\"") && html.contains("new EventSource(\"/events\")"));
    assert!(
        !html.contains("http://") && !html.contains("https://"),
        "no CDN"
    );

    let image = server.get("/image.png");
    assert_eq!(image.status, 200);
    assert_eq!(image.header("content-type"), Some("image/png"));
    let (side, red) = decode_png(&image.body);
    assert_eq!(side, 48);
    let centre = 3 * (24 * 48 + 24);
    assert!(red[centre] > 100 && red[centre + 1] == 0, "a red sphere");
    let diagnostics = server.get("/diagnostics");
    assert_eq!(diagnostics.header("content-type"), Some("application/json"));
    assert_eq!(diagnostics.body, check_json(&scene));
    assert_eq!(String::from_utf8_lossy(&diagnostics.body), "[]\n");

    // An edit: a new image, rendered from the new text.
    save(&scene, &scene_text("0 0 1"));
    let edited = events.until_rendered();
    assert!(edited["image"].as_u64() > first["image"].as_u64());
    let blue = server
        .get(&format!("/image.png?v={}", edited["image"]))
        .body;
    let (_, pixels) = decode_png(&blue);
    assert!(
        pixels[centre + 2] > 100 && pixels[centre] == 0,
        "a blue sphere"
    );

    // A broken edit: the diagnostics of `check`, the last good image, stale.
    save(
        &scene,
        &scene_text("0 0 1").replace("dimension", "dimenson"),
    );
    let broken = events.until("with errors", |u| u["phase"] == "errors");
    assert_eq!(broken["stale"], true);
    assert_eq!(broken["image"], edited["image"]);
    assert_eq!(broken["diagnostics"][0]["code"], "scene::unknown_attribute");
    assert_eq!(broken["diagnostics"][0]["labels"][0]["line"], 3);
    let diagnostics = server.get("/diagnostics").body;
    assert_eq!(diagnostics, check_json(&scene));
    let reported: Value = serde_json::from_slice(&diagnostics).expect("JSON");
    assert_eq!(reported, broken["diagnostics"]);
    assert_eq!(server.get("/image.png").body, blue, "the last good image");

    // Deleted: said so, still serving the last good image.
    std::fs::remove_file(&scene).expect("delete");
    let deleted = events.until("for the deletion", |u| u["phase"] == "deleted");
    assert_eq!(deleted["stale"], true);
    assert_eq!(deleted["diagnostics"][0]["code"], "io::read_scene");
    assert_eq!(server.get("/image.png").body, blue);
    assert_eq!(server.get("/").status, 200);

    // Back: rendered again.
    save(&scene, &scene_text("0 1 0"));
    let back = events.until_rendered();
    assert_eq!(back["stale"], false);
    let (_, green) = decode_png(&server.get("/image.png").body);
    assert!(
        green[centre + 1] > 100 && green[centre] == 0,
        "a green sphere"
    );
}

#[test]
fn a_large_scene_is_capped_and_shows_a_coarse_pass_first() {
    let large = |color| scene_text(color).replace("camera 48", "camera 2000");
    let (_dir, scene) = scene_in_temp(&large("1 1 1"));
    let server = Server::start(&scene, &["--max-size", "300"]);
    let mut events = server.events();
    // The first render may finish before the stream is connected; a save
    // made while it is connected shows both of its passes, in order.
    events.until_rendered();
    save(&scene, &large("1 0 0"));
    let coarse = events.until("with a coarse image", |u| u["coarse"] == true);
    assert_eq!(coarse["phase"], "rendering");
    assert_eq!(coarse["stats"]["resolution"], 75);
    let full = events.until_rendered();
    assert_eq!(full["coarse"], false);
    assert_eq!(full["stats"]["resolution"], 300);
    assert_eq!(full["stats"]["scene_resolution"], 2000);
    assert_eq!(decode_png(&server.get("/image.png").body).0, 300);
}

#[test]
fn nothing_but_the_four_paths_is_served() {
    let (dir, scene) = scene_in_temp(&scene_text("1 0 0"));
    write(dir.path(), "secret.txt", "do not serve me");
    let server = Server::start(&scene, &[]);
    server.events().until_rendered();
    for target in [
        "/scene.txt",
        "/secret.txt",
        "/../secret.txt",
        "/../../../../etc/passwd",
        "/%2e%2e/secret.txt",
        "/%2E%2E%2Fsecret.txt",
        "/..%2fsecret.txt",
        "/%2fetc%2fpasswd",
        "//etc/passwd",
        "/image.png/../secret.txt",
        "/image.png/",
        "/index.html",
        "/diagnostics/../scene.txt",
        "/events/..",
    ] {
        let response = server.get(target);
        assert_eq!(response.status, 404, "{target}");
        let body = String::from_utf8_lossy(&response.body);
        assert!(
            !body.contains("do not serve") && !body.contains("sphere") && !body.contains("root:"),
            "{target}: {body}"
        );
    }
    assert_eq!(server.request("POST / HTTP/1.1").status, 405);
    // A page elsewhere whose name was pointed at 127.0.0.1 (DNS rebinding)
    // is refused; the names of loopback are not.
    let port = server.address.port();
    for (host, status) in [
        (format!("attacker.example:{port}"), 403),
        (format!("127.0.0.1.attacker.example:{port}"), 403),
        (format!("localhost:{port}"), 200),
        (format!("LOCALHOST:{port}"), 200),
    ] {
        let response = http_to_host(server.address, "GET /diagnostics HTTP/1.1", &host);
        assert_eq!(response.status, status, "{host}");
    }
    // A query string names no file: it is ignored.
    assert_eq!(server.get("/image.png?../secret.txt").status, 200);
}

#[test]
fn it_listens_on_loopback_only_and_ctrl_c_exits_130_without_an_error() {
    let (_dir, scene) = scene_in_temp(&scene_text("1 0 0"));
    let server = Server::start(&scene, &[]);
    assert_eq!(server.address.ip(), Ipv4Addr::LOCALHOST);
    // Another loopback address reaches a socket bound to all interfaces,
    // not one bound to 127.0.0.1.
    let other = SocketAddr::from((Ipv4Addr::new(127, 0, 0, 2), server.address.port()));
    assert!(
        TcpStream::connect_timeout(&other, Duration::from_secs(5)).is_err(),
        "reachable on {other}"
    );
    #[cfg(target_os = "linux")]
    {
        // The kernel's table of TCP sockets: the listening one (state 0A)
        // on this port has local address 127.0.0.1 (0100007F).
        let port = format!(":{:04X}", server.address.port());
        let table = std::fs::read_to_string("/proc/net/tcp").expect("read /proc/net/tcp")
            + &std::fs::read_to_string("/proc/net/tcp6").unwrap_or_default();
        let listening: Vec<&str> = table
            .lines()
            .filter_map(|line| {
                let fields: Vec<&str> = line.split_whitespace().collect();
                (fields.get(3) == Some(&"0A") && fields[1].ends_with(&port)).then_some(fields[1])
            })
            .collect();
        assert_eq!(listening, [format!("0100007F{port}")]);
    }
    assert_eq!(server.get("/").status, 200);
    // Ctrl-C is how a preview stops: no `interrupted` error on stderr.
    let (code, stderr) = server.interrupt();
    assert_eq!(code, Some(130), "{stderr}");
    assert_eq!(stderr, "");
}

#[cfg(unix)]
#[test]
fn a_browser_that_fails_is_a_warning_with_its_command_and_status() {
    use std::os::unix::fs::PermissionsExt;
    let (dir, scene) = scene_in_temp(&scene_text("1 0 0"));
    let ran = dir.path().join("browser-ran");
    let browser = dir.path().join("fake-browser");
    std::fs::write(
        &browser,
        format!("#!/bin/sh\ntouch '{}'\nexit 1\n", ran.display()),
    )
    .unwrap();
    std::fs::set_permissions(&browser, std::fs::Permissions::from_mode(0o755)).unwrap();
    let server = Server::start_with(
        Path::new("."),
        &scene,
        &["--open"],
        &[("BROWSER", &browser)],
    );
    let url = format!("http://{}/", server.address);
    let deadline = std::time::Instant::now() + PATIENCE;
    while !ran.exists() && std::time::Instant::now() < deadline {
        std::thread::sleep(Duration::from_millis(20));
    }
    assert!(ran.exists(), "the browser never ran");
    // The warning follows the browser's exit, on the thread that waits for it.
    std::thread::sleep(Duration::from_millis(500));
    let (_, stderr) = server.interrupt();
    let command = format!("`{} {url}`", browser.display());
    assert!(
        stderr.contains(&format!(
            "warning: the browser command {command} failed (exit status: 1); open {url} yourself"
        )),
        "{stderr}"
    );
}

#[test]
fn stdin_an_unreadable_scene_and_a_taken_port_are_refused() {
    let stdin = run(&["preview", "-"]);
    assert_eq!(stdin.status.code(), Some(2));
    let stderr = String::from_utf8_lossy(&stdin.stderr);
    assert!(stderr.contains("usage::preview_stdin"), "{stderr}");

    let dir = tempfile::tempdir().expect("temp dir");
    let missing = dir.path().join("missing.txt");
    let missing = run(&["preview", missing.to_str().expect("UTF-8")]);
    assert_eq!(missing.status.code(), Some(2));
    let stderr = String::from_utf8_lossy(&missing.stderr);
    assert!(stderr.contains("io::read_scene"), "{stderr}");

    let (_dir, scene) = scene_in_temp(&scene_text("1 0 0"));
    let server = Server::start(&scene, &[]);
    let port = server.address.port().to_string();
    let taken = run(&["preview", scene.to_str().expect("UTF-8"), "--port", &port]);
    assert_eq!(taken.status.code(), Some(2));
    let stderr = String::from_utf8_lossy(&taken.stderr);
    assert!(
        stderr.contains("io::listen") && stderr.contains("--port 0"),
        "{stderr}"
    );
}
