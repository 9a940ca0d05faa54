//! The command line: every clap type in one place (the ripgrep layout).
//!
//! `raytracer SCENE OUT` is the course's form of `raytracer render SCENE OUT`;
//! [`parse_args`] rewrites it before clap sees the arguments.

use std::ffi::OsString;
use std::path::PathBuf;

use clap::builder::{PossibleValuesParser, TypedValueParser};
use clap::{Args, Parser, Subcommand, ValueEnum};

use raytracer_render::render::adaptive::DEFAULT_THRESHOLD;
use raytracer_render::render::{self, Accel};
use raytracer_render::tile::Band;

/// Render and check scenes of the raytracer scene language.
#[derive(Debug, Parser)]
#[command(name = "raytracer", long_about = None)]
#[command(override_usage = "raytracer SCENE OUT [OPTIONS]\n       raytracer <COMMAND>")]
#[command(
    after_help = "`raytracer SCENE OUT` is short for `raytracer render SCENE OUT` \
(the course's form).\n\n\
Exit codes: 0 success; 1 the command's own failure (a scene with errors, images that \
differ, files that would change: each command's --help says which); 2 a usage error, a \
file that cannot be read or written, or an internal error; 130 interrupted (Ctrl-C; no \
output file is left half-written)."
)]
pub struct Cli {
    #[command(subcommand)]
    pub command: Command,
    /// The version `--version` printed: this build's (the binary's build
    /// script names its commit), for the man pages.
    #[arg(skip)]
    pub version: &'static str,
}

/// Each command's exit codes, at the end of its `--help` and its man page
/// (docs/cli.md shows them from there).
mod exit {
    pub const RENDER: &str = "Exit codes: 0 the image was written; 1 the scene has errors \
(nothing is written); 2 a usage error or a file that cannot be read or written; 130 \
interrupted (no output file is left half-written).";
    pub const CHECK: &str = "Exit codes: 0 no scene has errors (warnings allowed); 1 a \
scene has errors (or warnings, with --deny-warnings), or a scene found in a folder cannot \
be read; 2 a usage error or a file named on the command line that cannot be read.";
    pub const CONVERT: &str = "Exit codes: 0 converted; 1 the scene has errors (nothing is \
written); 2 a usage error or a file that cannot be read or written.";
    pub const FMT: &str = "Exit codes: 0 formatted, or with --check nothing would change; \
1 with --check a file would change, or a file has syntax errors (it is left alone), or a \
file found in a folder cannot be read; 2 a usage error, a JSON scene or a file that cannot \
be read, named on the command line.";
    pub const LSP: &str = "Exit codes: 0 after the protocol's shutdown and exit; 1 the \
client exited or disconnected without shutdown; 2 the conversation could not start.";
    pub const STITCH: &str = "Exit codes: 0 the image was written; 1 the parts do not make \
one frame (nothing is written); 2 a usage error or a file that cannot be read or written.";
    pub const ACCURACY: &str = "Exit codes: 0 the report was printed; 1 a scene has errors \
(nothing is measured); 2 a usage error (such as a --reference-spp that is not a square) \
or a file that cannot be read or written.";
    pub const PREVIEW: &str = "Exit codes: 130 stopped by Ctrl-C, its normal end; 2 it \
could not start (SCENE `-` or unreadable, an --spp that is not a square, an address that \
cannot be bound).";
    pub const COMPARE: &str = "Exit codes: 0 every candidate matches the reference (with \
--scene, every aspect passes); 1 one differs (in coverage, appearance or size; with --scene, in \
an aspect); 2 an image or the scene cannot be read, or the heat map cannot be written (or is \
asked of more than one candidate).";
    pub const GRADE: &str = "Exit codes: 0 every scene matches (with --class, every scene \
of every student); 1 a scene does not; 2 a usage error, a student folder without a usable \
tracer.txt or build.txt, a suite that cannot be read or has a scene with errors, a summary \
--merge cannot read, a report or cache that cannot be written, or no box for the programs \
without --unprotected.";
    pub const PRINT: &str = "Exit codes: 0 printed; 2 a usage error or a file that cannot \
be written.";
}

#[derive(Debug, Subcommand)]
pub enum Command {
    /// Render a scene to an image (.ppm or .png, by OUT's extension).
    #[command(after_help = exit::RENDER)]
    Render(RenderArgs),
    /// Check scenes and report every problem (a linter).
    #[command(after_help = exit::CHECK)]
    Check(CheckArgs),
    /// Convert a scene to JSON, canonical scene text, or POV-Ray.
    #[command(after_help = exit::CONVERT)]
    Convert(ConvertArgs),
    /// Lay out scene text files canonically, keeping every comment.
    #[command(after_help = exit::FMT)]
    Fmt(FmtArgs),
    /// Serve the Language Server Protocol on stdin and stdout (for editors).
    #[command(after_help = exit::LSP)]
    Lsp(LspArgs),
    /// Put the tiles of `render --tile` together into one image.
    #[command(after_help = exit::STITCH)]
    Stitch(StitchArgs),
    /// Measure what accuracy costs for a scene: error and time of each
    /// setting against a converged reference, as a table with findings.
    #[command(after_help = exit::ACCURACY)]
    Accuracy(AccuracyArgs),
    /// Serve a local page that re-renders the scene, and shows its
    /// diagnostics, every time it or one of its textures is saved.
    #[command(after_help = exit::PREVIEW)]
    Preview(PreviewArgs),
    /// Compare candidate images with a reference, each on its own: ꟻLIP,
    /// RMSE and PSNR, and the coverage of their pixels off the background;
    /// given the scene, grade's judge, aspect by aspect.
    #[command(after_help = exit::COMPARE)]
    Compare(CompareArgs),
    /// Grade a ray tracer: run it on a suite of scenes in a sandbox and
    /// judge each image against ours, into an HTML report.
    #[command(after_help = exit::GRADE, arg_required_else_help = true)]
    #[command(
        override_usage = "raytracer grade --tracer COMMAND [SUITE]... -o REPORT [OPTIONS]\n       \
raytracer grade --student DIR [SUITE]... -o REPORT [OPTIONS]\n       \
raytracer grade --class DIR [SUITE]... -o REPORT [OPTIONS]\n       \
raytracer grade --merge REPORT\n       \
raytracer grade --export-suite DIR"
    )]
    Grade(Box<GradeArgs>),
    /// Print a completion script for SHELL to stdout.
    #[command(after_help = COMPLETIONS_HELP)]
    Completions(CompletionsArgs),
    /// Print the man page of `raytracer`, or of one command, in roff; or
    /// write every page to a folder (`make man` writes target/man/).
    #[command(after_help = exit::PRINT)]
    Man(ManArgs),
}

/// Where each shell finds the script, from a home where the folder may
/// not exist yet (as README.md's install section has it), and the exit codes.
const COMPLETIONS_HELP: &str = "Where each shell finds it (the folders may need creating):
  bash (with the bash-completion package):
    dir=~/.local/share/bash-completion/completions
    mkdir -p $dir && raytracer completions bash > $dir/raytracer
  zsh (and `fpath=(~/.zfunc $fpath)` in ~/.zshrc, before compinit):
    mkdir -p ~/.zfunc && raytracer completions zsh > ~/.zfunc/_raytracer
  fish:
    mkdir -p ~/.config/fish/completions
    raytracer completions fish > ~/.config/fish/completions/raytracer.fish

Exit codes: 0 printed; 2 a usage error or a file that cannot be written.";

/// `raytracer completions SHELL`.
#[derive(Debug, Args)]
pub struct CompletionsArgs {
    /// The shell to complete in.
    pub shell: clap_complete::Shell,
}

/// `raytracer man [COMMAND] [--dir DIR]`.
#[derive(Debug, Args)]
pub struct ManArgs {
    /// The command whose page to print (`grade` prints raytracer-grade(1))
    /// [default: the page of `raytracer`].
    #[arg(value_name = "COMMAND")]
    pub command: Option<String>,
    /// Write every page (raytracer.1 and raytracer-COMMAND.1 for each
    /// command) to DIR, created if missing, instead of printing one.
    #[arg(long, value_name = "DIR", conflicts_with = "command")]
    pub dir: Option<PathBuf>,
}

/// The command line as clap sees it, with `version` for `--version` (the
/// build's, from the binary).
pub fn command(version: &'static str) -> clap::Command {
    <Cli as clap::CommandFactory>::command().version(version)
}

/// The completion script for `shell`, generated from this command line.
pub fn completions(shell: clap_complete::Shell, version: &'static str) -> Vec<u8> {
    let mut command = command(version);
    let mut out = Vec::new();
    clap_complete::generate(shell, &mut command, "raytracer", &mut out);
    out
}

/// The man pages, generated from this command line (clap_mangen): the
/// page of `raytracer` (named `raytracer.1`), then one per command
/// (`raytracer-grade.1`), each with its options and exit codes, as
/// (file name, roff).
pub fn man_pages(version: &'static str) -> Vec<(String, Vec<u8>)> {
    let mut top = command(version).disable_help_subcommand(true);
    top.build();
    let mut pages = Vec::new();
    let mut page = |cmd: clap::Command| {
        // The footer's centre, where a date would go, names the build: an
        // empty date would shift the title line's fields (roff quotes only
        // words with spaces).
        let man = clap_mangen::Man::new(cmd)
            .date(format!("raytracer {version}"))
            .source("raytracer")
            .manual("General Commands Manual");
        let mut roff = Vec::new();
        // Writing to a vector cannot fail.
        let _ = man.render(&mut roff);
        pages.push((man.get_filename(), roff));
    };
    for sub in top.get_subcommands() {
        page(sub.clone().version(version));
    }
    page(top);
    pages.rotate_right(1);
    pages
}

/// `--accel`: the renderer's [`Accel`] as the command line spells it.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, ValueEnum)]
pub enum AccelArg {
    /// A hierarchy above a few primitives, else testing them all.
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
pub use raytracer_render::render::Precision;

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

impl Antialias {
    /// The renderer's setting, refining at `threshold` when adaptive.
    pub fn with_threshold(self, threshold: f64) -> render::Antialias {
        match self {
            Antialias::Uniform => render::Antialias::Uniform,
            Antialias::Adaptive => render::Antialias::Adaptive { threshold },
        }
    }
}

/// The options `render` and `preview` share: how each pixel is sampled and
/// computed, and on how many threads.
#[derive(Debug, Args)]
pub struct SamplingArgs {
    /// Floating-point precision of every ray computation.
    #[arg(long, default_value = "f64",
          value_parser = PossibleValuesParser::new(["f32", "f64"]).map(|s| if s == "f32" { Precision::F32 } else { Precision::F64 }))]
    pub precision: Precision,
    /// Samples per pixel, stratified on a √N×√N grid (1 = pixel centre).
    #[arg(long, default_value_t = 1, value_parser = clap::value_parser!(u32).range(1..=1024))]
    pub spp: u32,
    /// Which pixels take all `--spp` samples: every one, or only those
    /// whose corners, then four samples, differ by more than the adaptive
    /// threshold.
    #[arg(long, value_enum, default_value_t = Antialias::Uniform)]
    pub aa: Antialias,
    /// Worker threads for rendering (default: all cores).
    #[arg(long, value_parser = clap::value_parser!(u32).range(1..=1024))]
    pub threads: Option<u32>,
}

#[derive(Debug, Args)]
pub struct RenderArgs {
    /// Scene file (`.json` is read as JSON; `-` reads stdin).
    pub scene: PathBuf,
    /// Output image; the extension picks the format.
    pub out: PathBuf,
    #[command(flatten)]
    pub sampling: SamplingArgs,
    /// The contrast within a pixel, in steps of 1/255 (fractions allowed),
    /// that refines it under `--aa adaptive` (0 refines every pixel).
    #[arg(long, default_value_t = DEFAULT_THRESHOLD, value_name = "STEPS", value_parser = contrast_steps)]
    pub aa_threshold: f64,
    /// Maximum number of reflections per primary ray.
    #[arg(long, default_value_t = 8, value_parser = clap::value_parser!(u32).range(0..=64))]
    pub max_depth: u32,
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
    /// Also apply the unsafe fixes (such as a "did you mean"
    /// replacement); implies `--fix`.
    #[arg(long)]
    pub unsafe_fixes: bool,
    /// Show at most N problems per file in the human and short formats,
    /// then how many more there are (0 shows every one; the json, sarif
    /// and github formats always carry every one).
    #[arg(long, value_name = "N", default_value_t = 50)]
    pub max_errors: usize,
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
#[command(group(clap::ArgGroup::new("target").args(["to", "json"])))]
pub struct ConvertArgs {
    /// Scene file (`.json` is read as JSON; `-` reads stdin).
    pub scene: PathBuf,
    /// Output language [default: from the extension of `-o`: `.json`,
    /// `.txt` or `.scene`, `.pov`].
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
    /// The output language: `--to`, `--json` (clap allows one of them),
    /// or the extension of `-o`. `None` when none says it.
    pub fn target(&self) -> Option<Target> {
        let by_extension = || {
            let extension = self.output.as_deref()?.extension()?.to_str()?;
            match extension.to_ascii_lowercase().as_str() {
                "json" => Some(Target::Json),
                "txt" | "scene" => Some(Target::Scene),
                "pov" => Some(Target::Pov),
                _ => None,
            }
        };
        self.to
            .or(self.json.then_some(Target::Json))
            .or_else(by_extension)
    }
}

/// The usage error of a `convert` that does not say what to write.
fn convert_without_target(args: &ConvertArgs) -> Option<clap::Error> {
    use clap::CommandFactory;
    if args.target().is_some() {
        return None;
    }
    let message = match &args.output {
        Some(path) => format!(
            "cannot tell the output language from `{}`: give `--to json`, `--to scene` or `--to pov`, or name the output `.json`, `.txt` or `.pov`",
            raytracer_scene::escape::escape(&path.display().to_string())
        ),
        None => "expected `--to json`, `--to scene` or `--to pov` (or `-o` with a `.json`, `.txt` or `.pov` name)".to_string(),
    };
    Some(
        Cli::command()
            .find_subcommand_mut("convert")?
            .error(clap::error::ErrorKind::MissingRequiredArgument, message),
    )
}

#[derive(Debug, Args)]
pub struct AccuracyArgs {
    /// Scene files (`.json` is read as JSON). With several thresholds they
    /// are the tuning set that chooses one.
    #[arg(required = true, num_args = 1..)]
    pub scenes: Vec<PathBuf>,
    /// Scenes measured only at the threshold the SCENES chose, and judged
    /// apart from them.
    #[arg(long, value_name = "SCENE", num_args = 1..)]
    pub held_out: Vec<PathBuf>,
    /// Render at N×N [default: the scene's own side, or its smallest odd
    /// multiple of at least 128, or its largest odd divisor of at most
    /// 400, each of which keeps every pixel centre].
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
    /// of 1/255 (fractions allowed); several, comma-separated, are
    /// candidates the SCENES choose among.
    #[arg(long, default_values_t = [DEFAULT_THRESHOLD], value_name = "STEPS", value_parser = contrast_steps, value_delimiter = ',')]
    pub aa_threshold: Vec<f64>,
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
pub struct PreviewArgs {
    /// Scene file to watch (`.json` is read as JSON; not `-`).
    pub scene: PathBuf,
    /// TCP port to listen on (0 picks a free one; the printed URL says which).
    #[arg(long, default_value_t = 8000)]
    pub port: u16,
    /// Address to listen on. Anything but a loopback address lets every
    /// machine that can reach this one see the scene and its image: unsafe
    /// on a shared machine or network.
    #[arg(long, default_value = "127.0.0.1", value_name = "ADDRESS")]
    pub bind: std::net::IpAddr,
    /// Open the page in the default browser.
    #[arg(long)]
    pub open: bool,
    /// Render at most N×N pixels: a larger camera resolution is rendered
    /// at N (the same view, fewer pixels).
    #[arg(long, default_value_t = 800, value_name = "N", value_parser = clap::value_parser!(u32).range(1..=16384))]
    pub max_size: u32,
    #[command(flatten)]
    pub sampling: SamplingArgs,
    /// Where diagnostic codes link: the URL of docs/diagnostics.md, beside
    /// which each code's page is (docs/diagnostics/) [default: codes are
    /// not links].
    #[arg(long, value_name = "URL")]
    pub docs: Option<String>,
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

/// The commands, as the first argument names them: clap's subcommands (so
/// a new command is never taken for a scene) and `help`.
fn command_names() -> Vec<String> {
    <Cli as clap::CommandFactory>::command()
        .get_subcommands()
        .map(|c| c.get_name().to_string())
        .chain(["help".to_string()])
        .collect()
}

/// Parse the process arguments, accepting `raytracer SCENE OUT` for
/// `raytracer render SCENE OUT`. A first argument that is no command and
/// no existing file, and does not look like a path (no `.`, `/` or `\`),
/// is a mistyped command (exit 2), with the nearest command suggested.
pub fn parse_args(
    args: impl IntoIterator<Item = OsString>,
    version: &'static str,
) -> Result<Cli, clap::Error> {
    let mut args: Vec<OsString> = args.into_iter().collect();
    let names = command_names();
    let is_subcommand = |a: &OsString| {
        let a = a.to_string_lossy();
        a.starts_with('-') && a != "-" || names.iter().any(|name| *name == a)
    };
    if args.len() > 1 && !is_subcommand(&args[1]) {
        if let Some(error) = unknown_command(&args[1], &names) {
            return Err(error);
        }
        args.insert(1, "render".into());
    }
    use clap::FromArgMatches;
    let matches = command(version).try_get_matches_from(args)?;
    let mut cli = Cli::from_arg_matches(&matches)?;
    cli.version = version;
    if let Command::Man(ManArgs {
        command: Some(name),
        ..
    }) = &cli.command
    {
        // Every command has a page; `help` has none.
        let pages: Vec<String> = names.into_iter().filter(|n| n != "help").collect();
        if !pages.contains(name) {
            let shown = raytracer_scene::escape::escape(name);
            let expected = pages
                .iter()
                .map(|c| format!("`{c}`"))
                .collect::<Vec<_>>()
                .join(", ");
            return Err(command(version).error(
                clap::error::ErrorKind::InvalidValue,
                format!("unknown command `{shown}`: expected one of {expected}"),
            ));
        }
    }
    if let Command::Convert(convert) = &cli.command {
        if let Some(error) = convert_without_target(convert) {
            return Err(error);
        }
    }
    Ok(cli)
}

/// The usage error for a first argument that is a mistyped command rather
/// than a scene path, or `None` when it may be a scene.
fn unknown_command(first: &OsString, names: &[String]) -> Option<clap::Error> {
    use clap::CommandFactory;
    let word = first.to_string_lossy();
    let candidates: Vec<&str> = names.iter().map(String::as_str).collect();
    let nearest = raytracer_scene::suggest::nearest(&word, &candidates).map(|(command, _)| command);
    let looks_like_path = word.contains(['.', '/', '\\']);
    if word == "-" || PathBuf::from(first).exists() || (looks_like_path && nearest.is_none()) {
        return None;
    }
    let shown = raytracer_scene::escape::escape(&word);
    let message = match nearest {
        Some(command) => format!("unknown command `{shown}`: did you mean `{command}`?"),
        None => format!(
            "unknown command `{shown}`: expected one of {}, or a scene file",
            candidates
                .iter()
                .map(|c| format!("`{c}`"))
                .collect::<Vec<_>>()
                .join(", ")
        ),
    };
    Some(Cli::command().error(clap::error::ErrorKind::InvalidSubcommand, message))
}

/// How `compare` prints its findings.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, ValueEnum)]
pub enum CompareFormat {
    /// Lines for a person.
    #[default]
    Human,
    /// One JSON object.
    Json,
}

/// The bounds within which two images match (`compare` and `grade`).
#[derive(Debug, Args)]
pub struct ThresholdArgs {
    /// The least intersection over union of the pixels each image covers
    /// (off its background colour); below it the verdict is `coverage`.
    #[arg(long, value_name = "IOU", default_value_t = crate::compare::DEFAULT_MIN_COVERAGE, value_parser = unit_interval)]
    pub min_coverage: f64,
    /// The largest mean ꟻLIP error; above it the appearance differs.
    #[arg(long, value_name = "FLIP", default_value_t = crate::compare::DEFAULT_MAX_FLIP, value_parser = unit_interval)]
    pub max_flip: f64,
    /// A pixel is background (not covered) when no channel is further than
    /// this from the image's background colour (0–255).
    #[arg(long, value_name = "VALUE", default_value_t = crate::compare::DEFAULT_BLACK_LEVEL)]
    pub black_level: u8,
}

impl ThresholdArgs {
    /// The thresholds as the library takes them.
    pub fn thresholds(&self) -> crate::compare::Thresholds {
        crate::compare::Thresholds {
            min_coverage: self.min_coverage,
            max_flip: self.max_flip,
            black_level: self.black_level,
        }
    }
}

/// A number in [0, 1].
fn unit_interval(text: &str) -> Result<f64, String> {
    match text.parse::<f64>() {
        Ok(value) if (0.0..=1.0).contains(&value) => Ok(value),
        _ => Err(format!("expected a number from 0 to 1, found `{text}`")),
    }
}

#[derive(Debug, Args)]
pub struct CompareArgs {
    /// The reference image (PPM, PNG or JPEG, recognised by content).
    pub reference: PathBuf,
    /// The images to judge against it, each on its own (one run judges a
    /// whole class's images of a scene, probing the scene once).
    #[arg(required = true, value_name = "CANDIDATE")]
    pub candidates: Vec<PathBuf>,
    /// Write the ꟻLIP error map, in ꟻLIP's colour map, to this PNG (one
    /// candidate only).
    #[arg(long, value_name = "OUT.png")]
    pub heatmap: Option<PathBuf>,
    /// The scene both images are of: judge the candidate aspect by aspect
    /// against the reference, as `grade` does (geometry, shadows,
    /// reflection, textures, shading), instead of pixel by pixel.
    #[arg(long, value_name = "SCENE")]
    pub scene: Option<PathBuf>,
    /// Output format.
    #[arg(long, value_enum, default_value_t = CompareFormat::Human)]
    pub format: CompareFormat,
    #[command(flatten)]
    pub thresholds: ThresholdArgs,
}

/// The limits `grade` runs each tracer process under.
#[derive(Debug, Args)]
pub struct SandboxArgs {
    /// Wall-clock seconds per scene; then the whole process group is killed.
    #[arg(long, value_name = "SECONDS", default_value_t = 60, value_parser = clap::value_parser!(u32).range(1..=86_400))]
    pub timeout: u32,
    /// CPU seconds per process (`RLIMIT_CPU`).
    #[arg(long, value_name = "SECONDS", default_value_t = 60, value_parser = clap::value_parser!(u32).range(1..=86_400))]
    pub cpu: u32,
    /// Address space per process in MiB (`RLIMIT_AS`).
    #[arg(long, value_name = "MIB", default_value_t = 4096, value_parser = clap::value_parser!(u32).range(16..))]
    pub memory: u32,
    /// The largest file a process may write, in MiB (`RLIMIT_FSIZE`).
    #[arg(long, value_name = "MIB", default_value_t = 256, value_parser = clap::value_parser!(u32).range(1..))]
    pub max_file_size: u32,
    /// The disk space of each run's working folder, in MiB, and 32,768
    /// files: in a box a scene's is a tmpfs of this size; other folders
    /// are watched, and the run killed when they hold more.
    #[arg(long, value_name = "MIB", default_value_t = 256, value_parser = clap::value_parser!(u32).range(1..))]
    pub disk: u32,
    /// Processes and threads the tracer's user may have at once
    /// (`RLIMIT_NPROC`; the count takes in every process of that user).
    #[arg(long, value_name = "N", default_value_t = 512, value_parser = clap::value_parser!(u32).range(1..))]
    pub max_processes: u32,
    /// Bytes of stdout and of stderr kept per scene, in KiB.
    #[arg(long, value_name = "KIB", default_value_t = 64, value_parser = clap::value_parser!(u32).range(1..))]
    pub max_output: u32,
    /// Grade even where no box (mount and PID namespaces) can be had, with
    /// only limits, a uid and a network namespace: the program can then
    /// read whatever its user may read (docs/grading.md, "The sandbox").
    #[arg(long)]
    pub unprotected: bool,
    /// The uids (and gids) a root grader runs students as, one each, FIRST
    /// to LAST: a range no account uses (an id that names a user or group
    /// is skipped; graders running at once share the range by lock files).
    #[arg(long, value_name = "FIRST-LAST", default_value = "60000-64999", value_parser = uid_range)]
    pub uids: std::ops::RangeInclusive<u32>,
}

/// `FIRST-LAST`, ids from 1 to 4294967294 (never root's, nor the
/// kernel's "no id", -1).
fn uid_range(text: &str) -> Result<std::ops::RangeInclusive<u32>, String> {
    let expected = || format!("expected a range of ids like `60000-64999`, found `{text}`");
    let (first, last) = text.split_once('-').ok_or_else(expected)?;
    let (first, last): (u32, u32) = (
        first.parse().map_err(|_| expected())?,
        last.parse().map_err(|_| expected())?,
    );
    if first == 0 || last == u32::MAX || first > last {
        return Err(format!(
            "expected ids from 1 to 4294967294 with FIRST at most LAST, found `{text}`"
        ));
    }
    Ok(first..=last)
}

#[derive(Debug, Args)]
#[command(group(clap::ArgGroup::new("mode").required(true)
    .args(["tracer", "student", "class", "merge", "export_suite"])))]
pub struct GradeArgs {
    /// The tracer's command line: `{scene}` and `{out}` are replaced by the
    /// scene's file name and the image to write; split into words like a
    /// shell would, never run through one.
    #[arg(long, value_name = "COMMAND")]
    pub tracer: Option<String>,
    /// Grade the student whose folder is DIR: its `tracer.txt` names the
    /// command, its optional `build.txt` a build run there first.
    #[arg(long, value_name = "DIR")]
    pub student: Option<PathBuf>,
    /// Grade every student folder in DIR into REPORT/<student>/, then
    /// write REPORT/class.html and REPORT/class.csv.
    #[arg(long, value_name = "DIR")]
    pub class: Option<PathBuf>,
    /// Write REPORT/class.html and REPORT/class.csv from the student
    /// reports in REPORT/*/summary.json, and exit.
    #[arg(long, value_name = "REPORT", conflicts_with_all = ["report", "suite"])]
    pub merge: Option<PathBuf>,
    /// Scene files or folders (default: the built-in suite).
    pub suite: Vec<PathBuf>,
    /// The report folder (index.html, summary.json, results.json; with
    /// `--class`, a folder per student and the class overview).
    #[arg(
        short = 'o',
        long = "output",
        value_name = "REPORT",
        required_unless_present_any = ["export_suite", "merge"]
    )]
    pub report: Option<PathBuf>,
    /// Write the built-in suite to DIR (scenes, textures, suite.json) and exit.
    #[arg(long, value_name = "DIR", conflicts_with_all = ["report", "suite"])]
    pub export_suite: Option<PathBuf>,
    /// Where our reference images are cached, by content hash (default:
    /// `$XDG_CACHE_HOME/raytracer/references`, else `~/.cache/…`).
    #[arg(long, value_name = "DIR")]
    pub cache: Option<PathBuf>,
    /// Compare with the images in DIR instead of ours: `DIR/<scene>.png`
    /// or `.ppm`, the scene's path with its extension replaced.
    #[arg(long, value_name = "DIR", conflicts_with = "reference_tracer")]
    pub references: Option<PathBuf>,
    /// Compare with the images the course's own tracer makes: COMMAND
    /// like `--tracer`, run once per scene under the same sandbox, its
    /// images cached by a hash of the command, its files and the scene.
    #[arg(long, value_name = "COMMAND")]
    pub reference_tracer: Option<String>,
    /// Render our reference with the course's constants instead of ours:
    /// a JSON file like `{"ambient": 0.2, "diffuse": 0.7, "specular": 0.5,
    /// "exponent": 20, "pixel": "corner", "reflection": "blended",
    /// "depth": 5}`, every key optional (docs/grading.md).
    #[arg(long, value_name = "FILE", conflicts_with_all = ["references", "reference_tracer"])]
    pub reference_options: Option<PathBuf>,
    /// Scenes graded at once.
    #[arg(long, value_name = "N", default_value_t = 1, value_parser = clap::value_parser!(u32).range(1..=256))]
    pub jobs: u32,
    #[command(flatten)]
    pub thresholds: ThresholdArgs,
    #[command(flatten)]
    pub sandbox: SandboxArgs,
}

#[cfg(test)]
mod tests {
    use super::*;

    fn parse(args: &[&str]) -> Result<Cli, clap::Error> {
        parse_args(args.iter().map(OsString::from), "0.0.0 (commit test)")
    }

    #[test]
    fn uid_ranges_are_first_to_last_and_never_root() {
        assert_eq!(uid_range("65100-65109"), Ok(65_100..=65_109));
        assert_eq!(uid_range("7-7"), Ok(7..=7));
        for bad in ["0-10", "10-9", "60000", "1-4294967295", "a-b", "-5-6"] {
            assert!(uid_range(bad).is_err(), "{bad}");
        }
    }

    #[test]
    fn bare_form_is_render() {
        let cli = parse(&["raytracer", "scene.txt", "out.ppm"]).unwrap();
        let Command::Render(args) = cli.command else {
            panic!("not render")
        };
        assert_eq!(args.out, PathBuf::from("out.ppm"));
        assert_eq!(args.max_depth, 8);
        assert_eq!(args.sampling.spp, 1);
    }

    #[test]
    fn flags_are_still_flags() {
        let version = parse(&["raytracer", "--version"]).unwrap_err();
        assert_eq!(version.exit_code(), 0);
        assert_eq!(version.to_string(), "raytracer 0.0.0 (commit test)\n");
        assert!(parse(&["raytracer", "check"]).is_err_and(|e| e.exit_code() == 2));
    }

    #[test]
    fn convert_json_is_short_for_to_json() {
        let target = |args: &[&str]| match parse(args).map(|cli| cli.command) {
            Ok(Command::Convert(args)) => Ok(args.target().expect("a target")),
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

    /// `-o x.json` says what to write (issue 56); `--to` still wins, and
    /// an extension that names no language is a usage error naming the
    /// file and the ways to say it.
    #[test]
    fn convert_infers_the_target_from_the_output_extension() {
        let target = |args: &[&str]| match parse(args).map(|cli| cli.command) {
            Ok(Command::Convert(args)) => Ok(args.target()),
            Ok(_) => panic!("not convert"),
            Err(e) => Err((e.kind(), e.to_string())),
        };
        for (output, expected) in [
            ("x.json", Target::Json),
            ("out/X.JSON", Target::Json),
            ("x.txt", Target::Scene),
            ("x.scene", Target::Scene),
            ("x.pov", Target::Pov),
        ] {
            assert_eq!(
                target(&["raytracer", "convert", "s.txt", "-o", output]),
                Ok(Some(expected)),
                "{output}"
            );
        }
        assert_eq!(
            target(&[
                "raytracer",
                "convert",
                "s.txt",
                "-o",
                "x.json",
                "--to",
                "pov"
            ]),
            Ok(Some(Target::Pov))
        );
        let (kind, message) =
            target(&["raytracer", "convert", "s.txt", "-o", "x.png"]).unwrap_err();
        assert_eq!(kind, clap::error::ErrorKind::MissingRequiredArgument);
        assert!(
            message.contains("cannot tell the output language from `x.png`: give `--to json`"),
            "{message}"
        );
    }

    #[test]
    fn mistyped_commands_are_usage_errors_and_scene_paths_are_render() {
        let error = parse(&["raytracer", "chekc", "x.txt"]).unwrap_err();
        assert_eq!(error.exit_code(), 2);
        assert!(
            error.to_string().contains("did you mean `check`?"),
            "{error}"
        );
        let error = parse(&["raytracer", "frobnicate", "--help"]).unwrap_err();
        assert_eq!(error.exit_code(), 2);
        assert!(error.to_string().contains("unknown command"), "{error}");
        for scene in ["scene.txt", "scenes/a", "missing.json", "-"] {
            assert!(
                matches!(
                    parse(&["raytracer", scene, "out.png"]).map(|c| c.command),
                    Ok(Command::Render(_))
                ),
                "{scene}"
            );
        }
    }

    /// Whether `text` names `option` (`--aa` in `--aa adaptive`, not in
    /// `--aa-threshold`).
    fn names(text: &str, option: &str) -> bool {
        text.match_indices(option).any(|(at, _)| {
            !text[at + option.len()..].starts_with(|c: char| c.is_alphanumeric() || c == '-')
        })
    }

    #[test]
    fn docs_cli_md_has_every_command_and_option() {
        use clap::CommandFactory;
        let docs = include_str!("../../../docs/cli.md");
        for command in Cli::command().get_subcommands() {
            let name = command.get_name();
            let heading = format!("\n## `raytracer {name}");
            let start = docs
                .find(&heading)
                .unwrap_or_else(|| panic!("docs/cli.md has no section for `{name}`"));
            let section = &docs[start + heading.len()..];
            let section = &section[..section.find("\n## ").unwrap_or(section.len())];
            for arg in command.get_arguments() {
                let Some(long) = arg.get_long() else { continue };
                assert!(
                    names(section, &format!("--{long}")),
                    "docs/cli.md's `{name}` section lacks `--{long}`"
                );
            }
        }
    }

    /// Every `--flag` a help text names, with the word before it when that
    /// word, in backticks with it, is another command (`render --tile`).
    fn named_flags(help: &str) -> Vec<(Option<String>, String)> {
        let mut flags = Vec::new();
        for (at, _) in help.match_indices("--") {
            let before = help[..at].chars().next_back();
            if before.is_some_and(|c| c.is_alphanumeric() || c == '-') {
                continue;
            }
            let name: String = help[at + 2..]
                .chars()
                .take_while(|c| c.is_ascii_alphanumeric() || *c == '-')
                .collect();
            let name = name.trim_end_matches('-').to_string();
            if name.is_empty() {
                continue;
            }
            let command = help[..at]
                .strip_suffix(' ')
                .and_then(|head| head.rsplit(['`', ' ', '(']).next())
                .filter(|word| help[..at].ends_with(&format!("`{word} ")))
                .map(str::to_string);
            flags.push((command, name));
        }
        flags
    }

    #[test]
    fn named_flags_finds_flags_and_the_command_they_belong_to() {
        assert_eq!(
            named_flags("tiles of `render --tile` (--aa-threshold, not-a--flag)"),
            [
                (Some("render".to_string()), "tile".to_string()),
                (None, "aa-threshold".to_string())
            ]
        );
    }

    /// Each help text, every command's and the top one's, names only flags
    /// its command has, or another command's in the form `render --tile`
    /// (the lists come from clap's definition, not from a list of ours).
    #[test]
    fn help_texts_name_only_flags_their_command_has() {
        let top = command("0.0.0");
        let longs = |cmd: &clap::Command| -> Vec<String> {
            cmd.get_arguments()
                .filter_map(|a| a.get_long())
                .map(str::to_string)
                .chain(["help".to_string()])
                .collect()
        };
        let mut commands: Vec<clap::Command> = top.get_subcommands().cloned().collect();
        commands.push(top.clone());
        let mut checked = 0;
        for mut cmd in commands {
            let mut own = longs(&cmd);
            if cmd.get_name() == "raytracer" {
                own.push("version".to_string());
            }
            let help = cmd.render_long_help().to_string();
            for (other, flag) in named_flags(&help) {
                let theirs = match &other {
                    Some(name) => longs(
                        top.find_subcommand(name)
                            .unwrap_or_else(|| panic!("`{name} --{flag}` names no command")),
                    ),
                    None => own.clone(),
                };
                assert!(
                    theirs.contains(&flag),
                    "the help of `{}` names `--{flag}`, which {} has not",
                    cmd.get_name(),
                    other.as_deref().unwrap_or("it")
                );
                checked += 1;
            }
        }
        assert!(
            checked > 100,
            "only {checked} flags were found in the help texts"
        );
    }

    #[test]
    fn grade_needs_an_output_only_where_it_writes_a_report() {
        let kind = |args: &[&str]| parse(args).err().map(|e| e.kind());
        assert_eq!(kind(&["raytracer", "grade", "--merge", "r"]), None);
        assert_eq!(kind(&["raytracer", "grade", "--export-suite", "d"]), None);
        assert_eq!(
            kind(&["raytracer", "grade", "--tracer", "t {scene} {out}"]),
            Some(clap::error::ErrorKind::MissingRequiredArgument)
        );
        assert_eq!(
            kind(&["raytracer", "grade", "--tracer", "t", "-o", "r"]),
            None
        );
        // Alone, it shows its forms rather than one missing option.
        assert_eq!(
            kind(&["raytracer", "grade"]),
            Some(clap::error::ErrorKind::DisplayHelpOnMissingArgumentOrSubcommand)
        );
    }

    #[test]
    fn the_usage_shows_the_course_form_and_every_command_its_exit_codes() {
        let mut top = command("0.0.0");
        let help = top.render_long_help().to_string();
        assert!(help.contains("Usage: raytracer SCENE OUT"), "{help}");
        for sub in top.get_subcommands_mut().filter(|s| s.get_name() != "help") {
            let help = sub.render_long_help().to_string();
            assert!(help.contains("\nExit codes: "), "{help}");
        }
    }

    #[test]
    fn there_is_a_man_page_for_raytracer_and_each_command_with_its_options() {
        let pages = man_pages("1.2.3 (commit abc)");
        let names: Vec<&str> = pages.iter().map(|(name, _)| name.as_str()).collect();
        let mut expected = vec!["raytracer.1".to_string()];
        expected.extend(
            command("0")
                .get_subcommands()
                .map(|c| format!("raytracer-{}.1", c.get_name())),
        );
        assert_eq!(names, expected);
        let grade = &pages
            .iter()
            .find(|(n, _)| n == "raytracer-grade.1")
            .unwrap()
            .1;
        let grade = String::from_utf8_lossy(grade);
        assert!(grade.contains(".TH raytracer-grade 1"), "{grade}");
        assert!(grade.contains("1.2.3 (commit abc)"), "{grade}");
        for option in command("0")
            .find_subcommand("grade")
            .unwrap()
            .get_arguments()
        {
            if let Some(long) = option.get_long() {
                let roff = format!("\\fB\\-\\-{}\\fR", long.replace('-', "\\-"));
                assert!(grade.contains(&roff), "raytracer-grade.1 lacks {roff}");
            }
        }
        assert!(grade.contains("Exit codes: 0 every scene matches"));
    }

    #[test]
    fn help_texts_hold_no_rustdoc_links() {
        use clap::CommandFactory;
        let mut command = Cli::command();
        for sub in command.get_subcommands_mut() {
            let help = sub.render_long_help().to_string();
            assert!(!help.contains("[`"), "{help}");
        }
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
