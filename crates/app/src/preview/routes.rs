//! The preview's four endpoints and nothing else: the request target's
//! path, up to any `?`, must be exactly one of them. No path is decoded,
//! joined or looked up on disk, so no spelling of `..` (plain, `%2e%2e`,
//! `%2f`) can reach a file: every other path is a 404.

use std::net::SocketAddr;
use std::sync::Arc;

use tiny_http::{Header, Method, Request, Response, StatusCode};

use super::page::PAGE;
use super::state::State;

/// What a request asks for.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Route {
    /// `/`: the page.
    Page,
    /// `/image.png`: the latest good image (a query string such as
    /// `?v=3` is ignored; the page uses it to defeat caches).
    Image,
    /// `/diagnostics`: the JSON of `check --format json`.
    Diagnostics,
    /// `/events`: the Server-Sent Events stream of updates.
    Events,
}

impl Route {
    /// The route of a request target, `None` for anything else.
    pub fn of(target: &str) -> Option<Route> {
        let path = target.split_once('?').map_or(target, |(path, _)| path);
        match path {
            "/" => Some(Route::Page),
            "/image.png" => Some(Route::Image),
            "/diagnostics" => Some(Route::Diagnostics),
            "/events" => Some(Route::Events),
            _ => None,
        }
    }
}

/// The `Host` headers a request may carry: on a loopback address only
/// the names of loopback, so that a web page whose name an attacker points
/// at 127.0.0.1 (DNS rebinding) cannot read the preview; any name when
/// `--bind` chose another address.
pub enum Hosts {
    Loopback(Vec<String>),
    Any,
}

impl Hosts {
    /// The hosts allowed for a server bound to `address`.
    pub fn of(address: SocketAddr) -> Hosts {
        if !address.ip().is_loopback() {
            return Hosts::Any;
        }
        let port = address.port();
        Hosts::Loopback(vec![
            address.to_string(),
            format!("localhost:{port}"),
            format!("127.0.0.1:{port}"),
            format!("[::1]:{port}"),
        ])
    }

    fn allow(&self, request: &Request) -> bool {
        match self {
            Hosts::Any => true,
            Hosts::Loopback(names) => request
                .headers()
                .iter()
                .find(|h| h.field.equiv("Host"))
                .is_some_and(|h| {
                    names
                        .iter()
                        .any(|n| h.value.as_str().eq_ignore_ascii_case(n))
                }),
        }
    }
}

/// Answer `request` from `state`. Errors writing a response mean the
/// client went away; there is no one left to tell.
pub fn answer(request: Request, state: &State, hosts: &Hosts) {
    if !hosts.allow(&request) {
        let _ = request.respond(text(403, "expected a loopback `Host`, such as 127.0.0.1\n"));
        return;
    }
    if *request.method() != Method::Get {
        let _ = request.respond(text(405, "only GET is served\n"));
        return;
    }
    let _ = match Route::of(request.url()) {
        None => request.respond(text(404, "not found\n")),
        Some(Route::Page) => request.respond(bytes(PAGE.as_bytes(), "text/html; charset=utf-8")),
        Some(Route::Image) => match state.png() {
            Some(png) => request.respond(bytes(&png, "image/png")),
            None => request.respond(text(404, "no image yet: the scene has not rendered\n")),
        },
        Some(Route::Diagnostics) => {
            let json: Arc<Vec<u8>> = state.diagnostics();
            request.respond(bytes(&json, "application/json"))
        }
        Some(Route::Events) => {
            state.subscribe(request.into_writer());
            Ok(())
        }
    };
}

/// A 200 response of `body`, never cached (every answer can change on the
/// next save).
fn bytes(body: &[u8], content_type: &str) -> Response<std::io::Cursor<Vec<u8>>> {
    Response::from_data(body.to_vec())
        .with_header(header("Content-Type", content_type))
        .with_header(header("Cache-Control", "no-store"))
}

/// A plain-text response with `status`.
fn text(status: u16, body: &str) -> Response<std::io::Cursor<Vec<u8>>> {
    Response::from_data(body.as_bytes().to_vec())
        .with_status_code(StatusCode(status))
        .with_header(header("Content-Type", "text/plain; charset=utf-8"))
}

fn header(name: &str, value: &str) -> Header {
    // Both are ASCII constants of this module.
    Header::from_bytes(name.as_bytes(), value.as_bytes()).expect("an ASCII header")
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn only_the_four_paths_route() {
        assert_eq!(Route::of("/"), Some(Route::Page));
        assert_eq!(Route::of("/image.png?v=7"), Some(Route::Image));
        assert_eq!(Route::of("/diagnostics"), Some(Route::Diagnostics));
        assert_eq!(Route::of("/events"), Some(Route::Events));
        for other in [
            "",
            "/index.html",
            "/image.png/",
            "//image.png",
            "/../image.png",
            "/%2e%2e/",
            "/..%2fCargo.toml",
            "/%2fetc%2fpasswd",
            "/image%2epng",
            "http://127.0.0.1/",
            "*",
        ] {
            assert_eq!(Route::of(other), None, "{other}");
        }
    }
}
