//! `raytracer preview`'s server: a page beside the editor that shows the
//! scene's image and diagnostics and redraws them on every save.
//!
//! Three kinds of thread share one [`State`]: the watcher's ([`watch`])
//! reports changes to the scene and its textures; one rebuilding thread
//! waits for a pause in them and runs the front end and the renderer
//! ([`rebuild`]); the server ([`tiny_http`]) answers each request on a
//! thread of its own ([`routes`]) and pushes every new state to the open
//! event streams. Nothing here knows about the command line.

mod page;
mod rebuild;
mod routes;
mod state;
mod watch;

use std::net::SocketAddr;
use std::path::PathBuf;
use std::sync::mpsc;
use std::sync::Arc;
use std::time::Duration;

use miette::Diagnostic;

pub use rebuild::Settings;

use raytracer_scene::diagnostic::{io_reason, lowercase_first, FileError};
use state::State;
use watch::Watch;

/// How long changes must pause before the scene is rebuilt: an editor's
/// save is often several events (write, rename, attributes).
const QUIET: Duration = Duration::from_millis(30);

/// The preview could not start.
#[derive(Debug, thiserror::Error, Diagnostic)]
pub enum PreviewError {
    /// The address could not be bound.
    #[error("cannot listen on {address}: {reason}")]
    #[diagnostic(
        code(io::listen),
        help("another program may be using the port: `--port 0` picks a free one")
    )]
    Listen { address: SocketAddr, reason: String },

    /// The scene's folder could not be watched.
    #[error(transparent)]
    #[diagnostic(code(io::watch))]
    Watch(FileError),
}

/// A preview bound to its address, ready to [`Preview::run`].
pub struct Preview {
    server: tiny_http::Server,
    address: SocketAddr,
    scene: PathBuf,
    settings: Settings,
    watch: Watch,
    changed: mpsc::Receiver<()>,
    state: Arc<State>,
}

impl Preview {
    /// Listen on `address` (port 0 picks a free port) and watch `scene`;
    /// the page links diagnostic codes to sections of `docs`, when given.
    pub fn bind(
        scene: PathBuf,
        settings: Settings,
        address: SocketAddr,
        docs: Option<String>,
    ) -> Result<Preview, PreviewError> {
        let server = tiny_http::Server::http(address).map_err(|e| PreviewError::Listen {
            address,
            reason: match e.downcast_ref::<std::io::Error>() {
                Some(io) => io_reason(io),
                None => e.to_string(),
            },
        })?;
        let address = server.server_addr().to_ip().unwrap_or(address);
        let (sender, changed) = mpsc::channel();
        let watch = Watch::new(&scene, sender).map_err(|e| {
            PreviewError::Watch(FileError::with_reason(
                "watch",
                &scene,
                lowercase_first(&e.to_string()),
            ))
        })?;
        let state = Arc::new(State::new(scene.display().to_string(), docs));
        Ok(Preview {
            server,
            address,
            scene,
            settings,
            watch,
            changed,
            state,
        })
    }

    /// The page's URL: `http://ADDRESS:PORT/`.
    pub fn url(&self) -> String {
        format!("http://{}/", self.address)
    }

    /// Render the scene, then serve and rebuild on every change until the
    /// process is stopped.
    pub fn run(self) {
        let Preview {
            server,
            address,
            scene,
            settings,
            mut watch,
            changed,
            state,
            ..
        } = self;
        let rebuilt = state.clone();
        std::thread::spawn(move || loop {
            let textures = rebuild::rebuild(&scene, &settings, &rebuilt);
            watch.add_textures(&textures);
            if changed.recv().is_err() {
                return;
            }
            while changed.recv_timeout(QUIET).is_ok() {}
        });
        let hosts = Arc::new(routes::Hosts::of(address));
        for request in server.incoming_requests() {
            let (state, hosts) = (state.clone(), hosts.clone());
            std::thread::spawn(move || routes::answer(request, &state, &hosts));
        }
    }
}
