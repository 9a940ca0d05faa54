//! The statistics of a render: what `raytracer render --stats` prints,
//! what `--stats-json` writes, and the part of a tile's statistics that
//! `raytracer stitch --part-stats` reads back and sums ([`TileStats`]).
//! One definition, so the writer and the reader cannot drift apart.

use serde::{Deserialize, Serialize};

use raytracer_render::ir::Effects;
use raytracer_render::render::{Accel, Counters, Precision};
use raytracer_render::tile::TileInfo;

/// Seconds per stage.
#[derive(Clone, Copy, Debug, Default, Serialize, Deserialize, derive_more::AddAssign)]
pub struct Seconds {
    pub parse: f64,
    pub check: f64,
    pub lower: f64,
    pub render: f64,
    pub write: f64,
    pub total: f64,
}

/// What `render --stats` prints and `--stats-json` writes.
#[derive(Clone, Debug, Serialize)]
pub struct Stats {
    #[serde(flatten)]
    pub counters: Counters,
    pub seconds: Seconds,
    pub threads: usize,
    pub precision: Precision,
    pub spp: u32,
    pub antialias: &'static str,
    pub max_depth: u32,
    pub skip: bool,
    /// What was asked for (`auto` chooses by the scene's size).
    pub accel: Accel,
    /// What ran: `bvh` (with `bvh_nodes` nodes) or `brute`.
    pub accel_used: &'static str,
    pub resolution: u32,
    pub effects: Effects,
    /// With `--tile`: where the tile belongs.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub tile: Option<TileInfo>,
}

/// What a tile's `--stats-json` holds that `stitch` sums.
#[derive(Clone, Debug, Deserialize)]
pub struct TileStats {
    #[serde(flatten)]
    pub counters: Counters,
    pub seconds: Seconds,
    pub tile: TileInfo,
}

impl Stats {
    /// Which pixels took how many samples.
    fn sampling(&self) -> String {
        if self.antialias == "adaptive" {
            let pixels = u64::from(self.resolution).pow(2);
            format!(
                "adaptive: of {pixels} pixels {} took {} samples, {} took 4, the rest only their corners",
                self.counters.pixels_refined, self.spp, self.counters.pixels_partly_refined
            )
        } else {
            format!("uniform: every pixel took {}", self.spp)
        }
    }

    /// The `--stats` block for stderr.
    pub fn human(&self) -> String {
        let c = &self.counters;
        let s = &self.seconds;
        format!(
            "effects            {}\n\
             primary rays       {} (samples; {})\n\
             shadow rays        {} ({} skipped)\n\
             reflection rays    {} ({} paths saturated)\n\
             texture lookups    {}\n\
             acceleration       {} (--accel {})\n\
             seconds            parse {:.4}, check {:.4}, lower {:.4}, render {:.4}, write {:.4}, total {:.4}\n\
             threads            {} ({}, {} spp, max depth {})\n",
            self.effects.summary(),
            c.primary_rays,
            self.sampling(),
            c.shadow_rays,
            c.shadow_rays_skipped,
            c.reflection_rays,
            c.paths_saturated,
            c.texture_lookups,
            match c.bvh_nodes {
                0 => "brute force".to_string(),
                1 => "bvh, 1 node".to_string(),
                nodes => format!("bvh, {nodes} nodes"),
            },
            format!("{:?}", self.accel).to_lowercase(),
            s.parse,
            s.check,
            s.lower,
            s.render,
            s.write,
            s.total,
            self.threads,
            self.precision,
            self.spp,
            self.max_depth,
        ) + &self.tile.as_ref().map_or(String::new(), |tile| {
            let rows = tile.rows();
            format!(
                "tile               {} (rows {}..{} of {})\n",
                tile.band(),
                rows.start,
                rows.end,
                tile.height
            )
        })
    }
}
