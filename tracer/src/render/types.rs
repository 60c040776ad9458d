//! The render's types: what to render ([`RenderOptions`]), what comes out
//! ([`RenderResult`], with its counters [`RenderStats`]), and what the tiles share and
//! return inside a render.

use crate::render::shade::{self, Light, Material};
use crate::search::cull::Culler;
use crate::search::ray::{Precision, RayParams, RayStats};
use model_ir::camera::Camera;
use model_ir::shape::{Aabb, View};
use model_sources::Model;
use std::sync::atomic::AtomicBool;
use std::sync::Arc;
use std::time::{Duration, Instant};
use tracer_kit::progress::Progress;

/// What to render and how.
#[derive(Clone, Debug)]
pub struct RenderOptions {
    /// Image width in pixels.
    pub width: u32,
    /// Image height in pixels.
    pub height: u32,
    /// The camera placement.
    pub view: View,
    /// Rays are clipped to this box; the function is not looked at outside it.
    pub domain: Aabb,
    /// Absolute precision of the roots along the ray (`--eps`). `None`: a quarter of a
    /// pixel's footprint at the root's distance, floored at `1e-7` of the domain diagonal.
    pub eps: Option<f64>,
    /// Algorithm 2 (screen-space cell culling).
    pub culling: bool,
    /// Argument pruning in Algorithm 1.
    pub pruning: bool,
    /// Region specialisation ([`Shape::specialise`](model_ir::shape::Shape::specialise)): each cell culling keeps searches,
    /// and hands its rays, the shape specialised to its region. Only with `culling`;
    /// no effect on shapes that do not specialise (the built-in models).
    pub specialise: bool,
    /// Shadow rays towards the light.
    pub shadows: bool,
    /// Surface reflectance.
    pub material: Material,
    /// Colour of pixels that miss, RGB.
    pub background: [u8; 3],
    /// Told the number of tiles and each finished tile (a progress bar, say).
    pub progress: Option<Arc<dyn Progress>>,
    /// Stop starting new tiles after this instant (the result says it was cut).
    pub deadline: Option<Instant>,
    /// Stop starting new tiles once this flag is set.
    pub cancel: Option<Arc<AtomicBool>>,
    /// Tile side in pixels (the unit of parallel work and of the culling quadtree's root).
    pub tile: u32,
    /// How each pixel's first root is searched for.
    pub search: Search,
}

/// How the renderer searches for each pixel's first root. Both searches are sound and
/// find the same first roots within the precision.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum Search {
    /// [`Search::Slabs`] for a shape that specialises (formula, `.vm` and HyperFun
    /// tapes, with specialisation on), [`Search::Paper`] otherwise: the slab search
    /// gains by specialising every tile-slab (0.3-0.6 times the paper's CPU time on
    /// fidget's models and scenes of many primitives, in orthographic and perspective
    /// views), the paper's narrows the cells of a shape that does not with frustum
    /// forms in the render's arithmetic (0.5 times the slab search's on the built-in
    /// Mitchell and the other Appendix A models; `docs/slab-search.md`).
    #[default]
    Auto,
    /// Image tiles by depth slabs, each tile-slab one interval evaluation in a batch,
    /// down to Algorithm 1 on each ray's piece in a leaf's slab
    /// ([`crate::search::slabs`]).
    Slabs,
    /// The revised-affine paper's: Algorithm 2's cell culling in the arithmetic's cell
    /// form ([`crate::search::cull`], only with [`RenderOptions::culling`]), then
    /// Algorithm 1 on each ray from the depths culling left; for the paper's counts.
    Paper,
}

impl std::str::FromStr for Search {
    type Err = String;

    fn from_str(s: &str) -> Result<Self, String> {
        match s {
            "auto" => Ok(Search::Auto),
            "slabs" => Ok(Search::Slabs),
            "paper" => Ok(Search::Paper),
            _ => Err(format!("unknown search '{s}' (auto, slabs or paper)")),
        }
    }
}

impl Search {
    /// The search a render of `shape` runs: this one, [`Search::Auto`] resolved
    /// (`specialise`: whether the render specialises, [`RenderOptions::specialise`]).
    pub fn resolve<S: model_ir::shape::Shape>(self, shape: &S, specialise: bool) -> Search {
        match self {
            Search::Auto if specialise && shape.specialises() => Search::Slabs,
            Search::Auto => Search::Paper,
            s => s,
        }
    }

    /// Its name on the command line and in `--stats json`.
    pub fn name(self) -> &'static str {
        match self {
            Search::Auto => "auto",
            Search::Slabs => "slabs",
            Search::Paper => "paper",
        }
    }
}

impl RenderOptions {
    /// The model's domain and view, culling and pruning on, no shadows.
    pub fn new(model: &Model, width: u32, height: u32) -> Self {
        Self::for_view(model.view, model.domain, width, height)
    }

    /// A view and a domain, culling and pruning on, no shadows.
    pub fn for_view(view: View, domain: Aabb, width: u32, height: u32) -> Self {
        RenderOptions {
            width,
            height,
            view,
            domain,
            eps: None,
            culling: true,
            pruning: true,
            specialise: true,
            shadows: false,
            material: Material::default(),
            background: shade::BACKGROUND,
            progress: None,
            deadline: None,
            cancel: None,
            tile: 64,
            search: Search::default(),
        }
    }

    /// The precision actually used along primary rays (see [`RenderOptions::eps`]).
    pub fn precision(&self, cam: &Camera) -> Precision {
        match self.eps {
            Some(e) => Precision { abs: e, rel: 0.0 },
            None => Precision {
                abs: 1e-7 * (self.domain.max - self.domain.min).length() + 0.25 * cam.pixel_size(),
                rel: 0.25 * cam.pixel_angle(),
            },
        }
    }
}

/// Work and time counters of one render.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct RenderStats {
    /// Wall time of the render.
    pub wall: Duration,
    /// Primary rays traced (pixels not dropped by culling).
    pub rays: u64,
    /// Shadow rays traced.
    pub shadow_rays: u64,
    /// Range evaluations along rays (primary and shadow).
    pub range_evals: u64,
    /// Range evaluations along primary rays of pixels that hit.
    pub range_evals_hit: u64,
    /// Range evaluations of culling cells (narrowing and specialisation).
    pub cell_evals: u64,
    /// Range evaluations over the boxes of shading samples (the normals' tapes
    /// specialised there).
    pub shade_evals: u64,
    /// Instructions run by all range evaluations, on rays, cells and shading boxes, for
    /// shapes that are tapes ([`Shape::tape_len`](model_ir::shape::Shape::tape_len); 0 otherwise): with the three counts
    /// of evaluations, the mean tape length that specialisation brings down.
    pub range_ops: u64,
    /// Point evaluations (normals).
    pub point_evals: u64,
    /// Cells proved empty by culling.
    pub cells_culled: u64,
    /// Pixels inside culled cells (no ray traced).
    pub pixels_culled: u64,
    /// Segments proved root-free by argument pruning alone.
    pub pruned_empty: u64,
    /// Pixels whose ray hit the surface.
    pub hits: u64,
    /// Hit pixels whose root no sign change confirms: the six samples of `f` at the
    /// normal's step around the root (which the normal is computed from, so the check
    /// costs no evaluation) have one strict sign or are NaN; a sign change among them
    /// proves a surface point within that step. The search reports unconfirmed roots
    /// where a segment at the precision still has a range holding 0: tangent roots,
    /// features thinner than the precision, or a function whose ranges hold 0
    /// everywhere (infinite or NaN values).
    pub unconfirmed: u64,
    /// Rays whose unconfirmed hit was searched again in Hull (the default arithmetic,
    /// [`crate::render::auto_arith`]; 0 in every other).
    pub researched: u64,
    /// Tiles rendered in Hull throughout: the default arithmetic's sample tiles showed
    /// walls ([`crate::render::auto_arith`]; 0 in every other arithmetic).
    pub tiles_hull: u64,
    /// Whether the render stopped early (deadline or cancel): the pixels it did not finish are background.
    pub cut: bool,
    /// Tiles rendered.
    pub tiles_done: u64,
    /// Tiles in the image.
    pub tiles_total: u64,
}

impl RenderStats {
    /// Adds a ray search's counters (evaluations, instructions, pruned segments, point
    /// evaluations); hits are counted by the caller.
    pub(crate) fn add_rays(&mut self, r: &RayStats) {
        self.range_evals += r.range_evals;
        self.range_ops += r.range_ops;
        self.pruned_empty += r.pruned_empty;
        self.point_evals += r.point_evals;
    }

    /// Every counter under its field name (in `--stats json` and Python's stats), in
    /// this order; the wall time and `cut` are not counters.
    pub fn counters(&self) -> [(&'static str, u64); 17] {
        // Destructured so that a new counter cannot be left out.
        let RenderStats {
            wall: _,
            rays,
            shadow_rays,
            range_evals,
            range_evals_hit,
            cell_evals,
            shade_evals,
            range_ops,
            point_evals,
            cells_culled,
            pixels_culled,
            pruned_empty,
            hits,
            unconfirmed,
            researched,
            tiles_hull,
            cut: _,
            tiles_done,
            tiles_total,
        } = *self;
        [
            ("rays", rays),
            ("shadow_rays", shadow_rays),
            ("range_evals", range_evals),
            ("range_evals_hit", range_evals_hit),
            ("cell_evals", cell_evals),
            ("shade_evals", shade_evals),
            ("range_ops", range_ops),
            ("point_evals", point_evals),
            ("cells_culled", cells_culled),
            ("pixels_culled", pixels_culled),
            ("pruned_empty", pruned_empty),
            ("hits", hits),
            ("unconfirmed", unconfirmed),
            ("researched", researched),
            ("tiles_hull", tiles_hull),
            ("tiles_done", tiles_done),
            ("tiles_total", tiles_total),
        ]
    }

    /// Mean tape length of a range evaluation (rays and cells; 0 for shapes that are not
    /// tapes).
    pub fn mean_tape_len(&self) -> f64 {
        let evals = self.range_evals + self.cell_evals + self.shade_evals;
        if evals == 0 {
            0.0
        } else {
            self.range_ops as f64 / evals as f64
        }
    }

    /// Mean number of range evaluations per hit pixel (primary rays).
    pub fn mean_evals_per_hit(&self) -> f64 {
        if self.hits == 0 {
            0.0
        } else {
            self.range_evals_hit as f64 / self.hits as f64
        }
    }
}

/// Sums the counters (wall times too; `cut` if either was cut), as the searches'
/// [`RayStats`](crate::search::ray::RayStats) and
/// [`CullStats`](crate::search::cull::CullStats) sum.
impl std::ops::AddAssign for RenderStats {
    fn add_assign(&mut self, o: RenderStats) {
        self.wall += o.wall;
        self.rays += o.rays;
        self.shadow_rays += o.shadow_rays;
        self.range_evals += o.range_evals;
        self.range_evals_hit += o.range_evals_hit;
        self.cell_evals += o.cell_evals;
        self.shade_evals += o.shade_evals;
        self.range_ops += o.range_ops;
        self.point_evals += o.point_evals;
        self.cells_culled += o.cells_culled;
        self.pixels_culled += o.pixels_culled;
        self.pruned_empty += o.pruned_empty;
        self.hits += o.hits;
        self.unconfirmed += o.unconfirmed;
        self.researched += o.researched;
        self.tiles_hull += o.tiles_hull;
        self.cut |= o.cut;
        self.tiles_done += o.tiles_done;
        self.tiles_total += o.tiles_total;
    }
}

impl std::fmt::Display for RenderStats {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        writeln!(
            f,
            "wall time:            {:.3} s{}",
            self.wall.as_secs_f64(),
            if self.cut { " (cut short)" } else { "" }
        )?;
        writeln!(
            f,
            "rays:                 {} primary, {} shadow",
            self.rays, self.shadow_rays
        )?;
        writeln!(
            f,
            "range evaluations:    {} on rays, {} on cells, {} on shading boxes",
            self.range_evals, self.cell_evals, self.shade_evals
        )?;
        writeln!(f, "point evaluations:    {}", self.point_evals)?;
        writeln!(
            f,
            "cells culled:         {} ({} pixels)",
            self.cells_culled, self.pixels_culled
        )?;
        writeln!(f, "hit pixels:           {}", self.hits)?;
        writeln!(f, "unconfirmed hits:     {}", self.unconfirmed)?;
        if self.researched > 0 || self.tiles_hull > 0 {
            writeln!(
                f,
                "searched in hull:     {} rays, {} tiles",
                self.researched, self.tiles_hull
            )?;
        }
        write!(f, "range evals per hit:  {:.2}", self.mean_evals_per_hit())?;
        if self.range_ops > 0 {
            write!(f, "\nmean tape length:     {:.1}", self.mean_tape_len())?;
        }
        Ok(())
    }
}

/// An image with its depth and hit mask, row-major, row 0 at the top.
#[derive(Clone, Debug)]
pub struct RenderResult {
    /// Image width in pixels.
    pub width: u32,
    /// Image height in pixels.
    pub height: u32,
    /// RGB, 3 bytes per pixel.
    pub rgb: Vec<u8>,
    /// Distance from the eye along the normalised ray to the first root; `+inf` for a miss.
    pub depth: Vec<f32>,
    /// Whether each pixel's ray hit the surface.
    pub hit: Vec<bool>,
    /// The render's counters.
    pub stats: RenderStats,
}

impl RenderResult {
    /// The result of an image of `opts`'s size: its hit mask is where `depth` is finite.
    pub fn of_image(
        opts: &RenderOptions,
        rgb: Vec<u8>,
        depth: Vec<f32>,
        stats: RenderStats,
    ) -> Self {
        let hit = depth.iter().map(|d| d.is_finite()).collect();
        RenderResult {
            width: opts.width,
            height: opts.height,
            rgb,
            depth,
            hit,
            stats,
        }
    }
}

pub(crate) struct TileOut {
    pub(crate) rgb: Vec<u8>,
    pub(crate) depth: Vec<f32>,
    pub(crate) stats: RenderStats,
    /// Stopped before its last rays: those pixels are background.
    pub(crate) cut: bool,
    /// The rays (job indices) whose hits shading found unconfirmed.
    pub(crate) unconfirmed_rays: Vec<usize>,
    /// Of them, those a second search in Hull confirmed or removed.
    pub(crate) resolved: u64,
}

impl TileOut {
    /// `n` pixels of background.
    pub(crate) fn background(opts: &RenderOptions, n: usize) -> Self {
        TileOut {
            rgb: opts.background.repeat(n),
            depth: vec![f32::INFINITY; n],
            stats: RenderStats::default(),
            cut: false,
            unconfirmed_rays: Vec::new(),
            resolved: 0,
        }
    }
}

/// What every tile of a render shares.
pub(crate) struct TileCtx<'a, S> {
    /// The whole shape (shading and shadows reach outside a tile's rays).
    pub(crate) root: &'a S,
    pub(crate) opts: &'a RenderOptions,
    pub(crate) cam: &'a Camera,
    pub(crate) culler: &'a Culler,
    pub(crate) params: &'a RayParams,
    pub(crate) light: &'a Light,
    /// The domain's diagonal.
    pub(crate) scale: f64,
    /// How far the shading samples of a hit reach from it, at most (with a margin).
    pub(crate) shade_pad: f64,
}
