//! `raytracer check`: not yet implemented.

use super::{Failure, Outcome};
use crate::cli::CheckArgs;

/// Run `raytracer check`.
pub fn run(_args: CheckArgs) -> Result<Outcome, Failure> {
    Err(miette::miette!("`check` is not implemented yet").into())
}
