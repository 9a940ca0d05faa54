//! `raytracer preview`: check the arguments, bind the page's address, say
//! where it is (and open it with `--open`), then serve until Ctrl-C, which
//! the binary's handler turns into exit 130 without an error: it is how a
//! preview stops. The server is
//! [`crate::preview`].

use std::io::Write;
use std::net::SocketAddr;
use std::path::Path;

use miette::Diagnostic;

use super::render::thread_pool;
use super::{Outcome, WriteStdoutError};
use crate::browser;
use crate::cli::PreviewArgs;
use crate::preview::{Preview, Settings};
use raytracer_render::render::{adaptive::DEFAULT_THRESHOLD, Options};
use raytracer_scene::diagnostic::BoxedDiagnostic;
use raytracer_scene::frontend::read_scene;

/// The scene cannot be previewed from stdin.
#[derive(Debug, thiserror::Error, Diagnostic)]
#[error("expected a scene file to watch, found `-` (stdin)")]
#[diagnostic(
    code(usage::preview_stdin),
    help("save the scene to a file and pass its path: the preview re-reads it on every save")
)]
pub struct PreviewStdin;

/// Open the page in the browser; a command that cannot start, or that
/// ends unsuccessfully (watched on a thread of its own while the page is
/// served), is a warning that names it and its exit status.
fn open_browser(url: &str) {
    match browser::launch(url) {
        Err(error) => sayln!("warning: {error}; open {url} yourself"),
        Ok(launch) => {
            let url = url.to_string();
            std::thread::spawn(move || {
                if let Err(failed) = launch.wait() {
                    sayln!("warning: {failed}; open {url} yourself");
                }
            });
        }
    }
}

/// Run `raytracer preview`.
pub fn run(args: PreviewArgs) -> Result<Outcome, BoxedDiagnostic> {
    if args.scene == Path::new("-") {
        return Err(Box::new(PreviewStdin));
    }
    super::square_spp(args.sampling.spp, "--spp")?;
    // A scene that cannot be read at all is refused now, before serving,
    // as `render` refuses it; later reads that fail show on the page.
    read_scene(&args.scene)?;
    let settings = Settings {
        options: Options {
            spp: args.sampling.spp,
            antialias: args.sampling.aa.with_threshold(DEFAULT_THRESHOLD),
            ..Options::default()
        },
        precision: args.sampling.precision,
        max_size: args.max_size,
        pool: thread_pool(args.sampling.threads)?,
    };
    let preview = Preview::bind(
        args.scene.clone(),
        settings,
        SocketAddr::new(args.bind, args.port),
        args.docs,
    )?;
    let url = preview.url();
    let mut stdout = std::io::stdout();
    writeln!(
        stdout,
        "previewing {} at {url} (Ctrl-C stops)",
        args.scene.display()
    )
    .and_then(|()| stdout.flush())
    .map_err(WriteStdoutError::from)?;
    if args.open {
        open_browser(&url);
    }
    super::interrupt_stops();
    preview.run();
    Ok(Outcome::Success)
}
