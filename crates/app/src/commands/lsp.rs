//! `raytracer lsp`: run the language server of [`crate::lsp`] on stdio.
//! Exit 0 after the protocol's `shutdown` and `exit`, 1 when the client
//! leaves without `shutdown`, 2 when the conversation could not start.

use std::time::Duration;

use super::Outcome;
use crate::cli::LspArgs;
use crate::lsp::{serve_stdio, Ending, Options};
use raytracer_scene::diagnostic::BoxedDiagnostic;

/// Run `raytracer lsp`.
pub fn run(args: LspArgs) -> Result<Outcome, BoxedDiagnostic> {
    let options = Options {
        debounce: Duration::from_millis(args.debounce_ms),
    };
    match serve_stdio(&options) {
        Ok(Ending::Shutdown) => Ok(Outcome::Success),
        // Exit 1, as the protocol asks of a server told to exit early.
        Ok(Ending::Abandoned) => Ok(Outcome::SceneErrors),
        Err(error) => Err(Box::new(error)),
    }
}
