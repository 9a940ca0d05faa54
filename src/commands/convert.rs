//! `raytracer convert`: not yet implemented.

use super::{Failure, Outcome};
use crate::cli::ConvertArgs;

/// Run `raytracer convert`.
pub fn run(_args: ConvertArgs) -> Result<Outcome, Failure> {
    Err(miette::miette!("`convert` is not implemented yet").into())
}
