//! `raytracer render`: not yet implemented.

use super::{Failure, Outcome};
use crate::cli::RenderArgs;

/// Run `raytracer render`.
pub fn run(_args: RenderArgs) -> Result<Outcome, Failure> {
    Err(miette::miette!("`render` is not implemented yet").into())
}
