//! The command line: every clap type in one place (the ripgrep layout).
//!
//! `raytracer SCENE OUT` is the course's form of `raytracer render SCENE OUT`;
//! [`parse_args`] rewrites it before clap sees the arguments.

use std::ffi::OsString;
use std::path::PathBuf;

use clap::builder::{PossibleValuesParser, TypedValueParser};
use clap::{Args, Parser, Subcommand, ValueEnum};

use crate::render::adaptive::DEFAULT_THRESHOLD;
#[cfg(doc)]
use crate::render::world::BRUTE_FORCE_MAX;
use crate::render::Accel;
use crate::tile::Band;

/// Render and check scenes of the raytracer scene language.
#[derive(Debug, Parser)]
#[command(name = "raytracer", version, about, long_about = None)]
#[command(
    after_help = "`raytracer SCENE OUT` is short for `raytracer render SCENE OUT`.\n\
Exit codes: 0 success, 1 the scene has errors, 2 usage, I/O or internal error,\n\
130 interrupted (Ctrl-C; no output file is left half-written)."
)]
pub struct Cli {
    #[command(subcommand)]
    pub command: Command,
}

#[derive(Debug, Subcommand)]
pub enum Command {
    /// Render a scene to an image (.ppm or .png, by OUT's extension).
    Render(RenderArgs),
    /// Check scenes and report every problem (a linter).
    Check(CheckArgs),
    /// Convert a scene to JSON, canonical scene text, or POV-Ray.
    Convert(ConvertArgs),
    /// Lay out scene text files canonically, keeping every comment.
    Fmt(FmtArgs),
    /// Serve the Language Server Protocol on stdin and stdout (for editors).
    Lsp(LspArgs),
    /// Put the tiles of `render --tile` together into one image.
    Stitch(StitchArgs),
    /// Measure what accuracy costs for a scene: error and time of each
    /// setting against a converged reference, as a table with findings.
    Accuracy(AccuracyArgs),
}

/// `--accel`: the renderer's [`Accel`] as the command line spells it.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, ValueEnum)]
pub enum AccelArg {
    /// A hierarchy when the scene has more than [`BRUTE_FORCE_MAX`]
    /// primitives, else testing them all.
    #[default]
    Auto,
    /// Always a bounding volume hierarchy.
    Bvh,
    /// Always test every primitive.
    Brute,
}

impl From<AccelArg> for Accel {
    fn from(arg: AccelArg) -> Accel {
        match arg {
            AccelArg::Auto => Accel::Auto,
            AccelArg::Bvh => Accel::Bvh,
            AccelArg::Brute => Accel::Brute,
        }
    }
}

/// Floating-point precision of the tracer: the renderer's own type, read
/// from its name.
pub use crate::render::Precision;

/// Where the samples of `--spp` go.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, ValueEnum)]
pub enum Antialias {
    /// Every pixel takes all of them.
    #[default]
    Uniform,
    /// Corner samples first, four more where they disagree, all of them
    /// where those four do.
    Adaptive,
}

#[derive(Debug, Args)]
pub struct RenderArgs {
    /// Scene file (`.json` is read as JSON; `-` reads stdin).
    pub scene: PathBuf,
    /// Output image; the extension picks the format.
    pub out: PathBuf,
    /// Floating-point precision of every ray computation.
    #[arg(long, default_value = "f64",
          value_parser = PossibleValuesParser::new(["f32", "f64"]).try_map(|s| s.parse::<Precision>()))]
    pub precision: Precision,
    /// Samples per pixel, stratified on a √N×√N grid (1 = pixel centre).
    #[arg(long, default_value_t = 1, value_parser = clap::value_parser!(u32).range(1..=1024))]
    pub spp: u32,
    /// Which pixels take all `--spp` samples: every one, or only those
    /// whose corners, then four samples, differ by `--aa-threshold`.
    #[arg(long, value_enum, default_value_t = Antialias::Uniform)]
    pub aa: Antialias,
    /// The contrast within a pixel, in steps of 1/255 (fractions allowed),
    /// that refines it under `--aa adaptive` (0 refines every pixel).
    #[arg(long, default_value_t = DEFAULT_THRESHOLD, value_name = "STEPS", value_parser = contrast_steps)]
    pub aa_threshold: f64,
    /// Maximum number of reflections per primary ray.
    #[arg(long, default_value_t = 8, value_parser = clap::value_parser!(u32).range(0..=64))]
    pub max_depth: u32,
    /// Worker threads (default: all cores).
    #[arg(long, value_parser = clap::value_parser!(u32).range(1..=1024))]
    pub threads: Option<u32>,
    /// Trace rays even where their contribution cannot change an 8-bit
    /// value (for measuring what that skip saves).
    #[arg(long)]
    pub no_skip: bool,
    /// How rays find primitives: a hierarchy above a few primitives
    /// (`auto`), always (`bvh`) or never (`brute`). The image is the same.
    #[arg(long, value_enum, default_value_t = AccelArg::Auto)]
    pub accel: AccelArg,
    /// Print ray counts and stage timings to stderr.
    #[arg(long)]
    pub stats: bool,
    /// Write ray counts and stage timings as JSON to PATH.
    #[arg(long, value_name = "PATH")]
    pub stats_json: Option<PathBuf>,
    /// No progress bar and no warnings on stderr.
    #[arg(long, short)]
    pub quiet: bool,
    /// Render only band K of N bands of rows, to a PNG that records where
    /// it belongs (see `stitch`; docs/distributed.md).
    #[arg(long, value_name = "K/N", value_parser = clap::builder::ValueParser::new(str::parse::<Band>))]
    pub tile: Option<Band>,
}

#[derive(Debug, Args)]
pub struct StitchArgs {
    /// Output image; the extension picks the format (.ppm or .png).
    pub out: PathBuf,
    /// The tiles (PNG files of `render --tile K/N`), in any order.
    #[arg(required = true)]
    pub parts: Vec<PathBuf>,
    /// Write the tiles' statistics, summed, as JSON to PATH.
    #[arg(long, value_name = "PATH", requires = "part_stats")]
    pub stats_json: Option<PathBuf>,
    /// The tiles' `render --stats-json` files, in any order, one per part.
    #[arg(long, value_name = "PATH", num_args = 1.., requires = "stats_json")]
    pub part_stats: Vec<PathBuf>,
}

/// How `check` prints diagnostics.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, ValueEnum)]
pub enum Format {
    /// Annotated source snippets.
    #[default]
    Human,
    /// One line each: `file:line:col: severity[code]: message`.
    Short,
    /// One JSON array of every diagnostic of every file.
    Json,
    /// A SARIF 2.1.0 log, for code-scanning services.
    Sarif,
    /// GitHub Actions workflow commands (`::error file=…::message`).
    Github,
}

#[derive(Debug, Args)]
pub struct CheckArgs {
    /// Scene files, or folders to search for scenes (`-` reads stdin).
    #[arg(required = true)]
    pub scenes: Vec<PathBuf>,
    /// Output format.
    #[arg(long, value_enum, default_value_t = Format::Human)]
    pub format: Format,
    /// Exit 1 when there are warnings.
    #[arg(long)]
    pub deny_warnings: bool,
    /// Apply the safe fixes the diagnostics carry (such as projecting
    /// headup onto the plane) in place.
    #[arg(long)]
    pub fix: bool,
    /// With `--fix`, also apply the unsafe fixes (such as a "did you
    /// mean" replacement).
    #[arg(long, requires = "fix")]
    pub unsafe_fixes: bool,
}

/// What `convert` writes.
#[derive(Clone, Copy, Debug, PartialEq, Eq, ValueEnum)]
pub enum Target {
    /// The versioned JSON scene model.
    Json,
    /// Canonical scene text.
    Scene,
    /// A POV-Ray 3.7 scene.
    Pov,
}

#[derive(Debug, Args)]
#[command(group(clap::ArgGroup::new("target").required(true).args(["to", "json"])))]
pub struct ConvertArgs {
    /// Scene file (`.json` is read as JSON; `-` reads stdin).
    pub scene: PathBuf,
    /// Output language.
    #[arg(long, value_enum)]
    pub to: Option<Target>,
    /// Short for `--to json`.
    #[arg(long)]
    pub json: bool,
    /// Write here instead of stdout.
    #[arg(short, long, value_name = "PATH")]
    pub output: Option<PathBuf>,
}

impl ConvertArgs {
    /// The output language, from `--to` or `--json` (clap requires exactly
    /// one of them).
    pub fn target(&self) -> Target {
        self.to.unwrap_or(Target::Json)
    }
}

#[derive(Debug, Args)]
pub struct AccuracyArgs {
    /// Scene file (`.json` is read as JSON; `-` reads stdin).
    pub scene: PathBuf,
    /// Render at N×N [default: the scene's own side, or its smallest odd
    /// multiple of at least 128, which keeps every pixel centre].
    #[arg(long, value_parser = clap::value_parser!(u32).range(1..=4096))]
    pub size: Option<u32>,
    /// Timed repetitions of every setting (interleaved).
    #[arg(long, default_value_t = 5, value_parser = clap::value_parser!(u32).range(1..=100))]
    pub reps: u32,
    /// Samples per pixel of each of the reference's two halves (a square).
    #[arg(long, default_value_t = 256, value_parser = clap::value_parser!(u32).range(1..=4096))]
    pub reference_spp: u32,
    /// Also write the plot data (`STEM.sampling.csv`, `STEM.pareto.csv`)
    /// and the f32 − f64 difference map (`STEM.f32_f64.png`) to DIR.
    #[arg(long, value_name = "DIR")]
    pub assets: Option<PathBuf>,
    /// The contrast that refines a pixel in the adaptive rows, in steps
    /// of 1/255 (fractions allowed).
    #[arg(long, default_value_t = DEFAULT_THRESHOLD, value_name = "STEPS", value_parser = contrast_steps)]
    pub aa_threshold: f64,
    /// Worker threads for the reference (timed renders use one).
    #[arg(long, value_parser = clap::value_parser!(u32).range(1..=1024))]
    pub threads: Option<u32>,
}

#[derive(Debug, Args)]
pub struct FmtArgs {
    /// Scene text files, or folders to search for `.txt` and `.scene` files
    /// (`-` formats stdin to stdout).
    #[arg(required = true)]
    pub paths: Vec<PathBuf>,
    /// Write nothing; list the files that would change and exit 1 if any.
    #[arg(long)]
    pub check: bool,
}

#[derive(Debug, Args)]
pub struct LspArgs {
    /// Milliseconds a document must go unchanged before it is re-checked.
    #[arg(long, default_value_t = 150, value_name = "MS")]
    pub debounce_ms: u64,
}

/// A contrast for `--aa-threshold`: a number of 1/255 steps from 0 to
/// 255, fractions allowed (0.5 is half an 8-bit step).
fn contrast_steps(text: &str) -> Result<f64, String> {
    let steps: f64 = text
        .parse()
        .map_err(|_| format!("expected a number of 1/255 steps, found `{text}`"))?;
    if (0.0..=255.0).contains(&steps) {
        Ok(steps)
    } else {
        Err(format!("expected a number from 0 to 255, found `{text}`"))
    }
}

/// Parse the process arguments, accepting `raytracer SCENE OUT` for
/// `raytracer render SCENE OUT`.
pub fn parse_args(args: impl IntoIterator<Item = OsString>) -> Result<Cli, clap::Error> {
    let mut args: Vec<OsString> = args.into_iter().collect();
    let is_subcommand = |a: &OsString| {
        let a = a.to_string_lossy();
        a.starts_with('-') && a != "-"
            || matches!(
                &*a,
                "render" | "check" | "convert" | "stitch" | "accuracy" | "fmt" | "lsp" | "help"
            )
    };
    if args.len() > 1 && !is_subcommand(&args[1]) {
        args.insert(1, "render".into());
    }
    Cli::try_parse_from(args)
}

#[cfg(test)]
mod tests {
    use super::*;

    fn parse(args: &[&str]) -> Result<Cli, clap::Error> {
        parse_args(args.iter().map(OsString::from))
    }

    #[test]
    fn bare_form_is_render() {
        let cli = parse(&["raytracer", "scene.txt", "out.ppm"]).unwrap();
        let Command::Render(args) = cli.command else {
            panic!("not render")
        };
        assert_eq!(args.out, PathBuf::from("out.ppm"));
        assert_eq!(args.max_depth, 8);
        assert_eq!(args.spp, 1);
    }

    #[test]
    fn flags_are_still_flags() {
        assert!(parse(&["raytracer", "--version"]).is_err_and(|e| e.exit_code() == 0));
        assert!(parse(&["raytracer", "check"]).is_err_and(|e| e.exit_code() == 2));
    }

    #[test]
    fn convert_json_is_short_for_to_json() {
        let target = |args: &[&str]| match parse(args).map(|cli| cli.command) {
            Ok(Command::Convert(args)) => Ok(args.target()),
            Ok(_) => panic!("not convert"),
            Err(e) => Err(e.kind()),
        };
        assert_eq!(
            target(&["raytracer", "convert", "s.txt", "--json"]),
            Ok(Target::Json)
        );
        assert_eq!(
            target(&["raytracer", "convert", "s.txt", "--to", "pov"]),
            Ok(Target::Pov)
        );
        assert_eq!(
            target(&["raytracer", "convert", "s.txt", "--json", "--to", "pov"]),
            Err(clap::error::ErrorKind::ArgumentConflict)
        );
        assert_eq!(
            target(&["raytracer", "convert", "s.txt"]),
            Err(clap::error::ErrorKind::MissingRequiredArgument)
        );
    }

    #[test]
    fn clap_definition_is_consistent() {
        use clap::CommandFactory;
        Cli::command().debug_assert();
    }

    #[test]
    fn the_threshold_takes_fractions_of_a_step_and_nothing_outside_0_to_255() {
        let threshold = |value: &str| match parse(&[
            "raytracer",
            "render",
            "s.txt",
            "o.png",
            "--aa-threshold",
            value,
        ]) {
            Ok(Cli {
                command: Command::Render(args),
                ..
            }) => Ok(args.aa_threshold),
            Ok(_) => panic!("not render"),
            Err(e) => Err(e.exit_code()),
        };
        assert_eq!(threshold("0.5"), Ok(0.5));
        assert_eq!(threshold("0"), Ok(0.0));
        assert_eq!(threshold("255"), Ok(255.0));
        for bad in ["-1", "256", "NaN", "inf", "two"] {
            assert_eq!(threshold(bad), Err(2), "{bad}");
        }
    }
}
