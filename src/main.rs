//! The `raytracer` binary: install the Ctrl-C handler, parse arguments, run
//! the command, map the outcome to an exit code. Nothing else lives here
//! (the ripgrep layout).

use std::process::ExitCode;

use raytracer::cli;
use raytracer::commands;

fn main() -> ExitCode {
    // Without the handler a signal still stops the process; only the
    // clean-up of a temporary output file being written would be lost.
    let _ = ctrlc::set_handler(|| commands::interrupt());
    match cli::parse_args(std::env::args_os()) {
        Ok(cli) => commands::run(cli),
        Err(error) => {
            // clap prints help and version to stdout (exit 0) and usage
            // errors to stderr (exit 2).
            let _ = error.print();
            ExitCode::from(error.exit_code().clamp(0, 255) as u8)
        }
    }
}
