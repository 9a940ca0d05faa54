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
#[command(name = "raytracer", version, long_about = None)]
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
    /// Serve a local page that re-renders the scene, and shows its
    /// diagnostics, every time it or one of its textures is saved.
    Preview(PreviewArgs),
    /// Compare a candidate image with a reference: ꟻLIP, RMSE and PSNR,
    /// and the coverage of their non-black pixels.
    Compare(CompareArgs),
    /// Grade a ray tracer: run it on a suite of scenes in a sandbox and
    /// compare each image with ours, into an HTML report.
    Grade(Box<GradeArgs>),
    /// Print a completion script for SHELL to stdout, as in
    /// `raytracer completions bash > ~/.local/share/bash-completion/completions/raytracer`.
    Completions(CompletionsArgs),
    /// Print the man page, in roff, to stdout (`make man` writes raytracer.1).
    Man,
}

/// `raytracer completions SHELL`.
#[derive(Debug, Args)]
pub struct CompletionsArgs {
    /// The shell to complete in.
    pub shell: clap_complete::Shell,
}

/// The completion script for `shell`, generated from this command line.
pub fn completions(shell: clap_complete::Shell) -> Vec<u8> {
    let mut command = <Cli as clap::CommandFactory>::command();
    let mut out = Vec::new();
    clap_complete::generate(shell, &mut command, "raytracer", &mut out);
    out
}

/// The man page of `raytracer`, in roff, generated from this command line.
pub fn man_page() -> Vec<u8> {
    let command = <Cli as clap::CommandFactory>::command();
    let mut out = Vec::new();
    // Writing to a vector cannot fail.
    let _ = clap_mangen::Man::new(command).render(&mut out);
    out
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
          value_parser = PossibleValuesParser::new(["f32", "f64"]).try_map(|s| s.parse::<Precision>()))]
    pub precision: Precision,
    /// Samples per pixel, stratified on a √N×√N grid (1 = pixel centre).
    #[arg(long, default_value_t = 1, value_parser = clap::value_parser!(u32).range(1..=1024))]
    pub spp: u32,
    /// Which pixels take all `--spp` samples: every one, or only those
    /// whose corners, then four samples, differ by the adaptive threshold
    /// (`render --aa-threshold`).
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
    /// With `--fix`, also apply the unsafe fixes (such as a "did you
    /// mean" replacement).
    #[arg(long, requires = "fix")]
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
    /// Where diagnostic codes link: the URL of docs/diagnostics.md
    /// [default: codes are not links].
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
pub fn parse_args(args: impl IntoIterator<Item = OsString>) -> Result<Cli, clap::Error> {
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
    Cli::try_parse_from(args)
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
    /// The least intersection over union of the two images' non-black
    /// pixels; below it the geometry differs.
    #[arg(long, value_name = "IOU", default_value_t = crate::compare::DEFAULT_MIN_COVERAGE, value_parser = unit_interval)]
    pub min_coverage: f64,
    /// The largest mean ꟻLIP error; above it the appearance differs.
    #[arg(long, value_name = "FLIP", default_value_t = crate::compare::DEFAULT_MAX_FLIP, value_parser = unit_interval)]
    pub max_flip: f64,
    /// A pixel is black (not covered) when no channel exceeds this (0–255).
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
    /// The image to judge against it.
    pub candidate: PathBuf,
    /// Write the ꟻLIP error map, in ꟻLIP's colour map, to this PNG.
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
        parse_args(args.iter().map(OsString::from))
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
