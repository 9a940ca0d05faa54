//! The `raytracer` binary: install the Ctrl-C handler, parse arguments, run
//! the command, map the outcome to an exit code. Nothing else lives here
//! (the ripgrep layout).

use std::process::ExitCode;

use raytracer_app::cli;
use raytracer_app::commands;
use raytracer_scene::escape;

fn main() -> ExitCode {
    // Without the handler a signal still stops the process; only the
    // clean-up of a temporary output file being written would be lost.
    let _ = ctrlc::set_handler(|| commands::interrupt());
    let args: Vec<_> = std::env::args_os().collect();
    let hidden = args
        .iter()
        .any(|a| a.to_string_lossy().chars().any(escape::is_hidden));
    // The version and the commit it was built from (build.rs).
    match cli::parse_args(args, env!("RAYTRACER_VERSION")) {
        Ok(cli) => commands::run(cli),
        Err(error) => {
            // clap prints help and version to stdout (exit 0) and usage
            // errors to stderr (exit 2). When an argument holds characters
            // a terminal would obey, the error may quote it: it is shown
            // uncoloured (which drops escape sequences) and escaped.
            if error.use_stderr() && hidden {
                eprint!("{}", escape::escape(&error.render().to_string()));
            } else {
                let _ = error.print();
            }
            ExitCode::from(error.exit_code().clamp(0, 255) as u8)
        }
    }
}
