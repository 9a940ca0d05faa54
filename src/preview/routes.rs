//! The preview's four endpoints and nothing else: the request target's
//! path, up to any `?`, must be exactly one of them. No path is decoded,
//! joined or looked up on disk, so no spelling of `..` (plain, `%2e%2e`,
//! `%2f`) can reach a file: every other path is a 404.

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

/// Answer `request` from `state`. Errors writing a response mean the
/// client went away; there is no one left to tell.
pub fn answer(request: Request, state: &State) {
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
