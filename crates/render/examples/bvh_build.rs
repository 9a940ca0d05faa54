//! Times what `render` does before its first ray: building the world of
//! a scene in double precision (converting its objects and building the
//! bounding volume hierarchy that `--accel auto` chooses), which
//! `seconds.render` of `render --stats-json` includes. `make bench`
//! subtracts it from that figure to compare tracing alone with Embree's
//! (docs/performance.md, "Building and tracing apart").
//!
//! `cargo run --release -p raytracer-render --example bvh_build -- SCENE
//! [REPS]` prints the median over REPS builds (default 5), in seconds, and
//! the hierarchy's wide nodes. Reading and checking the scene are not
//! timed. It builds on one thread, as `render --threads 1` does.

use std::io::Write as _;
use std::path::Path;
use std::time::Instant;

use raytracer_render::ir;
use raytracer_render::render::trace::Tracer;

fn main() -> Result<(), String> {
    let usage = "usage: bvh_build SCENE [REPS]";
    let mut args = std::env::args().skip(1);
    let path = args.next().ok_or_else(|| usage.to_string())?;
    let reps: usize = match args.next() {
        Some(s) => s
            .parse()
            .ok()
            .filter(|&n| n > 0)
            .ok_or_else(|| format!("expected a positive number of repetitions, found `{s}`"))?,
        None => 5,
    };
    let loaded = raytracer_scene::frontend::load(Path::new(&path))
        .map_err(|error| format!("cannot load `{path}`: {error}"))?;
    let checked = loaded
        .checked
        .ok_or_else(|| format!("`{path}` has errors: run `raytracer check` on it"))?;
    let scene = ir::lower(checked);
    let pool = rayon::ThreadPoolBuilder::new()
        .num_threads(1)
        .build()
        .map_err(|error| format!("cannot start a thread: {error}"))?;
    let mut seconds = Vec::with_capacity(reps);
    let mut nodes = 0;
    for _ in 0..reps {
        let start = Instant::now();
        let tracer = pool.install(|| Tracer::<f64>::new(&scene, 8, true));
        seconds.push(start.elapsed().as_secs_f64());
        nodes = tracer.bvh_nodes();
    }
    seconds.sort_by(f64::total_cmp);
    writeln!(
        std::io::stdout().lock(),
        "seconds {:.6}\nbvh_nodes {nodes}",
        seconds[reps / 2]
    )
    .map_err(|error| format!("cannot write the result: {error}"))
}
