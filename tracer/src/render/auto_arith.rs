//! The default arithmetic (`tracer render --arith auto`, the CLI's default): RevAA,
//! with every hit that shading cannot confirm searched again in Hull.
//!
//! Measured on every built-in model and fidget's four (`docs/default-arith.md`,
//! `scripts/default-arith.sh`): RevAA is the fastest or within a few percent of it on
//! most models, but on some (fidget's bear) its `min`/`max` of overlapping affine forms
//! stay loose enough to report a wall of unconfirmed hits where the surface is not
//! (4.5% of the bear's hits at 512x512). Hull's ranges are the intersection of an
//! affine form's and an interval's, so never looser than RevAA's or IA's, and draw no
//! such wall; they cost about twice RevAA's per evaluation.
//!
//! So a tile is culled, searched and shaded in RevAA, and the rays of its unconfirmed
//! hits (no sign change among the normal's samples) are searched again, whole, in
//! Hull, and shaded again: a wall's pixels get Hull's answer (a later root, or none),
//! genuine unconfirmed hits (tangent touches, walls seen edge-on) get the same one
//! again. The extra work is one Hull search per unconfirmed hit, about 1% of the rays
//! on models without walls, instead of a probe render before the render: the choice
//! costs nothing where there is nothing to choose, is made pixel by pixel where there
//! is, and rests on counts, never on timings, so the same render always gives the same
//! image.
//!
//! Where RevAA's ranges draw a wall, though, RevAA costs more than Hull itself (its
//! loose ranges send the search down further: the bear takes about 1.5 times Hull's
//! time in RevAA). So a sample of the tiles ([`SAMPLE_TILES`], at most a quarter of
//! the image, spread over it) is rendered first as above; where Hull resolved (confirmed or removed) more of their
//! unconfirmed hits than [`WALL_SHARE`] of their hits (at least [`WALL_MIN`]), RevAA
//! draws walls here and the other tiles are rendered in Hull throughout, else like the
//! sample. The sample is part of the image, so the choice costs no extra render; it
//! only decides the cost, never the image's soundness or its walls (every tile
//! searches its unconfirmed hits again in Hull).
//!
//! Sound: each search is Algorithm 1 in a sound arithmetic from the depths culling
//! left (culling, in RevAA, drops only what its ranges exclude), so neither misses a
//! root; a pixel keeps whichever answer the second search gives.

use super::shade_hits::shade_hits;
use super::tile_shapes::TileShapes;
use super::types::{TileCtx, TileOut};
use super::{
    end_tile, render_tile, render_tiles, search_again, tile_shape, trace_tile, RenderOptions,
    RenderResult, Tiles,
};
use model_ir::arith::arith_hull::HullArith as Hull;
use model_ir::arith::arith_revaa::RevAaArith as RevAa;
use model_ir::shape::Shape;

/// Tiles rendered first (at most, and at most a quarter of the image's), whose counts
/// choose how the others are.
pub const SAMPLE_TILES: usize = 8;
/// How many of the sample's unconfirmed hits Hull must resolve, as a share of its hits,
/// for the other tiles to be rendered in Hull throughout.
pub const WALL_SHARE: f64 = 0.01;
/// The least number of resolved hits that counts as a wall.
pub const WALL_MIN: u64 = 2;

/// Renders `shape` in the default arithmetic (see the module doc). Errors as
/// [`super::render`] does.
pub fn render_auto<S: Shape>(shape: &S, opts: &RenderOptions) -> Result<RenderResult, String> {
    render_tiles(shape, opts, &schedule::<S>)
}

/// The sample tiles with [`auto_tile`], then the others with it or, where the sample
/// saw walls, in Hull; the outputs in tile order.
fn schedule<S: Shape>(tiles: &Tiles<'_, S>) -> Vec<Option<TileOut>> {
    let n = tiles.len();
    // At most a quarter of the image: where RevAA draws walls the sample costs more
    // than Hull would have.
    let stride = n / (n / 4).clamp(1, SAMPLE_TILES);
    let (sample, rest): (Vec<usize>, Vec<usize>) =
        (0..n).partition(|k| k % stride == stride / 2 || stride == 1);
    let first = tiles.run(&sample, auto_tile::<S>);
    let (hits, resolved) = first
        .iter()
        .flatten()
        .fold((0, 0), |(h, r), o| (h + o.stats.hits, r + o.resolved));
    let walls = resolved > ((hits as f64 * WALL_SHARE).ceil() as u64).max(WALL_MIN);
    let tile_fn = if walls {
        render_tile::<Hull, S>
    } else {
        auto_tile::<S>
    };
    let mut second = tiles.run(&rest, tile_fn);
    if walls {
        for o in second.iter_mut().flatten() {
            o.stats.tiles_hull += 1;
        }
    }
    let mut outs: Vec<Option<TileOut>> = (0..n).map(|_| None).collect();
    for (k, o) in sample
        .into_iter()
        .zip(first)
        .chain(rest.into_iter().zip(second))
    {
        outs[k] = o;
    }
    outs
}

/// One tile in RevAA, its unconfirmed hits searched and shaded again in Hull.
fn auto_tile<S: Shape>(
    ctx: &TileCtx<'_, S>,
    mine: Option<&TileShapes<S>>,
    rect: (u32, u32, u32, u32),
    stop: &(dyn Fn() -> bool + Sync),
) -> TileOut {
    let (rays, cs, mut out) = trace_tile::<RevAa, S>(ctx, mine, rect, stop);
    let shape = tile_shape(ctx, mine);
    let again = std::mem::take(&mut out.unconfirmed_rays);
    if !again.is_empty() && !out.cut {
        for &ray in &again {
            let k = rays.pixel_of[ray];
            out.depth[k] = f32::INFINITY;
            out.rgb[k * 3..k * 3 + 3].copy_from_slice(&ctx.opts.background);
        }
        let n = again.len() as u64;
        out.stats.hits -= n;
        out.stats.unconfirmed -= n;
        out.stats.researched += n;
        let mut hull = search_again::<Hull, S>(ctx, shape, &rays, rect, &again, stop, &mut out);
        let before = out.stats.unconfirmed;
        shade_hits::<Hull, S>(ctx, shape, mine, &rays, &mut hull, &mut out);
        out.resolved = n - (out.stats.unconfirmed - before);
        out.unconfirmed_rays.clear();
    }
    end_tile(&rays, cs, &mut out);
    out
}
