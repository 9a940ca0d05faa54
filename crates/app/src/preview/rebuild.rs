//! One rebuild of the preview: read and check the scene through the front
//! end, publish its diagnostics, and when it is valid render it (a coarse
//! pass first on large images, so the page answers a save at once) and
//! publish each image as PNG.

use std::io::Write;
use std::path::{Path, PathBuf};
use std::time::Instant;

use raytracer_render::ir;
use raytracer_render::output::{self, Format};
use raytracer_render::render::Precision;
use raytracer_render::render::{self, Counters, Image, Options};
use raytracer_scene::diagnostic::JsonDiagnostic;
use raytracer_scene::frontend::load;

use super::state::{Phase, RenderStats, State};

/// Images at least this many pixels on a side get a coarse pass first.
const COARSE_FROM: u32 = 256;
/// The coarse pass renders one pixel for this many on each side.
const COARSE_STEP: u32 = 4;

/// How the preview renders.
pub struct Settings {
    pub options: Options,
    pub precision: Precision,
    /// The largest side rendered (`--max-size`).
    pub max_size: u32,
    pub pool: rayon::ThreadPool,
}

/// Rebuild the preview of the scene at `scene` into `state`; the paths of
/// the textures of the scene when it is valid.
pub fn rebuild(scene: &Path, settings: &Settings, state: &State) -> Vec<PathBuf> {
    let started = Instant::now();
    let loaded = match load(scene) {
        Ok(loaded) => loaded,
        Err(error) => {
            let phase = if scene.try_exists().is_ok_and(|exists| !exists) {
                Phase::Deleted
            } else {
                Phase::Unreadable
            };
            state.diagnosed(phase, vec![JsonDiagnostic::unreadable(scene, &error)]);
            return Vec::new();
        }
    };
    let diagnostics = loaded.report.entries().collect();
    let Some(checked) = loaded.checked else {
        state.diagnosed(Phase::Errors, diagnostics);
        return Vec::new();
    };
    state.diagnosed(Phase::Rendering, diagnostics);
    let textures = checked
        .textures
        .values()
        .map(|texture| PathBuf::from(&texture.path))
        .collect();
    let scene_resolution = checked.scene.camera.resolution;
    let mut lowered = ir::lower(checked);
    let check_seconds = started.elapsed().as_secs_f64();
    let size = scene_resolution.min(settings.max_size);
    let passes = if size >= COARSE_FROM {
        vec![size / COARSE_STEP, size]
    } else {
        vec![size]
    };
    for (pass, &side) in passes.iter().enumerate() {
        lowered.resolution = side;
        let rendering = Instant::now();
        let (image, counters) = settings.pool.install(|| trace(&lowered, settings));
        let render_seconds = rendering.elapsed().as_secs_f64();
        let encoding = Instant::now();
        let mut png = Vec::new();
        if let Err(error) = output::encode(&image, Format::Png, &mut png) {
            // Encoding into memory fails only on a bug; the page keeps the
            // last image and the terminal says why.
            let _ = writeln!(
                std::io::stderr(),
                "error: cannot encode the preview image: {error}"
            );
            return textures;
        }
        let stats = RenderStats {
            resolution: side,
            scene_resolution,
            check_seconds,
            render_seconds,
            encode_seconds: encoding.elapsed().as_secs_f64(),
            primary_rays: counters.primary_rays,
            shadow_rays: counters.shadow_rays,
            reflection_rays: counters.reflection_rays,
            spp: settings.options.spp,
            precision: settings.precision.name(),
            threads: settings.pool.current_num_threads(),
        };
        let coarse = pass + 1 < passes.len();
        state.rendered(png, coarse, stats);
    }
    textures
}

/// Render `scene` in the chosen precision on the current pool.
fn trace(scene: &ir::Scene, settings: &Settings) -> (Image, Counters) {
    render::render(settings.precision, scene, &settings.options, &|| {})
}
